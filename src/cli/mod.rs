//! Command-line parsing and dispatch. Every failure a user can cause comes
//! back as an error with context; `main` prints it and exits 2.

mod args;
mod assemble;
#[cfg(feature = "gpu")]
mod bench;
mod choice;
#[cfg(feature = "gpu")]
mod compare;
pub mod console;
mod convert;
mod diff;
#[cfg(feature = "gpu")]
mod drivers;
#[cfg(feature = "gpu")]
mod explain;
mod fuzz;
#[cfg(feature = "gpu")]
mod info;
mod progress;
mod render;
mod render_aov;
#[cfg(feature = "gpu")]
mod render_gpu;
#[cfg(feature = "gpu")]
mod report;
#[cfg(feature = "gpu")]
mod serve;
#[cfg(feature = "gpu")]
mod shader;
mod shell;
pub mod signals;
#[cfg(feature = "gpu")]
mod stability;
mod tile;
pub mod version;
#[cfg(feature = "gpu")]
mod watch;
mod whole;
#[cfg(not(feature = "gpu"))]
mod without_gpu;
#[cfg(feature = "gpu")]
use drivers::probe as driver_probe;
#[cfg(not(feature = "gpu"))]
use without_gpu::{
    bench, compare, driver_probe, drivers, explain, info, render_gpu, report, serve, shader,
    stability, watch,
};

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use args::{inputs, Backend, DeviceArgs, Precision, SceneArgs};
#[cfg(feature = "gpu")]
pub use args::{parse_define, scene_files, scene_line, scene_name, OverrideArgs, MAX_RUNS};

#[derive(Parser)]
#[command(
    name = "glint",
    version = version::SHORT,
    about = "Headless Whitted-style ray tracer: a Vulkan compute shader checked against a CPU reference"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to PNG, PFM or EXR.
    Render(render::RenderArgs),
    /// Render on the GPU (f32) and with the CPU f64 reference; print the error and the times; exit 1 over tolerance.
    Compare(compare::CompareArgs),
    /// One pixel's ray tree on the GPU, the CPU's f32 and the f64 reference, side by side, down to the first number that differs and its cause; exit 1 where a tree leaves the reference.
    Explain(explain::ExplainArgs),
    /// The error figures of image A against reference image B.
    Diff(diff::DiffArgs),
    /// List the Vulkan devices and what they support.
    Info(info::InfoArgs),
    /// Robust and naive GPU forms and CPU f32 against CPU f64 on the extreme scenes.
    Stability(stability::StabilityArgs),
    /// Error against run time for every variant of each scene: tables, a plot and a page.
    Report(report::ReportArgs),
    /// Check a shader file, or dump a scene's shader variant.
    Shader(shader::ShaderArgs),
    /// Re-render whenever the scene or a shader file changes.
    Watch(watch::WatchArgs),
    /// A live page of the GPU image, the CPU f64 reference, the error and each pixel's ray tree, following the files as they change.
    Serve(serve::ServeArgs),
    /// Write an NFF scene (the SPD's format) as a TOML scene that renders the same image.
    Convert(convert::ConvertArgs),
    /// Put tiles of one render (render --tile or --region) together, checking that they are one whole render.
    Assemble(assemble::AssembleArgs),
    /// Time each scene on both renderers, with its rays, tests and node visits by ray type, against the device's ceiling.
    Bench(bench::BenchArgs),
    /// Run the scenes on every Vulkan driver the machine has, each held to the CPU f64 reference; a table, a page and a reproducer for each failure; exit 1 where a driver fails.
    Drivers(drivers::DriversArgs),
    /// One driver's run of one scene, for `glint drivers` (internal).
    #[command(hide = true)]
    DriverProbe(driver_probe::ProbeArgs),
    /// Generated scenes held to the CPU f64 reference and to their own variants (random, the CI set, or every small scene); each failure shrunk to a scene file; exit 1 where one fails.
    Fuzz(fuzz::FuzzArgs),
    /// Print a shell's completion script: `glint completions bash > /etc/bash_completion.d/glint`.
    Completions(shell::CompletionsArgs),
    /// Print the man page (roff): `glint man > glint.1; man ./glint.1`.
    Man,
}

pub fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Render(a) => render::run(&a),
        Command::Compare(a) => compare::run(&a),
        Command::Explain(a) => explain::run(&a),
        Command::Diff(a) => diff::run(&a),
        Command::Info(a) => info::run(&a),
        Command::Stability(a) => stability::run(&a),
        Command::Report(a) => report::run(&a),
        Command::Shader(a) => shader::run(&a),
        Command::Watch(a) => watch::run(&a),
        Command::Serve(a) => serve::run(&a),
        Command::Convert(a) => convert::run(&a),
        Command::Bench(a) => bench::run(&a),
        Command::Assemble(a) => assemble::run(&a),
        Command::Drivers(a) => drivers::run(&a),
        Command::DriverProbe(a) => driver_probe::run(&a),
        Command::Fuzz(a) => fuzz::run(&a),
        Command::Completions(a) => shell::completions(&a),
        Command::Man => shell::man(),
    }
}

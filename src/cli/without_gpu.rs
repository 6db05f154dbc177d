//! What a build without the GPU renderer (`--no-default-features`) answers
//! for the commands and renders that need it: one line, exit status 2.
//! The commands stay listed, so `--help` reads the same in both builds.

use std::ffi::OsString;
use std::path::Path;

use clap::Args;

use glint::raster::region::Region;
use glint::raster::Image;
use glint::scene::Scene;
use glint::tiles::Sidecar;

use super::{DeviceArgs, Precision};

/// A command's arguments, unread: it cannot run in this build.
#[derive(Args)]
pub struct Unbuilt {
    #[arg(num_args = 0.., trailing_var_arg = true, allow_hyphen_values = true, hide = true)]
    rest: Vec<OsString>,
}

/// The error of `what`, which needs the GPU renderer.
pub fn refuse(what: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{what} needs the GPU renderer, and this glint was built without it \
         (--no-default-features); build it with the default features, or render with --backend cpu"
    )
}

macro_rules! unbuilt {
    ($($command:ident :: $args:ident),* $(,)?) => {$(
        pub mod $command {
            pub type $args = super::Unbuilt;

            pub fn run(_: &$args) -> anyhow::Result<std::process::ExitCode> {
                Err(super::refuse(concat!("glint ", stringify!($command))))
            }
        }
    )*};
}

unbuilt!(
    bench::BenchArgs,
    compare::CompareArgs,
    drivers::DriversArgs,
    driver_probe::ProbeArgs,
    explain::ExplainArgs,
    info::InfoArgs,
    report::ReportArgs,
    shader::ShaderArgs,
    serve::ServeArgs,
    stability::StabilityArgs,
    watch::WatchArgs,
);

/// `render`'s GPU renders.
pub mod render_gpu {
    use super::*;

    pub fn whole(
        _: &Scene,
        _: &DeviceArgs,
        _: Precision,
        _: crate::cli::whole::Want,
    ) -> anyhow::Result<crate::cli::whole::Whole> {
        Err(refuse("render --backend gpu (the default)"))
    }

    pub fn tile(
        _: &Path,
        _: &Scene,
        _: &DeviceArgs,
        _: Precision,
        _: Region,
        _: Option<String>,
    ) -> anyhow::Result<(Image, String, Sidecar)> {
        Err(refuse("render --backend gpu (the default)"))
    }
}

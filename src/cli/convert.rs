//! `glint convert`: an NFF scene written out as glint's TOML, which renders
//! the same image (docs/scene-format.md, NFF).

use crate::cli::console::errln;

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;

use glint::output::{self, Outputs};
use glint::scene::{nff, Overrides};

#[derive(Args)]
pub struct ConvertArgs {
    /// The NFF file to read.
    scene: PathBuf,
    /// The TOML scene to write.
    #[arg(short, long)]
    output: PathBuf,
    /// Replace a read-only output file too.
    #[arg(long)]
    force: bool,
}

pub fn run(a: &ConvertArgs) -> anyhow::Result<ExitCode> {
    let mut outputs = Outputs::new([&a.scene], a.force);
    outputs.check(&a.output)?;
    let text = glint::input::read_text(&a.scene, glint::input::ReadAs::Scene).map_err(|cause| {
        glint::scene::SceneError::Read {
            path: a.scene.clone(),
            cause,
        }
    })?;
    let read = nff::read(&text, &a.scene)?;
    let toml = read
        .scene
        .to_toml()
        .context("cannot write the scene as TOML")?;
    // The whole scene is checked before anything is written: what is
    // written is a valid scene.
    read.check(&a.scene, &Overrides::default())?;
    let source = a.scene.file_name().unwrap_or_default().to_string_lossy();
    outputs.stage(&a.output, |out: &mut dyn Write| {
        write!(
            out,
            "# {source}, converted from NFF by glint convert (docs/scene-format.md, NFF).\n\n{toml}"
        )
        .map_err(output::io_err(&a.output))
    })?;
    outputs.commit()?;
    errln!(
        "converted {} -> {}",
        glint::printable::path(&a.scene),
        glint::printable::path(&a.output)
    );
    Ok(ExitCode::SUCCESS)
}

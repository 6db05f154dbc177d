//! `glint convert`: an NFF scene written out as glint's TOML, which renders
//! the same image (docs/scene-format.md, NFF).

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;

use glint::raster::io;
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
    io::refuse_input(&a.output, &[a.scene.as_path()])?;
    io::check_target(&a.output, a.force)?;
    let text =
        std::fs::read_to_string(&a.scene).map_err(|cause| glint::scene::SceneError::Read {
            path: a.scene.clone(),
            cause,
        })?;
    let read = nff::read(&text, &a.scene)?;
    let toml = toml::to_string(&read.scene).context("cannot write the scene as TOML")?;
    // The whole scene is checked before anything is written: what is
    // written is a valid scene.
    read.check(&a.scene, &Overrides::default())?;
    let source = a.scene.file_name().unwrap_or_default().to_string_lossy();
    io::write_atomic(&a.output, a.force, |out, path| {
        write!(
            out,
            "# {source}, converted from NFF by glint convert (docs/scene-format.md, NFF).\n\n{toml}"
        )
        .map_err(io::io_err(path))
    })?;
    eprintln!(
        "converted {} -> {}",
        glint::printable::path(&a.scene),
        glint::printable::path(&a.output)
    );
    Ok(ExitCode::SUCCESS)
}

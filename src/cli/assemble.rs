use crate::cli::console::errln;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;

use glint::output::Outputs;
use glint::raster::io;
use glint::tiles::{self, Tile};

#[derive(Args)]
pub struct AssembleArgs {
    /// Tiles (EXR or PFM, each with its sidecar TILE.json), or directories of them.
    #[arg(required = true)]
    tiles: Vec<PathBuf>,
    /// The whole image: .png, .pfm or .exr.
    #[arg(short, long)]
    output: PathBuf,
    /// Replace a read-only output file too.
    #[arg(long)]
    force: bool,
}

/// The tile files named, a directory standing for every EXR and PFM in it.
fn tile_files(args: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for a in args {
        if a.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(a)
                .with_context(|| format!("cannot list {}", a.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| matches!(io::Format::of(p), Ok(io::Format::Exr | io::Format::Pfm)))
                .collect();
            found.sort();
            files.extend(found);
        } else {
            files.push(a.clone());
        }
    }
    Ok(files)
}

pub fn run(a: &AssembleArgs) -> anyhow::Result<ExitCode> {
    io::Format::of_output(&a.output)?;
    let files = tile_files(&a.tiles)?;
    let inputs = files
        .iter()
        .flat_map(|f| [f.clone(), tiles::sidecar_path(f)]);
    let mut outputs = Outputs::new(inputs, a.force);
    outputs.check(&a.output)?;
    let bar = super::progress::bar(files.len() as u64, "reading tiles");
    let tiles: Vec<Tile> = files
        .iter()
        .map(|f| {
            let tile = tiles::read_tile(f);
            bar.inc(1);
            tile
        })
        .collect::<Result<_, _>>()?;
    bar.finish_and_clear();
    let (image, whole) = tiles::assemble(&tiles)?;
    io::stage(&mut outputs, &a.output, &image, whole.srgb)
        .with_context(|| "cannot write the image")?;
    outputs.commit()?;
    errln!(
        "assembled {} tiles of {} ({}x{}, {} {}) -> {}",
        tiles.len(),
        glint::printable::text(&whole.scene),
        whole.width,
        whole.height,
        whole.render.backend,
        whole.render.precision,
        a.output.display()
    );
    Ok(ExitCode::SUCCESS)
}

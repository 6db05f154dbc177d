//! Tiles of a render and their assembly (docs/scale-out.md): a tile is an
//! EXR or PFM of one region of the image with a sidecar `<tile>.json` that
//! says which render it belongs to; `assemble` checks that a set of tiles
//! is one whole render and puts it together.

mod assemble;

use std::hash::Hasher;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use assemble::{assemble, read_tile, Tile, TileError};

use crate::fnv::Fnv;
use crate::raster::region::Region;
use crate::raster::Image;
use crate::scene::Scene;

/// What a tile's sidecar says of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sidecar {
    /// The glint version that rendered it.
    pub glint: String,
    /// The scene file, as named on the command line.
    pub scene: String,
    /// [`scene_hash`] of the scene as loaded, overrides applied.
    pub scene_hash: String,
    /// The whole image's width.
    pub width: u32,
    /// The whole image's height.
    pub height: u32,
    /// Whether a PNG of it is sRGB-encoded.
    pub srgb: bool,
    /// What rendered it: every setting that can change a pixel's bits.
    pub render: RenderKey,
    /// The pixels this tile holds.
    pub region: Region,
    /// [`pixels_hash`] of the tile's image: what binds this sidecar to
    /// its pixels, so that a tile renamed over another's name, or
    /// re-rendered while it was read, is caught.
    pub pixels: String,
    /// `I/N` where it was rendered as tile I of N.
    pub tile: Option<String>,
}

/// The settings of a render that decide its pixels' bits.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderKey {
    /// `gpu` or `cpu`.
    pub backend: String,
    /// `f32` or `f64`.
    pub precision: String,
    /// The GPU's intersection forms, its generic shader, and the user's
    /// shader files and defines (a hash of their text); the device's name.
    pub gpu: Option<GpuKey>,
}

/// The GPU settings of a render that decide its pixels' bits.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GpuKey {
    /// `robust` or `naive`.
    pub intersect: String,
    /// Whether the generic shader rendered it.
    pub generic: bool,
    /// A hash of the user's shader files and defines; empty where there are none.
    pub shader: String,
    /// The device's name.
    pub device: String,
}

/// A hash of everything the loaded scene holds (its Debug form, which
/// writes every number in full): two tiles of one scene file with other
/// overrides, or of an edited file or mesh, differ.
pub fn scene_hash(scene: &Scene) -> String {
    let mut h = Fnv::default();
    h.write(format!("{scene:?}").as_bytes());
    format!("{:016x}", h.finish())
}

/// A hash of an image's pixels (every channel's f32 bits, row by row)
/// and size.
pub fn pixels_hash(image: &Image) -> String {
    let mut h = Fnv::default();
    h.write_u32(image.width);
    h.write_u32(image.height);
    for p in &image.pixels {
        for c in p {
            h.write_u32(c.to_bits());
        }
    }
    format!("{:016x}", h.finish())
}

/// Where a tile's sidecar is: `<tile>.json`.
pub fn sidecar_path(tile: &Path) -> PathBuf {
    let mut name = tile.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

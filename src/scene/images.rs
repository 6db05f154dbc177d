//! Image textures' files (docs/scene-format.md, Textures): each read once,
//! however many textures name it, into the scene's one list of texels that
//! both renderers read.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DVec3;

use super::texture::Texels;
use crate::raster::io;

/// The most texels of all a scene's images: 96 MiB as the renderers hold
/// them (three f32 each), inside lavapipe's 128 MiB storage buffer.
pub const MAX_TEXELS: u64 = 1 << 23;
/// The widest or tallest image.
pub const MAX_SIDE: u32 = 8192;

/// The images read so far and their texels, rows top to bottom.
#[derive(Debug, Default)]
pub struct Images {
    /// Every image's texels, in the order read.
    pub texels: Vec<[f32; 3]>,
    read: HashMap<PathBuf, Texels>,
    /// The files, in the order read: inputs of the run.
    pub files: Vec<PathBuf>,
}

impl Images {
    /// The texels of the image at `path`, read and appended where it was
    /// not yet. A PNG's 8- or 16-bit values are sRGB-encoded and decoded to
    /// linear (`raster::srgb_decode_level`, in `io::read`); an EXR's or PFM's are linear as
    /// stored. The message of an error names the file.
    pub fn texels(&mut self, path: &Path) -> Result<Texels, String> {
        let key = path.canonicalize().unwrap_or_else(|_| path.to_owned());
        if let Some(t) = self.read.get(&key) {
            return Ok(*t);
        }
        let shown = crate::printable::path(path);
        let unreadable = |e: io::ImageIoError| format!("cannot read the image: {e}");
        // The size first, from the header: an oversized image is refused
        // before it is decoded.
        let (w, h) = io::dimensions(path).map_err(unreadable)?;
        let total = self.texels.len() as u64 + u64::from(w) * u64::from(h);
        if w > MAX_SIDE || h > MAX_SIDE || total > MAX_TEXELS {
            return Err(format!(
                "{shown} is {w}x{h}: an image texture may be at most {MAX_SIDE} a side, and a \
                 scene's images {MAX_TEXELS} texels in all ({} before this one)",
                self.texels.len()
            ));
        }
        // Linear: a PNG's levels decoded from sRGB by `io::read`.
        let image = io::read(path).map_err(unreadable)?;
        let first = self.texels.len() as u32;
        let mut peak = DVec3::ZERO;
        self.texels.reserve_exact(image.pixels.len());
        for (i, p) in image.pixels.iter().enumerate() {
            if let Some(c) = p.iter().find(|c| !c.is_finite() || **c < 0.0) {
                let (x, y) = (i as u32 % image.width, i as u32 / image.width);
                self.texels.truncate(first as usize);
                return Err(format!(
                    "{shown}: texel ({x}, {y}) has the value {c}: texels must be finite and >= 0"
                ));
            }
            peak = peak.max(DVec3::from_array(p.map(f64::from)));
            self.texels.push(*p);
        }
        let t = Texels {
            first,
            width: image.width,
            height: image.height,
            peak,
        };
        self.read.insert(key, t);
        self.files.push(path.to_owned());
        Ok(t)
    }
}

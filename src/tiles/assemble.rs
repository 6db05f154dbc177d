//! `glint assemble`: a set of tiles checked to be one whole render, and put
//! together.

use std::path::{Path, PathBuf};

use super::{sidecar_path, Sidecar};
use crate::raster::io::{self, Format};
use crate::raster::region::{Region, RegionError};
use crate::raster::Image;

/// A tile as read from its files.
#[derive(Debug, Clone)]
pub struct Tile {
    /// The tile's image file.
    pub path: PathBuf,
    /// What its sidecar says of the render.
    pub sidecar: Sidecar,
    /// Its pixels.
    pub image: Image,
}

/// Why a set of tiles is not one whole render.
#[derive(Debug, thiserror::Error)]
pub enum TileError {
    /// A tile that is not EXR or PFM.
    #[error("{0}: a tile is an EXR or PFM file (a PNG rounds its values)")]
    NotFloat(PathBuf),
    /// A tile without a readable sidecar.
    #[error("{tile}: no sidecar {sidecar}: {err}")]
    NoSidecar {
        /// The tile.
        tile: PathBuf,
        /// Its sidecar's path.
        sidecar: PathBuf,
        /// Why it could not be read.
        err: std::io::Error,
    },
    /// A sidecar that is not a glint one: the file and why.
    #[error("{0}: not a glint tile sidecar: {1}")]
    BadSidecar(PathBuf, String),
    /// A tile image that cannot be read: the file and why.
    #[error("{0}: {1}")]
    Image(PathBuf, String),
    /// A tile whose image is not the size of its region.
    #[error("{tile}: holds {got_w}x{got_h} pixels where its sidecar's region is {want_w}x{want_h}: a partial tile")]
    Partial {
        /// The tile.
        tile: PathBuf,
        /// Its image's width.
        got_w: u32,
        /// Its image's height.
        got_h: u32,
        /// Its region's width.
        want_w: u32,
        /// Its region's height.
        want_h: u32,
    },
    /// A tile with NaN or infinite values, which `render` never writes.
    #[error(
        "{tile}: holds {count} non-finite values, the first at pixel ({x}, {y}) of the tile; \
         a render writes none, so the tile is not glint's as rendered"
    )]
    NonFinite {
        /// The tile.
        tile: PathBuf,
        /// How many values are NaN or infinite.
        count: usize,
        /// The first such pixel's column in the tile.
        x: u32,
        /// Its row.
        y: u32,
    },
    /// A tile whose region is not inside the image.
    #[error("{0}: {1}")]
    Outside(PathBuf, RegionError),
    /// A tile of another render (scene, settings, device or shader).
    #[error("{tile} is not of the render of {first}: its {field} is {got}, not {want}")]
    Mismatch {
        /// The tile.
        tile: PathBuf,
        /// The first tile, which the others are held to.
        first: PathBuf,
        /// The sidecar's field that differs.
        field: String,
        /// This tile's value.
        got: String,
        /// The first tile's value.
        want: String,
    },
    /// Two tiles of the same region.
    #[error("{a} and {b} are the same tile (region {x},{y},{w},{h})")]
    Duplicate {
        /// One tile.
        a: PathBuf,
        /// The other.
        b: PathBuf,
        /// The region's left column.
        x: u32,
        /// The region's top row.
        y: u32,
        /// The region's width.
        w: u32,
        /// The region's height.
        h: u32,
    },
    /// Two tiles that overlap.
    #[error("{a} and {b} overlap in row {y}")]
    Overlap {
        /// One tile.
        a: PathBuf,
        /// The other.
        b: PathBuf,
        /// A row both cover.
        y: u32,
    },
    /// A pixel no tile holds.
    #[error("no tile holds pixel ({x}, {y}) of the {w}x{h} image: a tile is missing")]
    Gap {
        /// The pixel's column.
        x: u32,
        /// The pixel's row.
        y: u32,
        /// The image's width.
        w: u32,
        /// The image's height.
        h: u32,
    },
    /// Tiles of an `--tile I/N` render that are not there.
    #[error("tile {missing} of the {w}x{h} image is missing (rerun it with --tile I/{n})")]
    Missing {
        /// The missing tiles' indices.
        missing: String,
        /// The count of tiles of the render.
        n: u32,
        /// The image's width.
        w: u32,
        /// The image's height.
        h: u32,
    },
    /// A tile whose pixels are not the ones its sidecar was written with:
    /// another tile's image under its name, or one rendered again since.
    #[error(
        "{tile}: its pixels are not the ones {sidecar} was written with (a tile renamed over \
         another's, or rendered again while being read); render it again"
    )]
    NotItsPixels {
        /// The tile's image.
        tile: PathBuf,
        /// Its sidecar.
        sidecar: PathBuf,
    },
    /// No tiles at all.
    #[error("no tiles given")]
    NoTiles,
}

/// Reads a tile and its sidecar, and checks that its image is its region.
pub fn read_tile(path: &Path) -> Result<Tile, TileError> {
    match Format::of(path) {
        Ok(Format::Exr | Format::Pfm) => {}
        _ => return Err(TileError::NotFloat(path.to_owned())),
    }
    let sidecar = sidecar_path(path);
    let text = crate::input::read_text(&sidecar, crate::input::ReadAs::Sidecar).map_err(|err| {
        TileError::NoSidecar {
            tile: path.to_owned(),
            sidecar: sidecar.clone(),
            err,
        }
    })?;
    let sidecar_path = sidecar;
    let sidecar: Sidecar = serde_json::from_str(&text)
        .map_err(|e| TileError::BadSidecar(sidecar_path.clone(), e.to_string()))?;
    let max = crate::scene::MAX_SIZE;
    if sidecar.width > max || sidecar.height > max {
        return Err(TileError::BadSidecar(
            sidecar_path,
            format!(
                "it claims a {}x{} image, larger than any render ({max} a side)",
                sidecar.width, sidecar.height
            ),
        ));
    }
    // A PNG tile holds its levels as the sidecar says it wrote them.
    let image = io::read_as(path, sidecar.srgb)
        .map_err(|e| TileError::Image(path.to_owned(), e.to_string()))?;
    let r = sidecar.region;
    if (image.width, image.height) != (r.width, r.height) {
        return Err(TileError::Partial {
            tile: path.to_owned(),
            got_w: image.width,
            got_h: image.height,
            want_w: r.width,
            want_h: r.height,
        });
    }
    r.within(sidecar.width, sidecar.height)
        .map_err(|e| TileError::Outside(path.to_owned(), e))?;
    if let Some((count, x, y)) = image.nonfinite() {
        return Err(TileError::NonFinite {
            tile: path.to_owned(),
            count,
            x,
            y,
        });
    }
    if super::pixels_hash(&image) != sidecar.pixels {
        return Err(TileError::NotItsPixels {
            tile: path.to_owned(),
            sidecar: sidecar_path,
        });
    }
    Ok(Tile {
        path: path.to_owned(),
        sidecar,
        image,
    })
}

/// The whole image from `tiles`, and the sidecar of the whole render
/// (region: all of it), once they are checked to be one render's tiles:
/// the same scene and settings, every pixel held by exactly one tile.
pub fn assemble(tiles: &[Tile]) -> Result<(Image, Sidecar), TileError> {
    let first = tiles.first().ok_or(TileError::NoTiles)?;
    let key = |s: &Sidecar| {
        let mut v = serde_json::to_value(s).expect("a sidecar serializes");
        let map = v.as_object_mut().expect("an object");
        map.remove("region");
        map.remove("tile");
        map.remove("pixels");
        v
    };
    let want = key(&first.sidecar);
    for t in &tiles[1..] {
        let got = key(&t.sidecar);
        if got != want {
            let (g, w) = (got.as_object().unwrap(), want.as_object().unwrap());
            let field = w
                .keys()
                .find(|k| g.get(*k) != w.get(*k))
                .cloned()
                .unwrap_or_default();
            return Err(TileError::Mismatch {
                tile: t.path.clone(),
                first: first.path.clone(),
                // A sidecar's values are anyone's text: shown as every name is.
                got: crate::printable::text(
                    &g.get(&field).map(|v| v.to_string()).unwrap_or_default(),
                ),
                want: crate::printable::text(
                    &w.get(&field).map(|v| v.to_string()).unwrap_or_default(),
                ),
                field: crate::printable::text(&field),
            });
        }
    }
    let (width, height) = (first.sidecar.width, first.sidecar.height);
    check_cover(tiles, width, height).map_err(|e| {
        let Some((n, present)) = split_of(tiles) else {
            return e;
        };
        let missing = missing_tiles(n, present);
        match e {
            // Every index present and still a gap: the split does not
            // cover the image the sidecars claim; the gap says where.
            TileError::Gap { w, h, .. } if !missing.is_empty() => {
                TileError::Missing { missing, n, w, h }
            }
            e => e,
        }
    })?;
    let mut pixels = vec![[0.0f32; 3]; width as usize * height as usize];
    for t in tiles {
        let r = t.sidecar.region;
        for (row, src) in t.image.pixels.chunks_exact(r.width as usize).enumerate() {
            let start = (r.y as usize + row) * width as usize + r.x as usize;
            pixels[start..start + r.width as usize].copy_from_slice(src);
        }
    }
    let image = Image::new(width, height, pixels);
    let whole = Sidecar {
        region: Region::whole(width, height),
        tile: None,
        pixels: super::pixels_hash(&image),
        ..first.sidecar.clone()
    };
    Ok((image, whole))
}

/// The tiles of `n` not `present`, as "I/N" for the first few and a count
/// of the rest: a sidecar may claim any N (one of 100,000,000 listed them
/// all, 3.8 GB). Empty where none is missing.
fn missing_tiles(n: u32, mut present: Vec<u32>) -> String {
    const NAMED: usize = 5;
    present.sort_unstable();
    present.dedup();
    let count = n as usize - present.iter().filter(|&&i| i < n).count();
    let mut names: Vec<String> = (0..n)
        .filter(|i| present.binary_search(i).is_err())
        .take(NAMED)
        .map(|i| format!("{i}/{n}"))
        .collect();
    if count > names.len() {
        names.push(format!("{} more", count - names.len()));
    }
    names.join(", ")
}

/// Where every tile is tile I of one N: N and the indices present.
fn split_of(tiles: &[Tile]) -> Option<(u32, Vec<u32>)> {
    let parse = |t: &Tile| -> Option<(u32, u32)> {
        let (i, n) = t.sidecar.tile.as_deref()?.split_once('/')?;
        Some((i.parse().ok()?, n.parse().ok()?))
    };
    let split: Option<Vec<(u32, u32)>> = tiles.iter().map(parse).collect();
    let split = split?;
    let n = split.first()?.1;
    split
        .iter()
        .all(|(_, m)| *m == n)
        .then(|| (n, split.iter().map(|(i, _)| *i).collect()))
}

/// Every pixel of the `width`×`height` image in exactly one tile: no
/// duplicate, no overlap, no gap.
fn check_cover(tiles: &[Tile], width: u32, height: u32) -> Result<(), TileError> {
    let mut by_region: Vec<(&Region, &Path)> = tiles
        .iter()
        .map(|t| (&t.sidecar.region, t.path.as_path()))
        .collect();
    by_region.sort_by_key(|(r, _)| (r.y, r.x, r.height, r.width));
    for pair in by_region.windows(2) {
        if pair[0].0 == pair[1].0 {
            let r = pair[0].0;
            return Err(TileError::Duplicate {
                a: pair[0].1.to_owned(),
                b: pair[1].1.to_owned(),
                x: r.x,
                y: r.y,
                w: r.width,
                h: r.height,
            });
        }
    }
    // Row by row, the tiles that cross it, left to right, must meet end to end.
    for y in 0..height {
        let mut row: Vec<(&Region, &Path)> = by_region
            .iter()
            .copied()
            .filter(|(r, _)| r.y <= y && y < r.y + r.height)
            .collect();
        row.sort_by_key(|(r, _)| r.x);
        let mut x = 0;
        let mut last: Option<&Path> = None;
        for (r, path) in row {
            if r.x < x {
                return Err(TileError::Overlap {
                    a: last.expect("a tile before").to_owned(),
                    b: path.to_owned(),
                    y,
                });
            }
            if r.x > x {
                break;
            }
            x = r.x + r.width;
            last = Some(path);
        }
        if x < width {
            return Err(TileError::Gap {
                x,
                y,
                w: width,
                h: height,
            });
        }
    }
    Ok(())
}

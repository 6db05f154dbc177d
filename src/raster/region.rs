//! A rectangle of an image's pixels: what a tile of a render covers
//! (docs/scale-out.md).

use serde::{Deserialize, Serialize};

/// A rectangle of pixels, in the whole image's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Region {
    /// The left column.
    pub x: u32,
    /// The top row.
    pub y: u32,
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

/// Rows of a band are whole workgroups of the shader (its 8×8), so that no
/// workgroup straddles two tiles.
pub const BAND_ROWS: u32 = crate::base::WORKGROUP;

/// A region or tile that does not fit its image.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RegionError {
    /// The region is empty or not inside the image.
    #[error("region {x},{y},{w},{h} is not inside the {iw}x{ih} image, or is empty")]
    Outside {
        /// The region's left column.
        x: u32,
        /// The region's top row.
        y: u32,
        /// The region's width.
        w: u32,
        /// The region's height.
        h: u32,
        /// The image's width.
        iw: u32,
        /// The image's height.
        ih: u32,
    },
    /// `--tile I/N` with I not below N, or N zero.
    #[error("tile {i}/{n}: the index must be below the count, and the count at least 1")]
    Index {
        /// The tile's index.
        i: u32,
        /// The count of tiles.
        n: u32,
    },
    /// More tiles than the image has bands.
    #[error("{n} tiles: a {height}-row image has only {bands} bands of {BAND_ROWS} rows")]
    TooMany {
        /// The count of tiles asked for.
        n: u32,
        /// The image's rows.
        height: u32,
        /// The bands the image has.
        bands: u32,
    },
}

impl Region {
    /// The whole image.
    pub fn whole(width: u32, height: u32) -> Self {
        Self {
            x: 0,
            y: 0,
            width,
            height,
        }
    }

    /// `self`, checked to lie in a `width`×`height` image and to hold a pixel.
    pub fn within(self, width: u32, height: u32) -> Result<Self, RegionError> {
        let inside = self.width > 0
            && self.height > 0
            && u64::from(self.x) + u64::from(self.width) <= u64::from(width)
            && u64::from(self.y) + u64::from(self.height) <= u64::from(height);
        if inside {
            Ok(self)
        } else {
            Err(RegionError::Outside {
                x: self.x,
                y: self.y,
                w: self.width,
                h: self.height,
                iw: width,
                ih: height,
            })
        }
    }

    /// Tile `i` of `n` of a `width`×`height` image: the image's bands of
    /// [`BAND_ROWS`] rows (the last may be shorter), shared out in order, as
    /// evenly as whole bands allow.
    pub fn tile(i: u32, n: u32, width: u32, height: u32) -> Result<Self, RegionError> {
        if n == 0 || i >= n {
            return Err(RegionError::Index { i, n });
        }
        let bands = height.div_ceil(BAND_ROWS);
        if n > bands {
            return Err(RegionError::TooMany { n, height, bands });
        }
        let row = |k: u32| {
            ((u64::from(k) * u64::from(bands) / u64::from(n)) as u32 * BAND_ROWS).min(height)
        };
        let (y0, y1) = (row(i), row(i + 1));
        Ok(Self {
            x: 0,
            y: y0,
            width,
            height: y1 - y0,
        })
    }

    /// Its pixels.
    pub fn pixel_count(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Whether pixel (x, y) of the image lies within it.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        (self.x..self.x + self.width).contains(&x) && (self.y..self.y + self.height).contains(&y)
    }

    /// The region of an image's corner grid (`Scene::corner_grid`) whose
    /// means are this region's pixels: one more corner each way.
    pub fn corners(self) -> Self {
        Self {
            width: self.width + 1,
            height: self.height + 1,
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_are_bands_of_whole_workgroups_that_cover_the_image() {
        for (h, n) in [(600, 1), (600, 3), (601, 7), (61, 8), (17, 3), (128, 16)] {
            let mut next = 0;
            for i in 0..n {
                let t = Region::tile(i, n, 97, h).unwrap();
                assert_eq!((t.x, t.width, t.y), (0, 97, next), "{h} {n} {i}");
                assert!(t.height > 0);
                assert!(t.y % BAND_ROWS == 0);
                next = t.y + t.height;
            }
            assert_eq!(next, h);
        }
        assert!(Region::tile(3, 3, 10, 10).is_err());
        assert!(Region::tile(0, 3, 10, 10).is_err(), "two bands only");
        assert!(Region::whole(4, 4).within(3, 4).is_err());
        assert!(Region {
            x: 1,
            y: 1,
            width: 0,
            height: 1
        }
        .within(4, 4)
        .is_err());
    }
}

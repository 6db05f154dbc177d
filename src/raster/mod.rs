//! Linear RGB float images, their files (docs/scene-format.md, Outputs) and their differences.

pub mod diff;
pub mod io;
mod levels;
pub mod memory;
mod pfm;
pub mod plane;
pub mod region;

/// A linear RGB image, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Row by row from the top, `width` a row: red, green, blue.
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    /// The largest finite channel value, or 1 for an image that is all zero
    /// (the scale errors are relative to).
    pub fn peak(&self) -> f64 {
        let p = self
            .pixels
            .iter()
            .flatten()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(f64::from(v.abs())));
        if p > 0.0 {
            p
        } else {
            1.0
        }
    }

    /// Where the image has non-finite values (NaN or infinite): how many
    /// values, and the column and row of the first pixel holding one.
    pub fn nonfinite(&self) -> Option<(usize, u32, u32)> {
        let first = self
            .pixels
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))?;
        let count = self.pixels[first..]
            .iter()
            .flatten()
            .filter(|c| !c.is_finite())
            .count();
        let w = self.width as usize;
        Some((count, (first % w) as u32, (first / w) as u32))
    }

    /// This image divided by `by`, in f64 before rounding back, so that
    /// 1e-30 and 1e30 scale without loss.
    pub fn scaled(&self, by: f64) -> Image {
        let pixels = self
            .pixels
            .iter()
            .map(|p| p.map(|c| (f64::from(c) / by) as f32))
            .collect();
        Image::new(self.width, self.height, pixels)
    }

    /// An image of these pixels (`width × height` of them; panics otherwise).
    pub fn new(width: u32, height: u32, pixels: Vec<[f32; 3]>) -> Self {
        assert_eq!(
            pixels.len(),
            width as usize * height as usize,
            "pixel count"
        );
        Self {
            width,
            height,
            pixels,
        }
    }

    /// The pixel at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }
}

/// The sRGB transfer curve (IEC 61966-2-1) for one linear value in [0, 1].
pub fn srgb_encode(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB curve undone: the linear value of an encoded one in [0, 1]
/// (IEC 61966-2-1), as an 8- or 16-bit PNG texture is read.
pub fn srgb_decode(c: f64) -> f64 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A PNG's level (as level / 255 or / 65535 in f32) as a linear value:
/// decoded in f64 and rounded once, as every PNG glint reads is (the
/// texture loader, `io::read`, a numpy array of levels in the Python
/// module).
pub fn srgb_decode_level(c: f32) -> f32 {
    srgb_decode(f64::from(c)) as f32
}

/// Every channel of `pixels`, in order, as [`quantize`] makes it, over
/// the threads: an image's bytes for an 8-bit file.
pub fn quantize_pixels(pixels: &[[f32; 3]], srgb: bool) -> Vec<u8> {
    use rayon::prelude::*;
    const ROWS: usize = 4096;
    let mut bytes = vec![0u8; pixels.len() * 3];
    bytes
        .par_chunks_mut(3 * ROWS)
        .zip(pixels.par_chunks(ROWS))
        .for_each(|(out, pixels)| {
            for (out, p) in out.chunks_exact_mut(3).zip(pixels) {
                for (o, &c) in out.iter_mut().zip(p) {
                    *o = quantize(c, srgb);
                }
            }
        });
    bytes
}

/// docs/scene-format.md, Outputs: round(255 * clamp(c, 0, 1)), after the sRGB curve if asked.
/// NaN maps to 0, as `clamp` would leave it undefined.
pub fn quantize(c: f32, srgb: bool) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    if srgb {
        // The same level as round(255 * srgb_encode(c)), by table.
        levels::srgb_level(c)
    } else {
        (255.0 * c).round() as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_decode_undoes_the_encoding_and_keeps_the_ends() {
        assert_eq!(srgb_decode(0.0), 0.0);
        assert!((srgb_decode(1.0) - 1.0).abs() < 1e-15);
        for i in 0..=255 {
            let c = f64::from(i) / 255.0;
            let back = f64::from(srgb_encode(srgb_decode(c) as f32));
            assert!((back - c).abs() < 1e-6, "{i}: {back}");
        }
        // Mid-grey is darker in linear terms.
        assert!((srgb_decode(0.5) - 0.214).abs() < 1e-3);
    }

    /// A PNG read as linear and written again keeps its levels: what
    /// `glint assemble` and `glint.read` then `glint.write` rely on.
    #[test]
    fn every_level_survives_decoding_and_quantizing_again() {
        for q in 0..=255u8 {
            let linear = srgb_decode_level(f32::from(q) / 255.0);
            assert_eq!(quantize(linear, true), q, "level {q}");
        }
    }

    #[test]
    fn quantize_clamps_rounds_and_maps_nan_to_zero() {
        assert_eq!(quantize(-1.0, false), 0);
        assert_eq!(quantize(2.0, false), 255);
        assert_eq!(quantize(0.5, false), 128);
        assert_eq!(quantize(f32::NAN, false), 0);
        assert_eq!(quantize(f32::INFINITY, false), 255);
    }

    /// The sRGB levels by table keep quantize's ends: NaN and below 0 to
    /// 0, 1 and past it (infinity too) to 255; an image's bytes are its
    /// channels' levels in order, none for an empty image.
    #[test]
    fn srgb_quantizing_keeps_the_ends_and_an_images_bytes_are_its_levels() {
        assert_eq!(quantize(f32::NAN, true), 0);
        assert_eq!(quantize(-1.0, true), 0);
        assert_eq!(quantize(f32::NEG_INFINITY, true), 0);
        assert_eq!(quantize(1.0, true), 255);
        assert_eq!(quantize(f32::INFINITY, true), 255);
        assert_eq!(quantize(f32::MAX, true), 255);
        assert!(quantize_pixels(&[], true).is_empty());
        let pixels: Vec<[f32; 3]> = (0..10_000)
            .map(|i| {
                let v = i as f32 / 9_000.0 - 0.05;
                [v, f32::NAN, 1.0 - v]
            })
            .collect();
        for srgb in [false, true] {
            let bytes = quantize_pixels(&pixels, srgb);
            let one_by_one: Vec<u8> = pixels
                .iter()
                .flat_map(|p| p.map(|c| quantize(c, srgb)))
                .collect();
            assert_eq!(bytes, one_by_one);
        }
    }

    #[test]
    fn srgb_curve_is_continuous_and_brightens_midtones() {
        let below = srgb_encode(0.003_130_8);
        let above = srgb_encode(0.003_130_9);
        assert!((above - below).abs() < 1e-5);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert_eq!(quantize(0.5, true), 188);
    }
}

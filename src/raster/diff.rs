//! Error figures of an image against a reference (docs/commands.md), the heat-map of
//! their difference, and the tolerance `glint compare` holds the GPU to.

use serde::Serialize;

use super::Image;

/// the figures of docs/commands.md, over linear unclamped values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorFigures {
    /// Largest |a - ref| over finite channel pairs.
    pub max_abs: f64,
    /// Root mean square over finite channel pairs.
    pub rmse: f64,
    /// 10 log10(1 / mse) for a peak of 1, over finite channel pairs; +∞
    /// where the images agree exactly (no non-finite value either), −∞
    /// where a value is non-finite; `null` in JSON for either.
    #[serde(serialize_with = "finite_or_null")]
    pub psnr_db: f64,
    /// Fraction of pixels whose largest channel error exceeds 1/255 (a pixel
    /// with a non-finite channel counts as over).
    pub frac_over_1_255: f64,
    /// Channel pairs in which either image is NaN or infinite (each fails
    /// the comparison, the same NaN in both included).
    pub nonfinite: u64,
}

fn finite_or_null<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if v.is_finite() {
        s.serialize_f64(*v)
    } else {
        s.serialize_none()
    }
}

/// Two images of different sizes: the first's width and height, then the
/// reference's.
#[derive(Debug, thiserror::Error)]
#[error("the images differ in size: {0}x{1} against {2}x{3}")]
pub struct SizeMismatch(u32, u32, u32, u32);

/// The per-pixel error: the largest channel error, infinite where either
/// image has a non-finite channel.
pub fn pixel_errors(img: &Image, reference: &Image) -> Result<Vec<f64>, SizeMismatch> {
    same_size(img, reference)?;
    Ok(img
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, r)| pixel_error(a, r))
        .collect())
}

fn same_size(img: &Image, reference: &Image) -> Result<(), SizeMismatch> {
    if (img.width, img.height) != (reference.width, reference.height) {
        return Err(SizeMismatch(
            img.width,
            img.height,
            reference.width,
            reference.height,
        ));
    }
    Ok(())
}

/// The largest channel error of one pixel, infinite where a channel is
/// not finite in either image.
fn pixel_error(a: &[f32; 3], r: &[f32; 3]) -> f64 {
    (0..3)
        .map(|c| {
            let (a, r) = (f64::from(a[c]), f64::from(r[c]));
            if a.is_finite() && r.is_finite() {
                (a - r).abs()
            } else {
                f64::INFINITY
            }
        })
        .fold(0.0, f64::max)
}

/// The error figures of `img` against `reference`, over every channel of
/// every pixel. A non-finite value in either image is counted (`nonfinite`)
/// and fails every tolerance; the other figures are over the finite pairs.
///
/// ```
/// use glint::raster::{diff, Image};
///
/// let reference = Image::new(2, 1, vec![[0.5; 3], [0.25; 3]]);
/// let mut perturbed = reference.clone();
/// perturbed.pixels[1][0] += 0.1;
/// let f = diff::figures(&perturbed, &reference)?;
/// assert!((f.max_abs - 0.1).abs() < 1e-6);
/// assert!(!diff::Tolerance::default().violations(&f).is_empty());
/// assert!(diff::Tolerance::default().violations(&diff::figures(&reference, &reference)?).is_empty());
/// # Ok::<(), diff::SizeMismatch>(())
/// ```
pub fn figures(img: &Image, reference: &Image) -> Result<ErrorFigures, SizeMismatch> {
    figures_where(img, reference, |_| true)
}

/// The figures over the pixels `i` for which `counted(i)` holds (the
/// fraction over 1/255 is of those pixels).
pub fn figures_where(
    img: &Image,
    reference: &Image,
    counted: impl Fn(usize) -> bool,
) -> Result<ErrorFigures, SizeMismatch> {
    // The per-pixel error is taken pixel by pixel: a list of it would be 8
    // bytes a pixel more (2 GiB at the largest image).
    same_size(img, reference)?;
    let mut max_abs = 0.0f64;
    let mut sum_sq = 0.0f64;
    let mut finite_pairs = 0u64;
    let mut nonfinite = 0u64;
    let mut pixels = 0usize;
    let mut over = 0usize;
    for (i, (a, r)) in img.pixels.iter().zip(&reference.pixels).enumerate() {
        if !counted(i) {
            continue;
        }
        pixels += 1;
        over += usize::from(pixel_error(a, r) > 1.0 / 255.0);
        for c in 0..3 {
            let (a, r) = (f64::from(a[c]), f64::from(r[c]));
            if !a.is_finite() || !r.is_finite() {
                nonfinite += 1;
            }
            if a.is_finite() && r.is_finite() {
                let e = (a - r).abs();
                max_abs = max_abs.max(e);
                sum_sq += e * e;
                finite_pairs += 1;
            }
        }
    }
    let mse = if finite_pairs == 0 {
        0.0
    } else {
        sum_sq / finite_pairs as f64
    };
    Ok(ErrorFigures {
        max_abs,
        rmse: mse.sqrt(),
        psnr_db: if nonfinite > 0 {
            f64::NEG_INFINITY
        } else if mse == 0.0 {
            f64::INFINITY
        } else {
            -10.0 * mse.log10()
        },
        frac_over_1_255: over as f64 / pixels.max(1) as f64,
        nonfinite,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nan_in_either_image_is_counted_and_is_never_identical() {
        let clean = Image::new(2, 2, vec![[0.5; 3]; 4]);
        let mut nan = clean.clone();
        nan.pixels[1] = [f32::NAN, 0.5, f32::NAN];
        for (a, b) in [(&nan, &clean), (&clean, &nan), (&nan, &nan)] {
            let f = figures(a, b).unwrap();
            assert_eq!(f.nonfinite, 2, "{f:?}");
            assert_eq!(f.psnr_db, f64::NEG_INFINITY);
            assert_eq!(f.frac_over_1_255, 0.25);
            assert!(!Tolerance::default().violations(&f).is_empty());
        }
        assert_eq!(figures(&clean, &clean).unwrap().psnr_db, f64::INFINITY);
    }
}

/// How far the GPU's f32 image may be from the CPU f64 reference.
///
/// Away from edges, f32 against f64 differs by a few ulp of the colour
/// (around 1e-6, far below 1/255). A pixel can differ by the full local
/// contrast only where a ray passes within rounding distance of a silhouette
/// or a shadow edge and the two precisions decide the hit differently; such
/// pixels lie on curves, so they are a small fraction of the image, and with
/// f32 their count is tiny. The tolerance therefore bounds the fraction of
/// pixels over 1/255 and the RMSE, and admits no non-finite value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    /// The largest share of pixel channels that may be off by more than 1/255.
    pub frac_over_1_255: f64,
    /// The largest RMSE.
    pub rmse: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Self {
            frac_over_1_255: 1e-3,
            rmse: 4e-3,
        }
    }
}

impl Tolerance {
    /// The ways `f` breaks this tolerance; empty when it passes.
    pub fn violations(&self, f: &ErrorFigures) -> Vec<String> {
        let mut v = Vec::new();
        if f.nonfinite > 0 {
            v.push(format!("{} non-finite values", f.nonfinite));
        }
        if f.frac_over_1_255.is_nan() || f.frac_over_1_255 > self.frac_over_1_255 {
            v.push(format!(
                "{:.4}% of pixels are off by more than 1/255 (at most {:.4}% allowed)",
                100.0 * f.frac_over_1_255,
                100.0 * self.frac_over_1_255
            ));
        }
        if f.rmse.is_nan() || f.rmse > self.rmse {
            v.push(format!("rmse {:.3e} is over {:.3e}", f.rmse, self.rmse));
        }
        v
    }
}

/// A heat-map of the per-pixel error, for eyes: black where the images
/// agree, then on a log scale from 1e-7 (blue) through 1/255 (red) to 1 and
/// more (white); magenta where a value is not finite.
pub fn heat_map(img: &Image, reference: &Image) -> Result<Image, SizeMismatch> {
    let errors = pixel_errors(img, reference)?;
    let pixels = errors
        .iter()
        .map(|&e| {
            if e.is_infinite() {
                return [1.0, 0.0, 1.0];
            }
            if e == 0.0 {
                return [0.0, 0.0, 0.0];
            }
            let t = ((e.log10() + 7.0) / 7.0).clamp(0.0, 1.0) as f32;
            ramp(t)
        })
        .collect();
    Ok(Image::new(img.width, img.height, pixels))
}

/// Dark blue -> blue -> red -> yellow -> white over t in [0, 1].
fn ramp(t: f32) -> [f32; 3] {
    const STOPS: [(f32, [f32; 3]); 5] = [
        (0.0, [0.05, 0.05, 0.2]),
        (0.4, [0.1, 0.2, 0.9]),
        (0.66, [0.9, 0.1, 0.1]),
        (0.85, [1.0, 0.9, 0.1]),
        (1.0, [1.0, 1.0, 1.0]),
    ];
    for w in STOPS.windows(2) {
        let ((t0, c0), (t1, c1)) = (w[0], w[1]);
        if t <= t1 {
            let s = (t - t0) / (t1 - t0);
            return [0, 1, 2].map(|i| c0[i] + s * (c1[i] - c0[i]));
        }
    }
    STOPS[4].1
}

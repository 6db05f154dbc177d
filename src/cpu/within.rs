//! Every pixel of a CPU render is held to the brightest value the model
//! can make of its scene ([`Scene::brightest_pixel`]). The reference is
//! the oracle that `compare` scales its tolerance by: a pixel past the
//! bound would pass a wrong GPU image, so it is an error, never an image.

use crate::raster::Image;
use crate::scene::Scene;

/// What the bound allows past itself: it is reckoned in f64, and a pixel
/// sums its bounces and lights in the render's precision, each sum
/// rounded (f32: 2^-24 a step, a few hundred steps at the deepest).
const ROUNDING: f64 = 1e-4;

/// A pixel past the model's bound.
#[derive(Debug, thiserror::Error)]
#[error(
    "pixel ({x}, {y}) of the CPU {precision} render is {value:e}, past {bound:.6e}, the \
     brightest this scene's model can make: the render is wrong there and is not used"
)]
pub struct PastBound {
    /// The first such pixel's column, in the image checked.
    pub x: u32,
    /// Its row.
    pub y: u32,
    /// Its brightest channel.
    pub value: f32,
    /// The scene's bound ([`Scene::brightest_pixel`]).
    pub bound: f64,
    /// The render's precision: "f64" or "f32".
    pub precision: &'static str,
}

/// The first pixel of `image` (a render of `scene`, or a region of one)
/// past `scene`'s bound, if any.
pub fn check(scene: &Scene, image: &Image, precision: &'static str) -> Result<(), PastBound> {
    let bound = scene.brightest_pixel();
    let limit = bound * (1.0 + ROUNDING);
    let past = |p: &[f32; 3]| p.iter().any(|&c| f64::from(c) > limit);
    let Some(i) = image.pixels.iter().position(past) else {
        return Ok(());
    };
    let w = image.width as usize;
    let value = image.pixels[i].into_iter().fold(f32::MIN, f32::max);
    Err(PastBound {
        x: (i % w) as u32,
        y: (i / w) as u32,
        value,
        bound,
        precision,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{parse, Overrides};

    fn scene() -> Scene {
        let text = std::fs::read_to_string("scenes/seed-fig3.toml").unwrap();
        let small = Overrides {
            width: Some(8),
            height: Some(6),
            ..Overrides::default()
        };
        parse(&text, "seed-fig3.toml".as_ref(), &small).unwrap()
    }

    #[test]
    fn a_render_is_within_and_one_pixel_past_is_named() {
        let scene = scene();
        let mut image = crate::cpu::render::<f64>(&scene);
        check(&scene, &image, "f64").unwrap();
        let bound = scene.brightest_pixel();
        image.pixels[8 + 3][1] = (bound * 1.01) as f32;
        let e = check(&scene, &image, "f64").unwrap_err();
        assert_eq!((e.x, e.y), (3, 1));
        let text = e.to_string();
        assert!(
            text.contains("pixel (3, 1)") && text.contains("past"),
            "{text}"
        );
        // At the bound itself (rounded to f32) it passes.
        image.pixels[8 + 3][1] = bound as f32;
        check(&scene, &image, "f64").unwrap();
    }
}

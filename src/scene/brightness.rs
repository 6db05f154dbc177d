//! The brightest pixel the model can make of a scene: the bound that
//! loading refuses past `MAX_BRIGHTNESS`, and that every pixel of a CPU
//! render is held to ([`Scene::within`]). The reference is the oracle that
//! `compare` scales its tolerance by: a pixel past the bound would pass a
//! wrong GPU image, so it is an error, never an image.

use glam::DVec3;

use super::Scene;
use crate::raster::Image;

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

impl Scene {
    /// The most one bounce can add, for each light: (Ia·Ka + Id·Kd +
    /// Is·Ks) / c with each colour's brightest channel (a textured colour at
    /// its texture's brightest); every other factor of the shading (the
    /// cosines, a cone's falloff, the rest of the attenuation) is at most 1.
    pub fn light_peaks(&self) -> Vec<f64> {
        let max = |v: DVec3| v.max_element();
        let brightest = |colour: DVec3, texture: Option<u32>| match texture {
            Some(t) => max(self.textures[t as usize].brightest()),
            None => max(colour),
        };
        let (ka, kd, ks) = self
            .materials
            .iter()
            .fold((0.0f64, 0.0f64, 0.0f64), |m, mat| {
                (
                    m.0.max(brightest(mat.ambient, mat.ambient_texture)),
                    m.1.max(brightest(mat.diffuse, mat.texture)),
                    m.2.max(max(mat.specular)),
                )
            });
        self.lights
            .iter()
            .map(|l| {
                let c = l.peak_divisor();
                (max(l.ambient) * ka + max(l.diffuse) * kd + max(l.specular) * ks) / c
            })
            .collect()
    }

    /// The brightest pixel value the model can make of this scene: a
    /// bounce adds at most the background or the sum of
    /// [`light_peaks`](Self::light_peaks), and the path weights of one depth
    /// sum to at most g^(depth − 1), where g is the largest reflectivity +
    /// transmittance (a ray spawns both, or one with their sum under total
    /// internal reflection). A pixel is a mean of samples, so it is bounded
    /// too.
    pub fn brightest_pixel(&self) -> f64 {
        let bounce = self
            .light_peaks()
            .iter()
            .sum::<f64>()
            .max(self.background.max_element());
        let g = self
            .materials
            .iter()
            .map(|m| m.reflectivity + m.transmittance)
            .fold(1.0f64, f64::max);
        bounce * (0..self.max_depth).map(|d| g.powi(d as i32)).sum::<f64>()
    }

    /// The first pixel of `image` (a render of this scene in
    /// `precision`, or a region of one) past [`brightest_pixel`](Self::brightest_pixel), if any.
    pub fn within(&self, image: &Image, precision: &'static str) -> Result<(), PastBound> {
        let bound = self.brightest_pixel();
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
}

#[cfg(test)]
mod tests {
    use crate::raster::Image;
    use crate::scene::{parse, Overrides};

    #[test]
    fn an_image_within_the_bound_passes_and_one_pixel_past_is_named() {
        let text = std::fs::read_to_string("scenes/seed-fig3.toml").unwrap();
        let small = Overrides {
            width: Some(8),
            height: Some(6),
            ..Overrides::default()
        };
        let scene = parse(&text, "seed-fig3.toml".as_ref(), &small).unwrap();
        let bound = scene.brightest_pixel();
        // At the bound itself (rounded to f32) it passes.
        let mut image = Image::new(8, 6, vec![[bound as f32; 3]; 48]);
        scene.within(&image, "f64").unwrap();
        image.pixels[8 + 3][1] = (bound * 1.01) as f32;
        let e = scene.within(&image, "f64").unwrap_err();
        assert_eq!((e.x, e.y), (3, 1));
        let text = e.to_string();
        assert!(
            text.contains("pixel (3, 1) of the CPU f64 render") && text.contains("past"),
            "{text}"
        );
    }
}

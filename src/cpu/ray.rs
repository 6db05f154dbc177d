//! Eye rays through the virtual screen (docs/scene-format.md, Rays); mirrors shaders/ray.glsl.

use super::world::World;
use crate::base::ray::Ray;
use crate::base::real::Real;

/// The eye ray through the point (px, py) of the image traced, in pixels
/// (the centre of pixel x is at x + 0.5): adaptive sampling's rays between
/// the corners. Mirrors ray_through() in shaders/ray.glsl.
pub fn ray_through<R: Real>(w: &World<R>, px: R, py: R) -> Ray<R> {
    let two = R::of(2.0);
    let u = two * px / R::of(f64::from(w.width)) - R::one();
    let v = R::one() - two * py / R::of(f64::from(w.height));
    let to_pixel = w.to_screen + w.screen_right * u + w.screen_up * v;
    Ray {
        origin: w.eye,
        dir: to_pixel.normalize(),
    }
}

/// The eye ray for sample (i, j) of pixel (x, y).
pub fn primary_ray<R: Real>(w: &World<R>, x: u32, y: u32, i: u32, j: u32) -> Ray<R> {
    let half = R::of(0.5);
    let two = R::of(2.0);
    let n = R::of(f64::from(w.samples));
    let u = two * (R::of(f64::from(x)) + (R::of(f64::from(i)) + half) / n)
        / R::of(f64::from(w.width))
        - R::one();
    let v = R::one()
        - two * (R::of(f64::from(y)) + (R::of(f64::from(j)) + half) / n)
            / R::of(f64::from(w.height));
    let to_pixel = w.to_screen + w.screen_right * u + w.screen_up * v;
    Ray {
        origin: w.eye,
        dir: to_pixel.normalize(),
    }
}

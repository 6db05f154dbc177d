//! The brightest pixel the model can make of a scene: the bound that
//! loading refuses past `MAX_BRIGHTNESS` and that every reference pixel is
//! held to (`glint::cpu::within`).

use glam::DVec3;

use super::{LightKind, Scene};

impl Scene {
    /// The most one bounce can add, for each light: (Ia·Ka + Id·Kd +
    /// Is·Ks) / c with each colour's brightest channel (a textured colour at
    /// its texture's brightest); every other factor of the shading (the
    /// cosines, a spot's falloff, the rest of the attenuation) is at most 1.
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
                let c = if l.kind == LightKind::Directional {
                    1.0
                } else {
                    l.attenuation.x
                };
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
}

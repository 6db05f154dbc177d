//! The most rays a CPU render of a scene can cast, and the bound past which
//! the CPU refuses it (issue 21, defect 5). A material that both reflects
//! and transmits splits a ray in two at each bounce, so a ray tree can
//! double at every level of `max_depth`: 15 nested glass shells at depth
//! 64 are a valid scene of about 10^19 rays a pixel. The GPU stops such a
//! render at its watchdog; the CPU has none, so it refuses it up front.

use crate::scene::Scene;

/// The most rays (eye, reflection, refraction and shadow) a CPU render may
/// cast in the worst case: at the 10^7 rays a second of 2 cores, about a
/// day.
pub const MAX_RAYS: f64 = 1e12;

/// A scene whose worst case is past `MAX_RAYS`.
#[derive(Debug, thiserror::Error)]
#[error(
    "this scene can cast up to {rays:.1e} rays on the CPU, past its bound of {MAX_RAYS:.0e}: \
     {why} split a ray in two at each of {depth} bounces; lower max_depth to {fits} or less \
     (--max-depth), or {instead}"
)]
pub struct TooManyRays {
    /// The worst case.
    pub rays: f64,
    /// The scene's max_depth.
    pub depth: u32,
    /// The largest max_depth within the bound.
    pub fits: u32,
    /// Which materials split a ray.
    pub why: &'static str,
    /// What else would avoid the split.
    pub instead: &'static str,
}

/// Whether a ray can split in two at a bounce of `scene`: where a material
/// both reflects and transmits, and under `spd_rays` (the SPD's procedure
/// follows a reflection ray at every transmitter) wherever one transmits.
fn splits(scene: &Scene) -> bool {
    scene
        .materials
        .iter()
        .any(|m| m.transmittance > 0.0 && (m.reflectivity > 0.0 || scene.spd_rays))
}

/// The most rays a render of `scene` can cast: every eye ray's tree full to
/// `max_depth` (binary where a ray can split, `splits`), each node
/// with a shadow ray to every light.
pub fn worst_case_rays(scene: &Scene) -> f64 {
    rays_at_depth(scene, scene.max_depth)
}

fn rays_at_depth(scene: &Scene, depth: u32) -> f64 {
    let per_eye_ray = if splits(scene) {
        2f64.powi(depth as i32) - 1.0
    } else {
        f64::from(depth)
    };
    let pixels = f64::from(scene.width) * f64::from(scene.height);
    let eye = (f64::from(scene.width) + 1.0)
        * (f64::from(scene.height) + 1.0)
        * f64::from(scene.samples * scene.samples)
        + scene
            .adaptive_sampling()
            .map_or(0.0, |a| pixels * a.most_rays_per_pixel());
    eye * per_eye_ray * (1.0 + scene.lights.len() as f64)
}

/// Fails where `scene`'s worst case is past `MAX_RAYS`, naming the depth
/// that would fit.
pub fn check(scene: &Scene) -> Result<(), TooManyRays> {
    let rays = worst_case_rays(scene);
    if rays <= MAX_RAYS {
        return Ok(());
    }
    let fits = (1..scene.max_depth)
        .rev()
        .find(|&d| rays_at_depth(scene, d) <= MAX_RAYS)
        .unwrap_or(1);
    let (why, instead) = if scene.spd_rays {
        (
            "under spd_rays its transmitting materials",
            "leave out spd_rays",
        )
    } else {
        (
            "its materials that both reflect and transmit",
            "make those materials reflect or transmit, not both",
        )
    };
    Err(TooManyRays {
        rays,
        depth: scene.max_depth,
        fits,
        why,
        instead,
    })
}

//! The most rays a CPU render of a scene can cast, and the bound past which
//! the CPU refuses it. A material that both reflects and transmits splits a
//! ray in two at each bounce, so a ray tree can double at every level of
//! `max_depth`: 15 nested glass shells at depth 64 are a valid scene of
//! about 10^19 rays a pixel. The GPU stops such a render at its watchdog;
//! the CPU has none, so it refuses it up front.
//!
//! A ray's cost is bounded too, by the tree the scene's primitives make: a
//! million identical faces cannot be split, and every ray tests them all.

use crate::accel;
use crate::scene::Scene;

/// The most rays (eye, reflection, refraction and shadow) a CPU render may
/// cast in the worst case: at the 10^7 rays a second of 2 cores, about a
/// day.
pub const MAX_RAYS: f64 = 1e12;

/// The most ray–primitive tests and node visits a CPU render may make in
/// the worst case: 2 cores make about 3·10^7 a second here (the SPD's
/// balls, 9 a ray), so about 9 hours. A good tree costs 10–60 a ray, so
/// this bound meets only scenes already near `MAX_RAYS` or trees that
/// cannot separate their primitives.
pub const MAX_TESTS: f64 = 1e12;

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

/// A scene whose worst case costs more than `MAX_TESTS` through its tree.
#[derive(Debug, thiserror::Error)]
#[error(
    "this scene can cost up to {tests:.1e} tests on the CPU ({rays:.1e} rays, each {per_ray:.3e} \
     node visits and tests through its tree of {primitives} primitives), past its bound of \
     {MAX_TESTS:.0e}: its primitives overlap so that no tree separates them; render fewer \
     pixels or samples (--width, --height, --samples), a smaller max_depth, or on the GPU"
)]
pub struct TooManyTests {
    /// The worst case.
    pub tests: f64,
    /// Its rays (`worst_case_rays`).
    pub rays: f64,
    /// What a ray costs through the tree (`Bvh::ray_cost`).
    pub per_ray: f64,
    /// The bounded primitives in the tree.
    pub primitives: usize,
}

/// Why the CPU refuses a scene up front.
#[derive(Debug, thiserror::Error)]
pub enum Refused {
    /// Its rays.
    #[error(transparent)]
    Rays(#[from] TooManyRays),
    /// Its rays' cost through its tree.
    #[error(transparent)]
    Tests(#[from] TooManyTests),
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

/// Fails where `scene`'s worst case is past `MAX_RAYS` (naming the depth
/// that would fit), or its rays through its tree past `MAX_TESTS`.
pub fn check(scene: &Scene) -> Result<(), Refused> {
    let rays = worst_case_rays(scene);
    check_rays(scene, rays)?;
    check_tests(scene, rays)?;
    Ok(())
}

/// Fails where the worst case's rays, each at what a ray costs through
/// the scene's tree, pass `MAX_TESTS`. The tree is built only where a
/// ray testing every primitive could pass it.
fn check_tests(scene: &Scene, rays: f64) -> Result<(), TooManyTests> {
    let bounded = scene.prims.bounded_count();
    let unbounded = (scene.prims.len() - bounded) as f64;
    // A tree has fewer nodes than primitives: a ray can visit them all
    // and test every primitive, and no more.
    if rays * (2.0 * bounded as f64 + unbounded) <= MAX_TESTS || bounded == 0 {
        return Ok(());
    }
    let tree = accel::relative_bvh(&scene.prims, scene.camera.eye);
    let per_ray = tree.ray_cost() + unbounded;
    let tests = rays * per_ray;
    if tests <= MAX_TESTS {
        return Ok(());
    }
    Err(TooManyTests {
        tests,
        rays,
        per_ray,
        primitives: bounded,
    })
}

fn check_rays(scene: &Scene, rays: f64) -> Result<(), TooManyRays> {
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

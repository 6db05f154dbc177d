//! The scene in the reference's scalar type: what the shader's buffers hold.

use crate::accel::{self, bvh::Bvh, tables::Tables, Accel};
use crate::prim::CpuPrims;
use crate::scene::light::LightR;
use crate::scene::texture::TextureR;
use crate::scene::{MaterialR, Scene};

use crate::base::real::{Real, Vec3};

pub struct World<R: Real> {
    pub eye: Vec3<R>,
    /// screen_center - eye, taken in f64 before rounding, as the GPU gets it:
    /// far from the origin the eye and the screen share most of their digits.
    pub to_screen: Vec3<R>,
    pub screen_right: Vec3<R>,
    pub screen_up: Vec3<R>,
    pub prims: CpuPrims<R>,
    /// The BVH over the bounded kinds, where the scene is traced through one.
    pub bvh: Option<Bvh>,
    /// The light buffers and the eye's tiles (`accel::tables`), where the
    /// scene reads them.
    pub tables: Option<Tables>,
    pub materials: Vec<MaterialR<R>>,
    pub textures: Vec<TextureR<R>>,
    /// The images' texels (`Scene::texels`), shared with the scene.
    pub texels: std::sync::Arc<Vec<[f32; 3]>>,
    pub lights: Vec<LightR<R>>,
    pub background: Vec3<R>,
    pub shadows: bool,
    /// The SPD's ray tree (`Scene::spd_rays`).
    pub spd_rays: bool,
    pub max_depth: u32,
    /// The image traced: (w+1)×(h+1) where the scene samples pixel
    /// corners (`Scene::corner_grid`), which `render_world` then averages.
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub corners: bool,
    /// Adaptive sampling's threshold (in steps of 1/255) and levels, where
    /// the scene samples so.
    pub adaptive: Option<(R, u32)>,
    /// Contrast sampling's settings, where the scene samples so.
    pub contrast: Option<crate::scene::Contrast>,
    /// The conditioning check's moves ([`crate::condition`]): a trial's
    /// seed and the move relative to a hit point's size and a direction's
    /// length. None in every render.
    pub hit_move: Option<(u64, f64)>,
    /// Once set, rows not yet begun are skipped (`cpu::Prepared::stop_when`).
    pub stop: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
    /// The sampling decisions to replay (`Scene::replay`), where set.
    pub replay: Option<std::sync::Arc<crate::scene::decisions::Decisions>>,
}

impl<R: Real> World<R> {
    /// How its sampling takes decisions: its own, or those it replays.
    pub fn decider(&self) -> crate::sampling::Decider<'_> {
        crate::sampling::Decider {
            replay: self.replay.as_deref(),
        }
    }

    /// Whether a stop was asked for: the render is then cut short.
    pub fn stopped(&self) -> bool {
        self.stop
            .as_ref()
            .is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// The scene in camera-relative coordinates (see `Scene::camera_relative`),
    /// rounded to `R`.
    pub fn new(scene: &Scene, accel: Accel) -> Self {
        let adaptive = scene
            .adaptive_sampling()
            .map(|a| (R::of(a.threshold_steps()), a.levels));
        let grid = scene.corner_grid();
        let corners = grid.is_some();
        let scene = grid.as_ref().unwrap_or(scene);
        // Camera-relative, as `Scene::camera_relative` makes it, primitive
        // by primitive: no translated copy of the scene is held.
        let origin = scene.camera.eye;
        let bvh = accel
            .uses_bvh(&scene.prims)
            .then(|| accel::relative_bvh(&scene.prims, origin));
        let tables = bvh
            .as_ref()
            .filter(|_| accel.uses_tables(&scene.prims))
            .and_then(|tree| scene.tables(tree, origin, (scene.width, scene.height)));
        let cam = &scene.camera;
        let (eye, screen_center) = (cam.eye - origin, cam.screen_center - origin);
        Self {
            eye: Vec3::of(eye),
            to_screen: Vec3::of(screen_center - eye),
            screen_right: Vec3::of(cam.screen_right),
            screen_up: Vec3::of(cam.screen_up),
            prims: scene.prims.relative_cpu(origin),
            bvh,
            tables,
            materials: scene.materials.iter().map(|m| m.cpu()).collect(),
            textures: scene.textures.iter().map(|t| t.cpu(origin)).collect(),
            texels: scene.texels.clone(),
            lights: scene.lights.iter().map(|l| l.cpu(origin)).collect(),
            background: Vec3::of(scene.background),
            shadows: scene.shadows,
            spd_rays: scene.spd_rays,
            max_depth: scene.max_depth,
            width: scene.width,
            height: scene.height,
            samples: scene.samples,
            corners,
            adaptive,
            contrast: scene.contrast_sampling(),
            hit_move: None,
            stop: None,
            replay: scene.replay.clone(),
        }
    }
}

impl<R: Real> World<R> {
    /// A trial's random unit vector for `p` and `salt`: drawn from their
    /// bits, so that every hit moves its own way and a trial repeats.
    fn trial_unit(seed: u64, p: Vec3<R>, salt: u64) -> glam::DVec3 {
        use std::hash::Hasher;
        let mut hash = crate::fnv::Fnv::from_state(seed);
        for c in [p.x, p.y, p.z] {
            hash.write_u64(c.to_f64().to_bits());
        }
        hash.write_u64(salt);
        crate::rng::Xorshift(hash.finish() | 1).unit()
    }

    /// The hit point `p`, moved by the trial's share of its largest
    /// coordinate, as f32 rounds it (`hit_move`); p itself in a render.
    pub fn moved_point(&self, p: Vec3<R>) -> Vec3<R> {
        let Some((seed, share)) = self.hit_move else {
            return p;
        };
        let size = p.x.abs().max(p.y.abs()).max(p.z.abs()).to_f64();
        p + Vec3::of(Self::trial_unit(seed, p, u64::MAX) * (share * size))
    }

    /// The unit direction `d` of a ray leaving `p` (`salt`: which of its
    /// rays), turned by the trial's share, as f32 rounds a direction: over
    /// a long ray (a shadow ray from a wall 1e6 away) that moves it across
    /// a shadow's edge as moving p does not. `d` itself in a render.
    pub fn moved_direction(&self, d: Vec3<R>, p: Vec3<R>, salt: u64) -> Vec3<R> {
        let Some((seed, share)) = self.hit_move else {
            return d;
        };
        (d + Vec3::of(Self::trial_unit(seed, p, salt) * share)).normalize()
    }
}

//! What the shader is compiled with for a scene and device: the features
//! the scene needs (everything else is left out of the shader), the
//! constants that replace run-time counts, and the bindings that go with
//! them. `--generic` compiles the one shader that handles every feature.

use ash::vk;

use super::layout::Uploads;
use super::vk::device::DeviceInfo;
use super::{Intersect, Precision};
use crate::scene::{LightKind, Scene};

/// Unrolling the scene loops is worth its compile time up to this many
/// spheres and planes (each loop body is copied once per object, at every
/// place the shader walks the scene). Also, lavapipe (Mesa 22.3) was seen to
/// miscompile the unrolled shadow loop of a scene with 103 objects; 60 were
/// right; `glint compare` and the tests catch such a thing.
const UNROLL_OBJECTS: usize = 64;
const UNROLL_LIGHTS: usize = 16;

/// The blocks of shaders/bindings.glsl, in binding order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Block {
    Globals,
    Spheres,
    Planes,
    Materials,
    Lights,
    Nodes,
    Pixels,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Variant {
    pub intersect: Intersect,
    pub precision: Precision,
    /// The BVH's layouts (8, one per ray octant, or 1) where spheres are
    /// traced through it (shaders/bvh.glsl); 0: a linear scan.
    pub bvh_layouts: usize,
    /// None: the generic shader.
    pub features: Option<Features>,
}

/// What one scene needs of the shader.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Features {
    /// Spheres, planes, lights.
    pub counts: [usize; 3],
    pub point: bool,
    pub directional: bool,
    pub spot: bool,
    /// A point or spot light whose falloff is not [1, 0, 0].
    pub attenuation: bool,
    /// Shadows on, with lights and objects to cast them.
    pub shadows: bool,
    /// Ray segments traced: 1 where no material reflects.
    pub max_depth: u32,
    pub samples: u32,
    /// The scene's arrays as uniform buffers of these lengths (spheres,
    /// planes, materials, lights) where they fit; else storage buffers.
    pub uniform_slots: Option<[usize; 4]>,
    pub unroll: bool,
    /// BVH nodes per layout; 0 without a BVH.
    pub nodes: usize,
    /// BVH layouts: 8 (one per ray octant) or 1.
    pub layouts: usize,
}

impl Features {
    pub fn of(scene: &Scene, uploads: &Uploads, device: &DeviceInfo) -> Self {
        let has = |k: LightKind| scene.lights.iter().any(|l| l.kind == k);
        let counts = [scene.spheres.len(), scene.planes.len(), scene.lights.len()];
        let objects = counts[0] + counts[1] > 0;
        let reflects = scene.materials.iter().any(|m| m.reflectivity > 0.0);
        // Lavapipe (Mesa 22.3) crashed in a worker thread rendering the
        // uniform-buffer variant of scenes without spheres (planes and lights
        // only); those take storage buffers.
        let range = device.max_uniform_buffer_range as usize;
        let fits = counts[0] > 0
            && uploads.array_bytes().iter().all(|b| *b <= range)
            && uploads
                .nodes
                .as_ref()
                .is_none_or(|n| n.bytes.len() <= range);
        Self {
            counts,
            point: has(LightKind::Point),
            directional: has(LightKind::Directional),
            spot: has(LightKind::Spot),
            attenuation: scene.lights.iter().any(|l| {
                l.kind != LightKind::Directional && l.attenuation != glam::DVec3::new(1.0, 0.0, 0.0)
            }),
            shadows: scene.shadows && objects && counts[2] > 0,
            max_depth: if reflects { scene.max_depth } else { 1 },
            samples: scene.samples,
            uniform_slots: fits.then(|| uploads.array_lengths()),
            unroll: fits && counts[0] + counts[1] <= UNROLL_OBJECTS && counts[2] <= UNROLL_LIGHTS,
            nodes: uploads.layout_len,
            layouts: uploads.layouts,
        }
    }

    fn defines(&self, d: &mut Vec<(String, Option<String>)>) {
        let mut def = |name: &str, value: String| d.push((name.to_owned(), Some(value)));
        let flag = |b: bool| u8::from(b).to_string();
        let [ns, np, nl] = self.counts;
        def("HAS_SPHERES", flag(ns > 0));
        def("HAS_PLANES", flag(np > 0));
        def("HAS_POINT", flag(self.point));
        def("HAS_DIRECTIONAL", flag(self.directional));
        def("HAS_SPOT", flag(self.spot));
        def("HAS_ATTENUATION", flag(self.attenuation));
        def("HAS_SHADOWS", flag(self.shadows));
        def("SHADOWS_ON", "true".to_owned());
        def("MAX_DEPTH", format!("{}u", self.max_depth));
        def("SAMPLES", format!("{}u", self.samples));
        def("SPHERE_COUNT", format!("{ns}u"));
        def("PLANE_COUNT", format!("{np}u"));
        def("LIGHT_COUNT", format!("{nl}u"));
        if let Some([s, p, m, l]) = self.uniform_slots {
            d.push(("SCENE_IN_UNIFORMS".to_owned(), None));
            for (name, n) in [
                ("SPHERE_SLOTS", s),
                ("PLANE_SLOTS", p),
                ("MATERIAL_SLOTS", m),
                ("LIGHT_SLOTS", l),
            ] {
                d.push((name.to_owned(), Some(format!("{n}u"))));
            }
        }
        if self.unroll {
            d.push(("UNROLL_LOOPS".to_owned(), None));
        }
        if self.nodes > 0 {
            d.push(("NODE_COUNT".to_owned(), Some(format!("{}u", self.nodes))));
            if self.uniform_slots.is_some() {
                let slots = self.nodes * self.layouts;
                d.push(("NODE_SLOTS".to_owned(), Some(format!("{slots}u"))));
            }
        }
    }
}

impl Variant {
    pub fn for_scene(
        scene: &Scene,
        uploads: &Uploads,
        intersect: Intersect,
        precision: Precision,
        device: &DeviceInfo,
        generic: bool,
    ) -> Self {
        Self {
            intersect,
            precision,
            bvh_layouts: uploads.layouts,
            features: (!generic).then(|| Features::of(scene, uploads, device)),
        }
    }

    pub fn defines(&self) -> Vec<(String, Option<String>)> {
        let mut d = Vec::new();
        if self.intersect == Intersect::Naive {
            d.push(("INTERSECT_NAIVE".to_owned(), None));
        }
        if self.precision == Precision::F64 {
            d.push(("GLINT_F64".to_owned(), None));
        }
        if self.bvh_layouts > 0 {
            d.push(("USE_BVH".to_owned(), None));
            d.push(("LAYOUTS".to_owned(), Some(format!("{}u", self.bvh_layouts))));
        }
        if let Some(f) = &self.features {
            f.defines(&mut d);
        }
        for (block, binding, _) in self.bindings() {
            let name = match block {
                Block::Globals => continue,
                Block::Spheres => "SPHERES_BINDING",
                Block::Planes => "PLANES_BINDING",
                Block::Materials => "MATERIALS_BINDING",
                Block::Lights => "LIGHTS_BINDING",
                Block::Nodes => "NODES_BINDING",
                Block::Pixels => "PIXELS_BINDING",
            };
            d.push((name.to_owned(), Some(binding.to_string())));
        }
        d
    }

    /// The blocks the shader declares, numbered densely from 0, with their
    /// descriptor types.
    pub fn bindings(&self) -> Vec<(Block, u32, vk::DescriptorType)> {
        let scene_type = if self.in_uniforms() {
            vk::DescriptorType::UNIFORM_BUFFER
        } else {
            vk::DescriptorType::STORAGE_BUFFER
        };
        let [spheres, planes, lights] = match &self.features {
            Some(f) => f.counts.map(|n| n > 0),
            None => [true; 3],
        };
        let blocks = [
            (Block::Globals, true, vk::DescriptorType::UNIFORM_BUFFER),
            (Block::Spheres, spheres, scene_type),
            (Block::Planes, planes, scene_type),
            (Block::Materials, spheres || planes, scene_type),
            (Block::Lights, lights, scene_type),
            (Block::Nodes, self.bvh_layouts > 0, scene_type),
            (Block::Pixels, true, vk::DescriptorType::STORAGE_BUFFER),
        ];
        blocks
            .into_iter()
            .filter(|(_, used, _)| *used)
            .enumerate()
            .map(|(i, (block, _, ty))| (block, i as u32, ty))
            .collect()
    }

    /// (binding, descriptor type) for the descriptor set layout.
    pub fn descriptor_layout(&self) -> Vec<(u32, vk::DescriptorType)> {
        self.bindings()
            .into_iter()
            .map(|(_, b, t)| (b, t))
            .collect()
    }

    /// Whether the scene's arrays are uniform buffers (else storage buffers).
    fn in_uniforms(&self) -> bool {
        self.features
            .as_ref()
            .is_some_and(|f| f.uniform_slots.is_some())
    }

    pub fn scene_buffer_usage(&self) -> vk::BufferUsageFlags {
        if self.in_uniforms() {
            vk::BufferUsageFlags::UNIFORM_BUFFER
        } else {
            vk::BufferUsageFlags::STORAGE_BUFFER
        }
    }

    /// A short name for files and messages: the generic shader, or the
    /// features this variant keeps.
    pub fn name(&self) -> String {
        let mut parts = vec![match self.intersect {
            Intersect::Robust => "robust",
            Intersect::Naive => "naive",
        }
        .to_owned()];
        if self.precision == Precision::F64 {
            parts.push("f64".to_owned());
        }
        if self.bvh_layouts > 0 {
            parts.push(format!("bvh{}", self.bvh_layouts));
        }
        match &self.features {
            None => parts.push("generic".to_owned()),
            Some(f) => {
                let [s, p, l] = f.counts;
                parts.push(format!("s{s}-p{p}-l{l}"));
                for (on, name) in [
                    (f.point, "point"),
                    (f.directional, "dir"),
                    (f.spot, "spot"),
                    (f.attenuation, "att"),
                    (f.shadows, "shadows"),
                    (f.uniform_slots.is_some(), "ubo"),
                    (f.unroll, "unrolled"),
                ] {
                    if on {
                        parts.push(name.to_owned());
                    }
                }
                parts.push(format!("d{}-ss{}", f.max_depth, f.samples));
            }
        }
        parts.join("-")
    }
}

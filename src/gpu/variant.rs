//! What the shader is compiled with for a given scene and device: the
//! preprocessor defines that pick a variant, and the descriptor types that
//! go with them.

use ash::vk;

use super::layout::Uploads;
use super::vk::device::DeviceInfo;
use super::Intersect;
use crate::scene::Scene;

/// Unrolling the scene loops is worth its compile time up to this many
/// spheres and planes (each loop body is copied once per object, at every
/// place the shader walks the scene). Also, lavapipe (Mesa 22.3) was seen to
/// miscompile the unrolled shadow loop of a scene with 103 objects; 60 were
/// right; `glint compare` and the tests catch such a thing.
const UNROLL_OBJECTS: usize = 64;
const UNROLL_LIGHTS: usize = 16;
const UNROLL_MATERIALS: usize = 16;

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Variant {
    pub intersect: Intersect,
    /// The scene's arrays as uniform buffers with constant counts; None:
    /// storage buffers, counts read from the uniform block.
    pub uniforms: Option<UniformScene>,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct UniformScene {
    /// Array lengths as uploaded: spheres, planes, materials, lights.
    pub slots: [usize; 4],
    /// Objects in the scene: spheres, planes, lights.
    pub counts: [usize; 3],
    pub unroll: bool,
}

impl Variant {
    pub fn for_scene(
        scene: &Scene,
        uploads: &Uploads,
        intersect: Intersect,
        device: &DeviceInfo,
    ) -> Self {
        let limit = device.max_uniform_buffer_range as usize;
        let fits = uploads.array_bytes().iter().all(|b| *b <= limit);
        let counts = [scene.spheres.len(), scene.planes.len(), scene.lights.len()];
        Self {
            intersect,
            uniforms: fits.then(|| UniformScene {
                slots: uploads.array_lengths(),
                counts,
                unroll: counts[0] + counts[1] <= UNROLL_OBJECTS
                    && counts[2] <= UNROLL_LIGHTS
                    && scene.materials.len() <= UNROLL_MATERIALS,
            }),
        }
    }

    pub fn defines(&self) -> Vec<(String, Option<String>)> {
        let mut d = Vec::new();
        if self.intersect == Intersect::Naive {
            d.push(("INTERSECT_NAIVE".to_owned(), None));
        }
        if let Some(u) = &self.uniforms {
            let [s, p, m, l] = u.slots;
            let [ns, np, nl] = u.counts;
            d.push(("SCENE_IN_UNIFORMS".to_owned(), None));
            let numbers = [
                ("SPHERE_SLOTS", s),
                ("PLANE_SLOTS", p),
                ("MATERIAL_SLOTS", m),
                ("LIGHT_SLOTS", l),
                ("SPHERE_COUNT", ns),
                ("PLANE_COUNT", np),
                ("LIGHT_COUNT", nl),
            ];
            for (name, n) in numbers {
                d.push((name.to_owned(), Some(format!("{n}u"))));
            }
            if u.unroll {
                d.push(("UNROLL_LOOPS".to_owned(), None));
            }
        }
        d
    }

    /// Binding 0 the globals, 1-4 the scene's arrays, 5 the output tile.
    pub fn descriptor_types(&self) -> [vk::DescriptorType; 6] {
        let scene = self.scene_descriptor();
        [
            vk::DescriptorType::UNIFORM_BUFFER,
            scene,
            scene,
            scene,
            scene,
            vk::DescriptorType::STORAGE_BUFFER,
        ]
    }

    fn scene_descriptor(&self) -> vk::DescriptorType {
        if self.uniforms.is_some() {
            vk::DescriptorType::UNIFORM_BUFFER
        } else {
            vk::DescriptorType::STORAGE_BUFFER
        }
    }

    pub fn scene_buffer_usage(&self) -> vk::BufferUsageFlags {
        if self.uniforms.is_some() {
            vk::BufferUsageFlags::UNIFORM_BUFFER
        } else {
            vk::BufferUsageFlags::STORAGE_BUFFER
        }
    }
}

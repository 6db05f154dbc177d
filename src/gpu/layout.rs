//! The host side of shaders/bindings.glsl: Pod structs of vec4/uvec4 only, so
//! std140 and std430 place every field where `repr(C)` does.

use bytemuck::{Pod, Zeroable};
use glam::{DVec3, UVec4, Vec4};

use super::Intersect;
use crate::scene::{LightKind, Scene};

fn v4(v: DVec3) -> Vec4 {
    v.as_vec3().extend(0.0)
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Globals {
    pub eye: Vec4,
    pub to_screen: Vec4,
    pub screen_right: Vec4,
    pub screen_up: Vec4,
    pub background: Vec4,
    /// width, height, samples, max_depth
    pub size: UVec4,
    /// spheres, planes, lights, shadows
    pub counts: UVec4,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuSphere {
    pub center_radius: Vec4,
    pub meta: UVec4,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuPlane {
    pub point: Vec4,
    pub normal: Vec4,
    pub meta: UVec4,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuMaterial {
    pub ambient: Vec4,
    pub diffuse: Vec4,
    pub specular: Vec4,
    pub params: Vec4,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuLight {
    pub position: Vec4,
    pub direction: Vec4,
    pub ambient: Vec4,
    pub diffuse: Vec4,
    pub specular: Vec4,
    pub attenuation: Vec4,
    pub spot: Vec4,
    pub meta: UVec4,
}

/// The push constant: tile origin x, y, width, height.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct TileRect(pub UVec4);

/// Everything the shader reads, laid out for upload.
pub struct Uploads {
    pub globals: Globals,
    pub spheres: Vec<GpuSphere>,
    pub planes: Vec<GpuPlane>,
    pub materials: Vec<GpuMaterial>,
    pub lights: Vec<GpuLight>,
}

impl Uploads {
    /// The robust forms trace the scene in camera-relative coordinates (see
    /// `Scene::camera_relative`); the naive ones trace it as written.
    pub fn new(scene: &Scene, intersect: Intersect) -> Self {
        let relative;
        let scene = match intersect {
            Intersect::Robust => {
                relative = scene.camera_relative();
                &relative
            }
            Intersect::Naive => scene,
        };
        let cam = &scene.camera;
        let globals = Globals {
            eye: v4(cam.eye),
            to_screen: v4(cam.screen_center - cam.eye),
            screen_right: v4(cam.screen_right),
            screen_up: v4(cam.screen_up),
            background: v4(scene.background),
            size: UVec4::new(scene.width, scene.height, scene.samples, scene.max_depth),
            counts: UVec4::new(
                scene.spheres.len() as u32,
                scene.planes.len() as u32,
                scene.lights.len() as u32,
                u32::from(scene.shadows),
            ),
        };
        let spheres = scene
            .spheres
            .iter()
            .map(|s| GpuSphere {
                center_radius: s.center.as_vec3().extend(s.radius as f32),
                meta: UVec4::new(s.material, 0, 0, 0),
            })
            .collect();
        let planes = scene
            .planes
            .iter()
            .map(|p| GpuPlane {
                point: v4(p.point),
                normal: v4(p.normal),
                meta: UVec4::new(p.material, 0, 0, 0),
            })
            .collect();
        let materials = scene
            .materials
            .iter()
            .map(|m| GpuMaterial {
                ambient: v4(m.ambient),
                diffuse: v4(m.diffuse),
                specular: v4(m.specular),
                params: Vec4::new(m.shininess as f32, m.reflectivity as f32, 0.0, 0.0),
            })
            .collect();
        let lights = scene
            .lights
            .iter()
            .map(|l| GpuLight {
                position: v4(l.position),
                direction: v4(l.direction),
                ambient: v4(l.ambient),
                diffuse: v4(l.diffuse),
                specular: v4(l.specular),
                attenuation: v4(l.attenuation),
                spot: Vec4::new(l.cos_cutoff as f32, l.exponent as f32, 0.0, 0.0),
                meta: UVec4::new(
                    match l.kind {
                        LightKind::Point => 0,
                        LightKind::Directional => 1,
                        LightKind::Spot => 2,
                    },
                    u32::from(l.has_direct_term()),
                    0,
                    0,
                ),
            })
            .collect();
        Self {
            globals,
            spheres: at_least_one(spheres),
            planes: at_least_one(planes),
            materials: at_least_one(materials),
            lights: at_least_one(lights),
        }
    }

    /// Bytes of each scene array: spheres, planes, materials, lights.
    pub fn array_bytes(&self) -> [usize; 4] {
        [
            std::mem::size_of_val(self.spheres.as_slice()),
            std::mem::size_of_val(self.planes.as_slice()),
            std::mem::size_of_val(self.materials.as_slice()),
            std::mem::size_of_val(self.lights.as_slice()),
        ]
    }

    /// Elements of each scene array, as uploaded.
    pub fn array_lengths(&self) -> [usize; 4] {
        [
            self.spheres.len(),
            self.planes.len(),
            self.materials.len(),
            self.lights.len(),
        ]
    }
}

/// Vulkan has no empty buffers and GLSL no empty arrays: an absent kind of
/// object is uploaded as one zeroed slot, which the counts never reach.
fn at_least_one<T: Zeroable>(mut v: Vec<T>) -> Vec<T> {
    if v.is_empty() {
        v.push(T::zeroed());
    }
    v
}

//! The host side of shaders/bindings.glsl: Pod structs of 4-vectors only, so
//! std140 and std430 place every field where `repr(C)` does. Each struct
//! comes in f32 (vec4) and f64 (dvec4) form; the f64 forms carry explicit
//! padding to the 32-byte alignment that std140/std430 give a dvec4.

use bytemuck::{Pod, Zeroable};
use glam::{DVec3, DVec4, UVec4, Vec4};

use super::{Intersect, Precision};
use crate::accel::{self, Accel};
use crate::scene::{LightKind, Scene};

/// Builds a 4-vector of the layout's scalar from f64 values.
pub trait Vector: Pod {
    fn of(x: f64, y: f64, z: f64, w: f64) -> Self;
    fn of3(v: DVec3) -> Self {
        Self::of(v.x, v.y, v.z, 0.0)
    }
}

impl Vector for Vec4 {
    fn of(x: f64, y: f64, z: f64, w: f64) -> Self {
        Vec4::new(x as f32, y as f32, z as f32, w as f32)
    }
}

impl Vector for DVec4 {
    fn of(x: f64, y: f64, z: f64, w: f64) -> Self {
        DVec4::new(x, y, z, w)
    }
}

/// Declares one family of structs: `$v` the 4-vector, `$pad_*` the padding
/// (in u32s) that rounds each struct up to its alignment.
macro_rules! structs {
    ($m:ident, $v:ty, $pad_sphere:expr, $pad_plane:expr, $pad_light:expr) => {
        pub mod $m {
            use super::*;

            #[repr(C)]
            #[derive(Clone, Copy, Pod, Zeroable)]
            pub struct Globals {
                pub eye: $v,
                pub to_screen: $v,
                pub screen_right: $v,
                pub screen_up: $v,
                pub background: $v,
                /// width, height, samples, max_depth
                pub size: UVec4,
                /// spheres, planes, lights, shadows
                pub counts: UVec4,
            }

            #[repr(C)]
            #[derive(Clone, Copy, Pod, Zeroable)]
            pub struct Sphere {
                pub center_radius: $v,
                pub meta: UVec4,
                pub pad: [u32; $pad_sphere],
            }

            #[repr(C)]
            #[derive(Clone, Copy, Pod, Zeroable)]
            pub struct Plane {
                pub point: $v,
                pub normal: $v,
                pub meta: UVec4,
                pub pad: [u32; $pad_plane],
            }

            #[repr(C)]
            #[derive(Clone, Copy, Pod, Zeroable)]
            pub struct Material {
                pub ambient: $v,
                pub diffuse: $v,
                pub specular: $v,
                pub params: $v,
            }

            #[repr(C)]
            #[derive(Clone, Copy, Pod, Zeroable)]
            pub struct Light {
                pub position: $v,
                pub direction: $v,
                pub ambient: $v,
                pub diffuse: $v,
                pub specular: $v,
                pub attenuation: $v,
                pub spot: $v,
                pub meta: UVec4,
                pub pad: [u32; $pad_light],
            }

            /// The scene's arrays in this layout; an absent kind of object is
            /// one zeroed slot (Vulkan has no empty buffers, GLSL no empty
            /// arrays), which the counts never reach.
            /// `order`: the spheres in the BVH's leaf order, where there is one.
            pub fn upload(scene: &Scene, order: Option<&[u32]>) -> Uploads {
                let cam = &scene.camera;
                let globals = Globals {
                    eye: <$v>::of3(cam.eye),
                    to_screen: <$v>::of3(cam.screen_center - cam.eye),
                    screen_right: <$v>::of3(cam.screen_right),
                    screen_up: <$v>::of3(cam.screen_up),
                    background: <$v>::of3(scene.background),
                    size: UVec4::new(scene.width, scene.height, scene.samples, scene.max_depth),
                    counts: UVec4::new(
                        scene.spheres.len() as u32,
                        scene.planes.len() as u32,
                        scene.lights.len() as u32,
                        u32::from(scene.shadows),
                    ),
                };
                let linear: Vec<u32>;
                let order = match order {
                    Some(o) => o,
                    None => {
                        linear = (0..scene.spheres.len() as u32).collect();
                        &linear
                    }
                };
                let spheres: Vec<Sphere> = order
                    .iter()
                    .map(|&i| {
                        let s = &scene.spheres[i as usize];
                        Sphere {
                            center_radius: <$v>::of(s.center.x, s.center.y, s.center.z, s.radius),
                            meta: UVec4::new(s.material, i, 0, 0),
                            pad: Zeroable::zeroed(),
                        }
                    })
                    .collect();
                let planes: Vec<Plane> = scene
                    .planes
                    .iter()
                    .map(|p| Plane {
                        point: <$v>::of3(p.point),
                        normal: <$v>::of3(p.normal),
                        meta: UVec4::new(p.material, 0, 0, 0),
                        pad: Zeroable::zeroed(),
                    })
                    .collect();
                let materials: Vec<Material> = scene
                    .materials
                    .iter()
                    .map(|m| Material {
                        ambient: <$v>::of3(m.ambient),
                        diffuse: <$v>::of3(m.diffuse),
                        specular: <$v>::of3(m.specular),
                        params: <$v>::of(m.shininess, m.reflectivity, 0.0, 0.0),
                    })
                    .collect();
                let lights: Vec<Light> = scene
                    .lights
                    .iter()
                    .map(|l| Light {
                        position: <$v>::of3(l.position),
                        direction: <$v>::of3(l.direction),
                        ambient: <$v>::of3(l.ambient),
                        diffuse: <$v>::of3(l.diffuse),
                        specular: <$v>::of3(l.specular),
                        attenuation: <$v>::of3(l.attenuation),
                        spot: <$v>::of(l.cos_cutoff, l.exponent, 0.0, 0.0),
                        meta: UVec4::new(kind_code(l.kind), u32::from(l.has_direct_term()), 0, 0),
                        pad: Zeroable::zeroed(),
                    })
                    .collect();
                Uploads {
                    nodes: None,
                    layout_len: 0,
                    layouts: 0,
                    bvh_s: 0.0,
                    globals: bytemuck::bytes_of(&globals).to_vec(),
                    arrays: [
                        array(spheres),
                        array(planes),
                        array(materials),
                        array(lights),
                    ],
                }
            }
        }
    };
}

structs!(f32_layout, Vec4, 0, 0, 0);
structs!(f64_layout, DVec4, 4, 4, 4);

fn kind_code(kind: LightKind) -> u32 {
    match kind {
        LightKind::Point => 0,
        LightKind::Directional => 1,
        LightKind::Spot => 2,
    }
}

/// One scene array as bytes, with its element count (at least 1).
#[derive(Debug, Clone)]
pub struct Array {
    pub bytes: Vec<u8>,
    pub len: usize,
}

fn array<T: Pod>(mut v: Vec<T>) -> Array {
    if v.is_empty() {
        v.push(T::zeroed());
    }
    Array {
        bytes: bytemuck::cast_slice(&v).to_vec(),
        len: v.len(),
    }
}

/// The push constant: tile origin x, y, width, height.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct TileRect(pub UVec4);

/// Everything the shader reads, laid out for upload.
pub struct Uploads {
    pub globals: Vec<u8>,
    /// Spheres, planes, materials, lights.
    pub arrays: [Array; 4],
    /// The spheres' BVH nodes, where the scene is traced through one: one
    /// layout per ray octant (or one), `layout_len` nodes each.
    pub nodes: Option<Array>,
    pub layout_len: usize,
    pub layouts: usize,
    /// Seconds spent building the BVH.
    pub bvh_s: f64,
}

impl Uploads {
    /// The robust forms trace the scene in camera-relative coordinates (see
    /// `Scene::camera_relative`); the naive ones trace it as written.
    pub fn new(scene: &Scene, intersect: Intersect, precision: Precision, accel: Accel) -> Self {
        let relative;
        let scene = match intersect {
            Intersect::Robust => {
                relative = scene.camera_relative();
                &relative
            }
            Intersect::Naive => scene,
        };
        let t0 = std::time::Instant::now();
        let bvh = accel.uses_bvh(scene).then(|| accel::sphere_bvh(scene));
        let bvh_s = t0.elapsed().as_secs_f64();
        let order = bvh.as_ref().map(|b| b.order.as_slice());
        let mut up = match precision {
            Precision::F32 => f32_layout::upload(scene, order),
            Precision::F64 => f64_layout::upload(scene, order),
        };
        up.layout_len = bvh.as_ref().map_or(0, |b| b.layout_len);
        up.layouts = bvh.as_ref().map_or(0, |b| b.layouts);
        up.nodes = bvh.map(|b| array(b.nodes));
        up.bvh_s = bvh_s;
        up
    }

    /// Bytes of each scene array: spheres, planes, materials, lights.
    pub fn array_bytes(&self) -> [usize; 4] {
        self.arrays.each_ref().map(|a| a.bytes.len())
    }

    /// Fails, naming the array and the limit, where one array is larger than
    /// a storage buffer of this device can be (lavapipe: 128 MiB, about four
    /// million spheres in f32 and two million in f64).
    pub fn check_storage_range(&self, limit: u32) -> Result<(), String> {
        let names = ["spheres", "planes", "materials", "lights", "BVH nodes"];
        let sizes = self
            .arrays
            .iter()
            .map(|a| a.bytes.len())
            .chain(self.nodes.as_ref().map(|n| n.bytes.len()));
        for (name, bytes) in names.iter().zip(sizes) {
            if bytes as u64 > u64::from(limit) {
                return Err(format!(
                    "the scene's {name} take {bytes} bytes, more than this device's \
                     maxStorageBufferRange of {limit} bytes; render fewer objects, in f32 \
                     rather than f64, or with --backend cpu"
                ));
            }
        }
        Ok(())
    }

    /// Elements of each scene array, as uploaded.
    pub fn array_lengths(&self) -> [usize; 4] {
        self.arrays.each_ref().map(|a| a.len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f64_structs_are_rounded_to_dvec4_alignment() {
        use std::mem::size_of;
        assert_eq!(size_of::<f64_layout::Globals>(), 5 * 32 + 2 * 16);
        assert_eq!(size_of::<f64_layout::Sphere>(), 64);
        assert_eq!(size_of::<f64_layout::Plane>(), 96);
        assert_eq!(size_of::<f64_layout::Material>(), 128);
        assert_eq!(size_of::<f64_layout::Light>(), 256);
        assert_eq!(size_of::<f32_layout::Sphere>(), 32);
        assert_eq!(size_of::<f32_layout::Light>(), 128);
    }

    #[test]
    fn arrays_over_the_storage_range_are_named() {
        let mut text = String::from(
            "[image]\nwidth = 4\nheight = 4\n[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 40\n\
             [materials.m]\n",
        );
        for i in 0..64 {
            text += &format!(
                "[[spheres]]\ncenter = [{}, 0, 0]\nradius = 1\nmaterial = \"m\"\n",
                3 * i
            );
        }
        let scene = crate::scene::parse(
            &text,
            std::path::Path::new("t.toml"),
            &crate::scene::Overrides::default(),
        )
        .unwrap();
        for (precision, sphere_bytes) in [(Precision::F32, 32), (Precision::F64, 64)] {
            let up = Uploads::new(&scene, Intersect::Robust, precision, Accel::Bvh);
            let nodes = up.nodes.as_ref().unwrap().bytes.len();
            let spheres = up.arrays[0].bytes.len();
            assert_eq!(spheres, 64 * sphere_bytes);
            let biggest = up.array_bytes().into_iter().chain([nodes]).max().unwrap();
            assert!(up.check_storage_range(biggest as u32).is_ok());
            let err = up.check_storage_range(spheres as u32 - 1).unwrap_err();
            assert!(
                err.contains(&format!("spheres take {spheres} bytes")),
                "{err}"
            );
            if nodes > spheres {
                let err = up.check_storage_range(nodes as u32 - 1).unwrap_err();
                assert!(err.contains("BVH nodes"), "{err}");
            }
        }
    }
}

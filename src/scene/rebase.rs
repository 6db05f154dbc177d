//! Camera-relative coordinates. Both renderers trace a copy of the scene
//! translated by -eye, computed in f64 before anything is rounded to f32: a
//! scene modelled a thousand kilometres from the origin then reaches the f32
//! arithmetic with the same digits as one modelled at the origin, and the
//! only rounding left from the offset is f64's.

use super::{Light, Scene};

impl Scene {
    /// The scene translated by −eye, in f64: the eye at the origin.
    pub fn camera_relative(&self) -> Scene {
        let origin = self.camera.eye;
        let mut camera = self.camera;
        camera.eye -= origin;
        camera.screen_center -= origin;
        // Built field by field: a clone would hold the primitives a third
        // time while they are moved (a million triangles are 208 MB).
        Scene {
            camera,
            prims: self.prims.relative_to(origin),
            lights: self
                .lights
                .iter()
                .map(|l| Light {
                    position: l.position - origin,
                    ..*l
                })
                .collect(),
            materials: self.materials.clone(),
            textures: self
                .textures
                .iter()
                .map(|t| super::texture::Texture {
                    origin: t.origin - origin,
                    ..*t
                })
                .collect(),
            input_files: self.input_files.clone(),
            texels: self.texels.clone(),
            replay: self.replay.clone(),
            ..*self
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::scene::{parse, Overrides};

    #[test]
    fn rebasing_moves_the_eye_to_the_origin_and_keeps_the_geometry() {
        let text = r#"
[image]
width = 4
height = 3
[camera]
eye = [1000000.5, 2.0, 3.0]
look_at = [1000000.0, 0.0, 0.0]
vfov = 30.0
[materials.m]
[[spheres]]
center = [1000001.0, 0.0, 0.0]
radius = 0.25
material = "m"
[[planes]]
point = [1000007.0, -1.0, 9.0]
normal = [0.0, 1.0, 0.0]
material = "m"
[[lights]]
type = "point"
position = [1000000.0, 5.0, 0.0]
"#;
        let s = parse(text, Path::new("t.toml"), &Overrides::default()).unwrap();
        let r = s.camera_relative();
        assert_eq!(r.camera.eye, glam::DVec3::ZERO);
        assert_eq!(r.prims.spheres[0].center, glam::DVec3::new(0.5, -2.0, -3.0));
        assert_eq!(r.prims.planes[0].point, glam::DVec3::new(0.0, -3.0, 0.0));
        assert_eq!(r.lights[0].position, glam::DVec3::new(-0.5, 3.0, -3.0));
        assert_eq!(r.camera.screen_right, s.camera.screen_right);
    }
}

//! A texture once checked (`Texture`), what a pattern's check gives
//! (`Look`), its struct in the shader's buffers and its form in the CPU
//! reference's arithmetic (`TextureR`).

use glam::DVec3;

use super::PatternId;
use crate::base::real::{Real, Vec3};

/// What of the surface a pattern reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Needs {
    /// Nothing: the point in the scene's coordinates.
    Nothing,
    /// The surface's own coordinates (`crate::prim::Shape::frame`).
    Frame,
    /// uv coordinates (`crate::prim::Shape::uv`).
    Uv,
}

/// Where an image's texels lie in `Scene::texels`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texels {
    /// The index of its top-left texel.
    pub first: u32,
    /// Its texels a row.
    pub width: u32,
    /// Its rows.
    pub height: u32,
    /// Its brightest value in each channel (for the scene's brightness
    /// bound).
    pub peak: DVec3,
}

/// One texture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texture {
    /// Its pattern.
    pub pattern: PatternId,
    /// The side of a square or cube; an image's repeat in uv.
    pub size: f64,
    /// A pattern's colour of the squares whose cell indices sum to an even
    /// number, then to an odd one. An image's: its tint (each texel is
    /// multiplied by the first, as an MTL file's Kd multiplies its
    /// map_Kd; 1 in a scene file), twice.
    pub colors: [DVec3; 2],
    /// The cosine and sine of the angle the squares, or the uv
    /// coordinates, are turned by.
    pub rotation: [f64; 2],
    /// A corner of a solid pattern's cubes, in the coordinates the scene
    /// is traced in (moved with it by `Scene::camera_relative`).
    pub origin: DVec3,
    /// Its pattern's own numbers, laid out by its module; 0 where it has
    /// none (no pattern of the table has any yet).
    pub own: [f64; 4],
    /// An image's texels.
    pub texels: Option<Texels>,
}

/// What a pattern's check gives: everything of a texture but its pattern
/// and texels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// `Texture::size`.
    pub size: f64,
    /// `Texture::colors`.
    pub colors: [DVec3; 2],
    /// `Texture::rotation`.
    pub rotation: [f64; 2],
    /// `Texture::origin`.
    pub origin: DVec3,
    /// `Texture::own`.
    pub own: [f64; 4],
}

impl Default for Look {
    /// Untinted, unturned, at the origin, of size 1.
    fn default() -> Self {
        Look {
            size: 1.0,
            colors: [DVec3::ONE; 2],
            rotation: [1.0, 0.0],
            origin: DVec3::ZERO,
            own: [0.0; 4],
        }
    }
}

impl Texture {
    /// An image's texture, untinted, unturned, repeating at 1.
    pub fn image(texels: Texels) -> Texture {
        Texture {
            pattern: PatternId::Image,
            size: 1.0,
            colors: [DVec3::ONE; 2],
            rotation: [1.0, 0.0],
            origin: DVec3::ZERO,
            own: [0.0; 4],
            texels: Some(texels),
        }
    }

    /// The brightest colour it gives, per channel.
    pub fn brightest(&self) -> DVec3 {
        match self.texels {
            Some(t) => t.peak * self.colors[0],
            None => self.colors[0].max(self.colors[1]),
        }
    }

    /// Its struct in the shader's buffers, in coordinates moved by
    /// `-origin`.
    pub(crate) fn gpu(&self, origin: DVec3) -> gpu::Values {
        let xyz = |v: DVec3| [v.x, v.y, v.z, 0.0];
        let o = self.origin - origin;
        let code = self.pattern.code();
        gpu::Values {
            origin_size: [o.x, o.y, o.z, self.size],
            color0: xyz(self.colors[0]),
            color1: xyz(self.colors[1]),
            rotation: [self.rotation[0], self.rotation[1], 0.0, 0.0],
            own: self.own,
            meta: match self.texels {
                Some(i) => [code, i.first, i.width, i.height],
                None => [code, 0, 0, 0],
            },
        }
    }

    /// The texture in the CPU reference's arithmetic, moved by `-origin`.
    pub fn cpu<R: Real>(&self, origin: DVec3) -> TextureR<R> {
        TextureR {
            pattern: self.pattern,
            size: R::of(self.size),
            colors: self.colors.map(Vec3::of),
            rotation: self.rotation.map(R::of),
            origin: Vec3::of(self.origin - origin),
            own: self.own.map(R::of),
            texels: self.texels,
        }
    }
}

crate::base::interface::gpu_struct!(
    pub(crate) mod gpu: "Texture" {
        /// xyz a corner of a solid pattern's cubes, w the side
        origin_size: real4,
        /// rgb the colour of even cells
        color0: real4,
        /// rgb the colour of odd cells
        color1: real4,
        /// x cos, y sin of the angle
        rotation: real4,
        /// its pattern's own numbers (`Texture::own`)
        own: real4,
        /// x the pattern (PATTERN_*); an image's y first texel, z width,
        /// w height (its colour0 is its tint)
        meta: uvec4,
    }
);

/// A texture in the reference's arithmetic, in camera-relative
/// coordinates.
#[derive(Debug, Clone, Copy)]
pub struct TextureR<R> {
    /// `Texture::pattern`.
    pub pattern: PatternId,
    /// `Texture::size`.
    pub size: R,
    /// `Texture::colors`.
    pub colors: [Vec3<R>; 2],
    /// `Texture::rotation`.
    pub rotation: [R; 2],
    /// `Texture::origin`, moved.
    pub origin: Vec3<R>,
    /// `Texture::own`.
    pub own: [R; 4],
    /// An image's texels in `Scene::texels`.
    pub texels: Option<Texels>,
}

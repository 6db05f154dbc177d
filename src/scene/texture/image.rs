//! An image's texels at the surface's uv coordinates, filtered bilinearly
//! and repeated; mirrors shaders/texture/image.glsl.

use serde::{Deserialize, Serialize};

use super::{Look, Needs, PatternAt, PatternType, TextureFile, TextureR};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::prim::Shape;
use crate::rng::Place;

/// An image file's texels.
pub struct Image;

/// An image's keys besides `image`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageFile {
    /// The uv distance it repeats at (default 1).
    pub size: Option<f64>,
    /// Its uv coordinates turned by this many degrees.
    pub angle: Option<f64>,
}

impl PatternType for Image {
    const NAME: &'static str = "image";
    const WHAT: &'static str = "an image";
    const GLSL: &'static str = include_str!("../../../shaders/texture/image.glsl");
    const INCLUDE: &'static str = "image";
    const FILE: bool = true;
    type File = ImageFile;
    const NEEDS: Needs = Needs::Uv;

    /// Untinted (a scene file's image has no colors of its own).
    fn check(file: ImageFile, at: &PatternAt) -> Result<Look, SceneError> {
        Ok(Look {
            size: at.size(file.size, Some(1.0))?,
            rotation: at.rotation(file.angle)?,
            ..Look::default()
        })
    }

    fn colour<R: Real>(
        t: &TextureR<R>,
        texels: &[[f32; 3]],
        surface: &dyn Shape<R>,
        p: Vec3<R>,
    ) -> Vec3<R> {
        // The scene's checks give an image only to primitives with uvs.
        let [a, b] = surface.uv(p).expect("a surface with uvs");
        let [c, s] = t.rotation;
        filtered(
            texels,
            t,
            [(c * a + s * b) / t.size, (c * b - s * a) / t.size],
        )
    }

    /// A 4×4 PFM of random texels beside the scene.
    fn sample(p: &mut Place) -> TextureFile {
        let name = p.file_name("texture", "pfm");
        let mut bytes = b"PF\n4 4\n-1.0\n".to_vec();
        for _ in 0..4 * 4 * 3 {
            bytes.extend((p.uniform(0.0, 1.0) as f32).to_le_bytes());
        }
        p.files.push((name.clone(), bytes));
        // Repeated at the scene's scale where it is large: a plane's uvs are
        // its own coordinates, and a texel a pixel's fraction wide is noise
        // no f32 renderer can match (`glint fuzz` found one at scale 1000);
        // a sphere's run 0 to 1 whatever its size.
        let own = ImageFile {
            size: Some(p.size.max(1.0) * p.uniform(0.3, 1.0)),
            angle: Some(p.uniform(0.0, 90.0)),
        };
        TextureFile::new(None, Some(name), &own)
    }
}

/// Cell `x` of a row (or column) of `n`, repeated: x mod n, kept inside
/// 0..n-1 where the rounding of a huge x would leave it outside.
fn wrap<R: Real>(x: R, n: u32) -> u32 {
    let nr = R::of(f64::from(n));
    let mut m = x - nr * (x / nr).floor();
    // As the shader: a quotient a driver rounds a few ULP below a whole
    // number leaves m = n.
    if m >= nr {
        m = m - nr;
    }
    if m < R::zero() {
        m += nr;
    }
    m.max(R::zero())
        .min(R::of(f64::from(n - 1)))
        .to_u32()
        .unwrap_or(0)
}

/// `a + (b − a) t`, written as the shader writes it.
fn lerp<R: Real>(a: Vec3<R>, b: Vec3<R>, t: R) -> Vec3<R> {
    a * (R::one() - t) + b * t
}

/// The image's colour at uv, filtered bilinearly between the four nearest
/// texel centres and repeated: v = 0 at its bottom row, 1 at its top, texel
/// centres at half-texel offsets; times the tint.
pub fn filtered<R: Real>(texels: &[[f32; 3]], t: &TextureR<R>, uv: [R; 2]) -> Vec3<R> {
    let image = t.texels.expect("an image texture has texels");
    let (w, h) = (image.width, image.height);
    let half = R::of(0.5);
    let x = uv[0] * R::of(f64::from(w)) - half;
    let y = (R::one() - uv[1]) * R::of(f64::from(h)) - half;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (i0, i1) = (wrap(x0, w), wrap(x0 + R::one(), w));
    let (j0, j1) = (wrap(y0, h), wrap(y0 + R::one(), h));
    let texel = |x: u32, y: u32| Vec3::of_rgb(texels[(image.first + y * w + x) as usize]);
    let top = lerp(texel(i0, j0), texel(i1, j0), fx);
    let bottom = lerp(texel(i0, j1), texel(i1, j1), fx);
    lerp(top, bottom, fy) * t.colors[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::texture::{PatternId, Texels};

    /// A 3 × 2 image: texel (x, y) is (x, y, 10).
    fn image() -> (Vec<[f32; 3]>, TextureR<f64>) {
        let texels = (0..2)
            .flat_map(|y| (0..3).map(move |x| [x as f32, y as f32, 10.0]))
            .collect();
        let t = TextureR {
            pattern: PatternId::Image,
            size: 1.0,
            colors: [Vec3::new(1.0, 1.0, 1.0); 2],
            rotation: [1.0, 0.0],
            origin: Vec3::zero(),
            own: [0.0; 4],
            texels: Some(Texels {
                first: 0,
                width: 3,
                height: 2,
                peak: glam::DVec3::new(2.0, 1.0, 10.0),
            }),
        };
        (texels, t)
    }

    /// uv of texel (x, y)'s centre (rows from the top).
    fn centre(x: f64, y: f64) -> [f64; 2] {
        [(x + 0.5) / 3.0, 1.0 - (y + 0.5) / 2.0]
    }

    fn at(uv: [f64; 2]) -> [f64; 3] {
        let (texels, t) = image();
        let c = filtered(&texels, &t, uv);
        [c.x, c.y, c.z]
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(a, b)| (a - b).abs() < 1e-12)
    }

    #[test]
    fn a_texel_centre_gives_that_texel_and_v_runs_up() {
        for (x, y) in [(0.0, 0.0), (2.0, 0.0), (1.0, 1.0)] {
            assert!(close(at(centre(x, y)), [x, y, 10.0]), "{x} {y}");
        }
        // v = 1 is the top row: a point near the top edge is row 0.
        assert!(at(centre(1.0, 0.0))[1] < at(centre(1.0, 1.0))[1]);
    }

    #[test]
    fn between_centres_the_filter_is_bilinear() {
        let mid = [(centre(0.0, 0.0)[0] + centre(1.0, 0.0)[0]) / 2.0, 0.5];
        assert!(close(at(mid), [0.5, 0.5, 10.0]), "{:?}", at(mid));
        let quarter = [centre(1.0, 0.0)[0] + 0.25 / 3.0, centre(1.0, 0.0)[1]];
        assert!(close(at(quarter), [1.25, 0.0, 10.0]), "{:?}", at(quarter));
    }

    #[test]
    fn the_image_repeats_and_its_edges_wrap() {
        // Half a texel left of u = 0: halfway between the last and first columns.
        let edge = [0.0, centre(0.0, 1.0)[1]];
        assert!(close(at(edge), [1.0, 1.0, 10.0]), "{:?}", at(edge));
        for k in [-3.0, 1.0, 7.0] {
            let c = centre(2.0, 1.0);
            assert!(close(at([c[0] + k, c[1] - k]), [2.0, 1.0, 10.0]), "{k}");
        }
        // Far beyond the repeat the index stays inside the image.
        let far = at([1e9 + 0.3, -1e9]);
        assert!(far.iter().all(|c| c.is_finite()));
    }

    #[test]
    fn the_tint_multiplies_each_texel() {
        let (texels, mut t) = image();
        t.colors[0] = Vec3::new(0.5, 2.0, 0.1);
        let c = filtered(&texels, &t, centre(2.0, 1.0));
        assert!(close([c.x, c.y, c.z], [1.0, 2.0, 1.0]));
    }

    #[test]
    fn wrap_keeps_every_cell_inside() {
        assert_eq!(wrap(-1.0f64, 3), 2);
        assert_eq!(wrap(3.0f64, 3), 0);
        assert_eq!(wrap(-3.0f64, 3), 0);
        // Where x / n rounds, x mod n can fall outside 0..n: clamped.
        for x in [1e30f32, -1e30, -16_777_215.0, 16_777_217.0] {
            assert!(wrap(x, 3) <= 2, "{x}");
        }
    }
}

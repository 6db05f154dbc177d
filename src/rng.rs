//! A small reproducible generator, so that random trials (the conditioning
//! check's, the unit tests') repeat exactly without a dependency.

use glam::DVec3;

/// xorshift64*, seeded by its one word (not zero).
pub(crate) struct Xorshift(pub(crate) u64);

impl Xorshift {
    /// A number in [0, 1).
    pub(crate) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A direction uniform on the sphere.
    pub(crate) fn unit(&mut self) -> DVec3 {
        let z = 2.0 * self.next() - 1.0;
        let phi = std::f64::consts::TAU * self.next();
        let r = (1.0 - z * z).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// Where a generated object goes (`crate::generate`): each primitive kind,
/// light type and texture pattern draws one sample of itself from a
/// `Place`, so that a new entry of a table is generated with no code in
/// the generator.
/// A spot of a generated scene and the draws that shape what goes there.
pub struct Place<'a> {
    /// Where the object is centred.
    pub center: DVec3,
    /// Its extent: a radius, a half-length, a distance to a light.
    pub size: f64,
    /// The name of the material it takes.
    pub material: &'a str,
    /// Files the object needs beside the scene (an image texture's), by
    /// name relative to the scene file.
    pub files: &'a mut Vec<(String, Vec<u8>)>,
    rng: &'a mut Xorshift,
}

impl<'a> Place<'a> {
    pub(crate) fn new(
        center: DVec3,
        size: f64,
        material: &'a str,
        files: &'a mut Vec<(String, Vec<u8>)>,
        rng: &'a mut Xorshift,
    ) -> Self {
        Self {
            center,
            size,
            material,
            files,
            rng,
        }
    }

    /// A number in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.rng.next()
    }

    /// One of `n` choices.
    pub fn pick(&mut self, n: usize) -> usize {
        ((self.rng.next() * n as f64) as usize).min(n.saturating_sub(1))
    }

    /// A name for a file of this object's, drawn as its shape is: the same
    /// spec names the same file, and two scenes written into one folder
    /// (`glint drivers --generated`) do not share one.
    pub fn file_name(&mut self, stem: &str, extension: &str) -> String {
        let token = (self.rng.next() * (1u64 << 52) as f64) as u64;
        format!("{stem}-{token:013x}.{extension}")
    }

    /// A direction uniform on the sphere.
    pub fn unit(&mut self) -> DVec3 {
        self.rng.unit()
    }

    /// A unit vector in the upper half (y > 0.2): a floor's normal, a
    /// light from above.
    pub fn upward(&mut self) -> DVec3 {
        let u = self.rng.unit();
        DVec3::new(u.x, u.y.abs().max(0.2), u.z).normalize()
    }

    /// Two unit vectors perpendicular to `axis` and to each other.
    pub fn frame(axis: DVec3) -> (DVec3, DVec3) {
        let helper = if axis.x.abs() < 0.9 {
            DVec3::X
        } else {
            DVec3::Y
        };
        let u = axis.cross(helper).normalize();
        (u, axis.cross(u))
    }

    /// `p` as a scene file's triple.
    pub fn triple(p: DVec3) -> [f64; 3] {
        p.to_array()
    }
}

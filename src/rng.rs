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

//! FNV-1a, 64 bits.

use std::hash::Hasher;

/// FNV-1a: a stable hash for cache keys and tile sidecars (std's hasher
/// may change between Rust versions, and a tile's hash must not).
pub struct Fnv(u64);

impl Fnv {
    /// A hash that goes on from `state`, an earlier `finish()`.
    pub fn from_state(state: u64) -> Self {
        Fnv(state)
    }
}

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Hasher for Fnv {
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0 ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3);
        }
        // Separates consecutive writes, so that ("ab", "c") and ("a", "bc") differ.
        self.0 = (self.0 ^ 0xff).wrapping_mul(0x0100_0000_01b3);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

//! A hash map keyed by pairs of u32 indices, with a multiply-shift hasher (the default SipHash costs more than the
//! work the caches save).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A map from index pairs to per-pair state.
pub(crate) type PairMap<V> = HashMap<(u32, u32), V, BuildHasherDefault<PairHasher>>;

/// Hashes the few integers of a key by multiply-and-rotate (Fibonacci hashing).
#[derive(Default)]
pub(crate) struct PairHasher(u64);

impl Hasher for PairHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }

    fn write_u32(&mut self, v: u32) {
        self.write_u64(v as u64);
    }

    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(29) ^ v).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

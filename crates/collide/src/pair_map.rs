//! Hash maps keyed by small integer tuples (index pairs, grid cells), with a multiply-shift hasher (the default SipHash costs more than the
//! work the caches save).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A hash map with the fast hasher below.
pub(crate) type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<PairHasher>>;

/// A map from index pairs to per-pair state.
pub(crate) type PairMap<V> = FastMap<(u32, u32), V>;

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

    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }

    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }

    fn write_u32(&mut self, v: u32) {
        self.write_u64(v as u64);
    }

    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(29) ^ v).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

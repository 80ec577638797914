//! Helpers shared by the integration tests.

use tumble::World;

/// Every number of a world's state, its time and its object counts, as bits (for bit-for-bit comparisons).
pub fn state_bits(w: &World) -> Vec<u64> {
    let mut out = vec![w.time().to_bits(), w.particle_count() as u64, w.body_count() as u64];
    for (_, p) in w.particles() {
        out.extend(p.position().iter().chain(p.velocity().iter()).map(|v| v.to_bits()));
    }
    for (_, b) in w.bodies() {
        let q = b.orientation();
        out.extend(
            b.position().iter().chain(b.velocity().iter()).chain(b.angular_velocity().iter()).map(|v| v.to_bits()),
        );
        out.extend([q.w, q.i, q.j, q.k].iter().map(|v| v.to_bits()));
    }
    out
}

/// A seeded linear congruential generator: the same numbers on every machine, for random scenes.
#[allow(dead_code)] // not every test file draws random scenes
pub struct Lcg(pub u64);

#[allow(dead_code)]
impl Lcg {
    /// The next number in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next number in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

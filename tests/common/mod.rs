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

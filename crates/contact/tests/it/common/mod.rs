//! What the contact tests share: a reproducible source of random numbers for their random scenes.

/// Uniform numbers in [0, 1) from a 64-bit linear congruential generator (Knuth's MMIX constants) seeded with
/// `seed`: the same scenes on every run and machine.
#[cfg_attr(not(feature = "clarabel"), allow(dead_code))]
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

//! The graph colours an island's manifolds are swept by: a greedy colouring in contact order, each manifold taking the
//! first colour that none of its moving bodies has yet. Manifolds of one colour share no moving body, so they can be
//! solved side by side, in vector lanes and on threads, with the bits of one after another. The colours depend on
//! the contacts alone, never on threads or timing.

use super::row::Mover;

/// Colours tracked per body; rows that find all of them taken go last, in contact order, with this colour (which,
/// unlike the others, may join rows that share a body).
pub(crate) const COLOURS: u32 = 64;

/// The colour of each of the rows joining the movers `pairs` (in contact order), to sweep them colour by colour.
pub(crate) fn colours(pairs: &[(usize, usize)], movers: &[Mover]) -> Vec<u32> {
    let mut taken = vec![0u64; movers.len()];
    let moving = |m: usize| movers[m].moves();
    pairs
        .iter()
        .map(|&(a, b)| {
            let used = (if moving(a) { taken[a] } else { 0 }) | (if moving(b) { taken[b] } else { 0 });
            let colour = (!used).trailing_zeros();
            if colour < COLOURS {
                for m in [a, b] {
                    if moving(m) {
                        taken[m] |= 1 << colour;
                    }
                }
            }
            colour.min(COLOURS)
        })
        .collect()
}

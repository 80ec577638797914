//! The order in which an island's rows are swept: a greedy colouring in contact order, each row taking the first
//! colour that none of its moving bodies has yet, then the rows colour by colour (contact order within a colour).
//! Rows of one colour share no moving body, so consecutive solves do not wait on each other's writes (the four
//! points of a box on a box would otherwise chain every solve to the last). The order depends on the contacts
//! alone, never on threads or timing.

use super::row::Mover;

/// Colours tracked per body; rows that find all of them taken go last, in contact order, with this colour (which,
/// unlike the others, may join rows that share a body).
pub(crate) const COLOURS: u32 = 64;

/// The order to sweep rows joining the movers `pairs` (in contact order) in: colour by colour, contact order within
/// a colour; each row as (its colour, its place in `pairs`).
pub(crate) fn colour_order(pairs: &[(usize, usize)], movers: &[Mover]) -> Vec<(u32, usize)> {
    let mut taken = vec![0u64; movers.len()];
    let moving = |m: usize| movers[m].moves();
    let colours: Vec<u32> = pairs
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
        .collect();
    let mut order: Vec<(u32, usize)> = colours.into_iter().zip(0..).collect();
    order.sort_unstable();
    order
}

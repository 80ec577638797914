//! The order in which an island's rows are swept: a greedy colouring in contact order, each row taking the first
//! colour that none of its moving bodies has yet, then the rows colour by colour (contact order within a colour).
//! Rows of one colour share no moving body, so consecutive solves do not wait on each other's writes (the four
//! points of a box on a box would otherwise chain every solve to the last). The order depends on the contacts
//! alone, never on threads or timing.

use super::row::{Mover, Row};

/// Colours tracked per body; rows that find all of them taken go last, in contact order.
const COLOURS: u32 = 64;

/// `rows` (in contact order) reordered colour by colour.
pub(crate) fn in_colour_order(rows: Vec<Row>, movers: &[Mover]) -> Vec<Row> {
    let mut taken = vec![0u64; movers.len()];
    let moving = |m: usize| movers[m].inv_mass > 0.0 || !movers[m].still_inertia();
    let colours: Vec<u32> = rows
        .iter()
        .map(|r| {
            let used = (if moving(r.a) { taken[r.a] } else { 0 }) | (if moving(r.b) { taken[r.b] } else { 0 });
            let colour = (!used).trailing_zeros();
            if colour < COLOURS {
                for m in [r.a, r.b] {
                    if moving(m) {
                        taken[m] |= 1 << colour;
                    }
                }
            }
            colour.min(COLOURS)
        })
        .collect();
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by_key(|&k| (colours[k], k));
    let mut slots: Vec<Option<Row>> = rows.into_iter().map(Some).collect();
    order.into_iter().map(|k| slots[k].take().expect("each row once")).collect()
}

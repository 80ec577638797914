//! Fast mode's warm start of lagged friction: each contact's friction is bounded by mu times a normal impulse
//! from the last step. A contact seen last step starts from its own impulse; a contact new to a pair that touched
//! last step, from the pair's last total shared among its contacts now; a contact of a pair that has just met has
//! none (its island gets a first pass). Sums run in key order, so the answer never depends on hashing.

use crate::engine::found_contact::{ContactKey, FoundContact};
use std::collections::BTreeMap;

/// Each contact's known impulse from the last step, if any.
pub(super) fn known_impulses(previous: &BTreeMap<ContactKey, f64>, found: &[FoundContact]) -> Vec<Option<f64>> {
    let mut last_pair: BTreeMap<(u32, u32), f64> = BTreeMap::new();
    for (key, p) in previous {
        *last_pair.entry(key.colliders).or_default() += p;
    }
    let mut now_pair: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for f in found {
        *now_pair.entry(f.key.colliders).or_default() += 1;
    }
    found
        .iter()
        .map(|f| {
            let pair = f.key.colliders;
            previous.get(&f.key).copied().or_else(|| last_pair.get(&pair).map(|p| p / now_pair[&pair] as f64))
        })
        .collect()
}

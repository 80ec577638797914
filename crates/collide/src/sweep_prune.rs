//! The chapter's sort-and-sweep broad phase: box intervals sorted along one axis (chosen from the spread of the box
//! centres) and swept, each candidate confirmed on the other two axes; between calls the sorted order is repaired by
//! insertion sort, which costs little when the boxes have moved little (temporal coherence).

use crate::aabb::Aabb;
use crate::error::ShapeError;

/// One box in sweep order: its bounds on the three axes and its index in the caller's slice.
#[derive(Clone, Copy, Debug)]
struct Entry {
    lo: [f64; 3],
    hi: [f64; 3],
    id: u32,
}

impl Entry {
    fn of(b: &Aabb, id: u32) -> Entry {
        Entry { lo: [b.min.x, b.min.y, b.min.z], hi: [b.max.x, b.max.y, b.max.z], id }
    }
}

/// Counters of the last `update`, to see temporal coherence at work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SweepStats {
    /// Neighbour swaps made by insertion sort (0 when nothing changed order).
    pub swaps: usize,
    /// Whether the order was rebuilt from scratch (first call, a new box count, a new axis, or too much disorder).
    pub full_sort: bool,
    /// Pairs that overlapped on the sweep axis and were tested on the other two.
    pub candidates: usize,
}

/// A persistent sort-and-sweep broad phase over a slice of boxes that keeps its indices from call to call.
#[derive(Clone, Debug, Default)]
pub struct SortAndSweep {
    axis: usize,
    entries: Vec<Entry>,
    pairs: Vec<(u32, u32)>,
    stats: SweepStats,
}

impl SortAndSweep {
    /// An empty broad phase.
    pub fn new() -> Self {
        Self::default()
    }

    /// Finds every pair of overlapping boxes (closed boxes: touching counts) and returns them as `(i, j)` with
    /// `i < j`, indices into `boxes`, in no particular order. Box `i` must be the same object from call to call for
    /// the sorted order to carry over; a different count starts afresh. A NaN or reversed box is an error, and the
    /// broad phase is left as it was.
    pub fn update(&mut self, boxes: &[Aabb]) -> Result<&[(u32, u32)], ShapeError> {
        if boxes.len() > u32::MAX as usize {
            return Err(ShapeError::new("boxes", "more than 2^32 boxes"));
        }
        for (i, b) in boxes.iter().enumerate() {
            b.check("boxes").map_err(|e| ShapeError::new("boxes", format!("box {i}: {}", e.reason)))?;
        }
        let mut full_sort = false;
        if self.entries.len() != boxes.len() {
            self.entries = boxes.iter().enumerate().map(|(i, b)| Entry::of(b, i as u32)).collect();
            full_sort = true;
        } else {
            for e in &mut self.entries {
                *e = Entry::of(&boxes[e.id as usize], e.id);
            }
        }
        let axis = choose_axis(boxes, self.axis);
        if axis != self.axis {
            self.axis = axis;
            full_sort = true;
        }
        let swaps = if full_sort { None } else { insertion_sort(&mut self.entries, axis, 16 * boxes.len() + 1024) };
        if swaps.is_none() {
            self.entries.sort_unstable_by(|a, b| a.lo[axis].total_cmp(&b.lo[axis]));
        }
        let candidates = sweep(&self.entries, axis, &mut self.pairs);
        self.stats = SweepStats { swaps: swaps.unwrap_or(0), full_sort: swaps.is_none(), candidates };
        Ok(&self.pairs)
    }

    /// The pairs of the last `update`.
    pub fn pairs(&self) -> &[(u32, u32)] {
        &self.pairs
    }

    /// The sweep axis of the last `update` (0 = x, 1 = y, 2 = z).
    pub fn axis(&self) -> usize {
        self.axis
    }

    /// Counters of the last `update`.
    pub fn stats(&self) -> SweepStats {
        self.stats
    }
}

/// The axis along which the finite box centres spread most (largest variance). The current axis is kept unless
/// another spreads at least 20% more, so that the order is not thrown away for a marginal gain.
fn choose_axis(boxes: &[Aabb], current: usize) -> usize {
    let mut n = 0.0;
    let mut sum = [0.0; 3];
    let mut sq = [0.0; 3];
    for b in boxes.iter().filter(|b| b.is_finite()) {
        n += 1.0;
        for k in 0..3 {
            let c = 0.5 * (b.min[k] + b.max[k]);
            sum[k] += c;
            sq[k] += c * c;
        }
    }
    if n < 2.0 {
        return current;
    }
    let var = |k: usize| sq[k] / n - (sum[k] / n).powi(2);
    let best = (0..3).max_by(|&a, &b| var(a).total_cmp(&var(b))).unwrap_or(current);
    if var(best) > 1.2 * var(current) {
        best
    } else {
        current
    }
}

/// Insertion sort by the lower bound on `axis`; `None` (order partly repaired) once more than `budget` swaps were
/// needed, when a full sort is cheaper.
fn insertion_sort(entries: &mut [Entry], axis: usize, budget: usize) -> Option<usize> {
    let mut swaps = 0;
    for i in 1..entries.len() {
        let e = entries[i];
        let key = e.lo[axis];
        let mut j = i;
        while j > 0 && entries[j - 1].lo[axis] > key {
            entries[j] = entries[j - 1];
            j -= 1;
        }
        entries[j] = e;
        swaps += i - j;
        if swaps > budget {
            return None;
        }
    }
    Some(swaps)
}

/// The sweep: each box against the boxes that start before it ends, confirmed on the other two axes.
fn sweep(entries: &[Entry], axis: usize, pairs: &mut Vec<(u32, u32)>) -> usize {
    let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
    pairs.clear();
    let mut candidates = 0;
    for (i, e) in entries.iter().enumerate() {
        let end = e.hi[axis];
        for f in &entries[i + 1..] {
            if f.lo[axis] > end {
                break;
            }
            candidates += 1;
            if e.lo[a1] <= f.hi[a1] && f.lo[a1] <= e.hi[a1] && e.lo[a2] <= f.hi[a2] && f.lo[a2] <= e.hi[a2] {
                pairs.push(if e.id < f.id { (e.id, f.id) } else { (f.id, e.id) });
            }
        }
    }
    candidates
}

/// Every overlapping pair by testing all n (n - 1) / 2 of them: the reference the sweep must match.
pub fn brute_force_pairs(boxes: &[Aabb]) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            if boxes[i].overlaps(&boxes[j]) {
                pairs.push((i as u32, j as u32));
            }
        }
    }
    pairs
}

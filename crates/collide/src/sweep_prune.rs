//! The chapter's sort-and-sweep broad phase. Box intervals are sorted along one axis (the one along which the box
//! centres spread most) and swept, each candidate confirmed on the other two axes. One sorted list over a whole 3D
//! scene checks every box against the whole slab of boxes that shares its interval, which grows like n^(5/3); so the
//! plane of the other two axes is cut into square columns a few boxes wide, each box is entered in the columns it
//! touches, and each column keeps its own sorted list (multi-box pruning). Between calls each list is repaired by
//! insertion sort, which costs little when the boxes have moved little (temporal coherence). A pair that shares
//! several columns is reported only by the column that holds the low corner of its overlap.

use crate::aabb::Aabb;
use crate::error::ShapeError;
use crate::pair_map::FastMap;

/// One box in a column's sweep order: its bounds and its index in the caller's slice. The axes are stored in sweep
/// order: index 0 is the sweep axis, 1 and 2 the cross axes of the columns.
#[derive(Clone, Copy, Debug)]
struct Entry {
    lo: [f64; 3],
    hi: [f64; 3],
    id: u32,
}

impl Entry {
    #[inline]
    fn of(b: &Aabb, id: u32, axis: usize) -> Entry {
        let (s, u, v) = (axis, (axis + 1) % 3, (axis + 2) % 3);
        Entry { lo: [b.min[s], b.min[u], b.min[v]], hi: [b.max[s], b.max[u], b.max[v]], id }
    }

    fn overlaps(&self, f: &Entry) -> bool {
        (0..3).all(|k| self.lo[k] <= f.hi[k] && f.lo[k] <= self.hi[k])
    }
}

/// A column of the grid over the two cross axes and its boxes in sweep order.
#[derive(Clone, Debug)]
struct Column {
    key: [i64; 2],
    entries: Vec<Entry>,
}

/// The columns a box touches, `[u0, u1, v0, v1]`, or `None` for a box too big for columns (unbounded, or more than
/// `MAX_SPAN` columns wide), which is tested against every box instead.
type Span = Option<[i64; 4]>;

const MAX_SPAN: i64 = 8;

/// Counters of the last `update`, to see temporal coherence at work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SweepStats {
    /// Neighbour swaps made by insertion sort (0 when nothing changed order).
    pub swaps: usize,
    /// Whether the lists were rebuilt from scratch (first call, a new box count, a new axis or column width).
    pub full_sort: bool,
    /// Pairs that overlapped on the sweep axis and were tested on the other two.
    pub candidates: usize,
    /// Columns holding boxes.
    pub columns: usize,
}

/// A persistent sort-and-sweep broad phase over a slice of boxes that keeps its indices from call to call.
#[derive(Clone, Debug, Default)]
pub struct SortAndSweep {
    axis: usize,
    width: f64,
    spans: Vec<Span>,
    columns: Vec<Column>,
    column_of: FastMap<[i64; 2], usize>,
    big: Vec<u32>,
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
        let (axis, width) = layout(boxes, self.axis, self.width);
        let rebuild = boxes.len() != self.spans.len() || axis != self.axis || width != self.width;
        (self.axis, self.width) = (axis, width);
        let mut swaps = 0;
        if rebuild {
            self.rebuild(boxes);
        } else {
            self.follow(boxes);
            for c in &mut self.columns {
                for e in c.entries.iter_mut() {
                    *e = Entry::of(&boxes[e.id as usize], e.id, axis);
                }
                swaps += insertion_sort(&mut c.entries);
            }
        }
        self.pairs.clear();
        let mut candidates = 0;
        for c in &self.columns {
            let owns =
                |e: &Entry, f: &Entry| [cell(e.lo[1].max(f.lo[1]), width), cell(e.lo[2].max(f.lo[2]), width)] == c.key;
            candidates += sweep(&c.entries, owns, &mut self.pairs);
        }
        candidates += self.big_pairs(boxes);
        let columns = self.columns.iter().filter(|c| !c.entries.is_empty()).count();
        self.stats = SweepStats { swaps, full_sort: rebuild, candidates, columns };
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

    fn span(&self, b: &Aabb) -> Span {
        let (u, v) = ((self.axis + 1) % 3, (self.axis + 2) % 3);
        if ![b.min[u], b.max[u], b.min[v], b.max[v]].iter().all(|x| x.is_finite()) {
            return None;
        }
        let w = self.width;
        let s = [cell(b.min[u], w), cell(b.max[u], w), cell(b.min[v], w), cell(b.max[v], w)];
        (s[1] - s[0] < MAX_SPAN && s[3] - s[2] < MAX_SPAN).then_some(s)
    }

    fn column(&mut self, key: [i64; 2]) -> &mut Column {
        let n = self.columns.len();
        let index = *self.column_of.entry(key).or_insert(n);
        if index == n {
            self.columns.push(Column { key, entries: Vec::new() });
        }
        &mut self.columns[index]
    }

    fn enter(&mut self, id: u32, span: Span, b: &Aabb) {
        match span {
            None => self.big.push(id),
            Some([u0, u1, v0, v1]) => {
                let entry = Entry::of(b, id, self.axis);
                for cu in u0..=u1 {
                    for cv in v0..=v1 {
                        self.column([cu, cv]).entries.push(entry);
                    }
                }
            }
        }
    }

    fn leave(&mut self, id: u32, span: Span) {
        match span {
            None => self.big.retain(|&k| k != id),
            Some([u0, u1, v0, v1]) => {
                for cu in u0..=u1 {
                    for cv in v0..=v1 {
                        self.column([cu, cv]).entries.retain(|e| e.id != id);
                    }
                }
            }
        }
    }

    /// Enters every box afresh and sorts every column.
    fn rebuild(&mut self, boxes: &[Aabb]) {
        self.columns.clear();
        self.column_of.clear();
        self.big.clear();
        self.spans = boxes.iter().map(|b| self.span(b)).collect();
        for (i, b) in boxes.iter().enumerate() {
            self.enter(i as u32, self.spans[i], b);
        }
        for c in &mut self.columns {
            c.entries.sort_unstable_by(|a, b| a.lo[0].total_cmp(&b.lo[0]));
        }
    }

    /// Moves the boxes whose columns changed; their new entries go to the ends of their lists for insertion sort.
    fn follow(&mut self, boxes: &[Aabb]) {
        for (i, b) in boxes.iter().enumerate() {
            let span = self.span(b);
            if span != self.spans[i] {
                self.leave(i as u32, self.spans[i]);
                self.enter(i as u32, span, b);
                self.spans[i] = span;
            }
        }
    }

    /// Pairs of a big box with any other box (each pair once).
    fn big_pairs(&mut self, boxes: &[Aabb]) -> usize {
        for (k, &g) in self.big.iter().enumerate() {
            let eg = Entry::of(&boxes[g as usize], g, self.axis);
            for (i, b) in boxes.iter().enumerate() {
                let i = i as u32;
                // a big box meets each other big box once, from the earlier of the two in `big`
                if i == g || (self.spans[i as usize].is_none() && self.big[..k].contains(&i)) {
                    continue;
                }
                if eg.overlaps(&Entry::of(b, i, self.axis)) {
                    self.pairs.push((g.min(i), g.max(i)));
                }
            }
        }
        self.big.len() * boxes.len()
    }
}

/// The column index of coordinate `x` for columns `width` wide.
#[inline]
fn cell(x: f64, width: f64) -> i64 {
    (x / width).floor().clamp(-1e15, 1e15) as i64
}

/// The sweep axis and the column width. The axis is the one along which the finite box centres spread most (largest
/// variance); the current one is kept unless another spreads 20% more. The width is four times the mean box extent
/// across the sweep axis (so a box touches one to four columns and a column holds a few boxes across), kept unless
/// that changes by more than a factor of two.
fn layout(boxes: &[Aabb], axis: usize, width: f64) -> (usize, f64) {
    let mut n = 0.0;
    let (mut sum, mut sq, mut ext) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    for b in boxes.iter().filter(|b| b.is_finite()) {
        n += 1.0;
        for k in 0..3 {
            let c = 0.5 * (b.min[k] + b.max[k]);
            sum[k] += c;
            sq[k] += c * c;
            ext[k] += b.max[k] - b.min[k];
        }
    }
    if n < 1.0 {
        return (axis, if width > 0.0 { width } else { 1.0 });
    }
    let var = |k: usize| sq[k] / n - (sum[k] / n).powi(2);
    let best = (0..3).max_by(|&a, &b| var(a).total_cmp(&var(b))).unwrap_or(axis);
    let axis = if var(best) > 1.2 * var(axis) { best } else { axis };
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    // Point-like boxes: columns sized to the spread instead, about sqrt(n) of them across each way.
    let spread = (var(u).max(0.0).sqrt() + var(v).max(0.0).sqrt()) / n.sqrt();
    let mut wanted = 2.0 * (ext[u] + ext[v]) / n;
    if wanted <= 0.0 {
        wanted = spread;
    }
    if !(wanted.is_finite() && wanted > 0.0) {
        wanted = 1.0;
    }
    let width = if width > 0.0 && wanted < 2.0 * width && wanted > 0.5 * width { width } else { wanted };
    (axis, width)
}

/// Insertion sort by the lower bound on the sweep axis; returns the number of neighbour swaps.
fn insertion_sort(entries: &mut [Entry]) -> usize {
    let mut swaps = 0;
    for i in 1..entries.len() {
        let e = entries[i];
        let key = e.lo[0];
        let mut j = i;
        while j > 0 && entries[j - 1].lo[0] > key {
            entries[j] = entries[j - 1];
            j -= 1;
        }
        entries[j] = e;
        swaps += i - j;
    }
    swaps
}

/// The sweep of one column: each box against the boxes that start before it ends, confirmed on the other two axes
/// and kept when `owns` says this column reports the pair.
fn sweep(entries: &[Entry], owns: impl Fn(&Entry, &Entry) -> bool, pairs: &mut Vec<(u32, u32)>) -> usize {
    let mut candidates = 0;
    for (i, e) in entries.iter().enumerate() {
        let end = e.hi[0];
        for f in &entries[i + 1..] {
            if f.lo[0] > end {
                break;
            }
            candidates += 1;
            if e.lo[1] <= f.hi[1] && f.lo[1] <= e.hi[1] && e.lo[2] <= f.hi[2] && f.lo[2] <= e.hi[2] && owns(e, f) {
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

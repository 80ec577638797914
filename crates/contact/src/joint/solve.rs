//! The row kernel, shared by accurate mode's joint forces and projections and by the soft step's direct joint
//! solve: K = J M^-1 J^T of a set of rows (`delassus`), its factorization (`factor`), and the bounded active-set
//! solve of K x = want with bounds on each row's accumulated value (`BoundedSolve`). A row's speed is
//! `JointRow::speed`.
//!
//! The active set: every row starts active; the active rows are solved together (Cholesky of K's active part,
//! faer's blocked dense factorization on one thread, slightly regularised if a redundant joint makes it singular); a
//! row whose accumulated value leaves its bounds is held at the bound and the rest are solved again, with the held
//! rows' parts moved to the right-hand side, for at most `rounds` rounds. K is positive semidefinite, so every
//! principal part factors once regularised.

use faer::linalg::solvers::{Llt, Solve};
use faer::Side;
use nalgebra::{DMatrix, Vector3};

/// One side of a row as K sees it: the body it acts on (`None`: a fixed one), that body's inverse mass, the row's
/// linear part on it (signed: -lin on A, +lin on B) and two angular vectors whose dot products between rows give
/// the angular part of K: the row's angular part and the same weighted by the body's world inverse inertia, in
/// either order (`(ang, I^-1 ang)` or `(I^-1 ang, ang)`: the same K, to the rounding).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowPart {
    pub body: Option<usize>,
    pub inv_mass: f64,
    pub lin: Vector3<f64>,
    pub ang: Vector3<f64>,
    pub weighted: Vector3<f64>,
}

/// K = J M^-1 J^T of rows given by their two parts: K_rc sums, over the parts of r and c on one moving body,
/// inv_mass lin_r . lin_c + ang_r . weighted_c (upper triangle computed, the lower mirrored). Only pairs of rows that
/// share a body are visited (each body's parts listed once), in the order of r's parts, then c's.
pub fn delassus(rows: &[[RowPart; 2]]) -> DMatrix<f64> {
    let n = rows.len();
    // each moving body's parts: (row, part), by row then part
    let mut on: Vec<(usize, usize, usize)> = rows
        .iter()
        .enumerate()
        .flat_map(|(r, parts)| parts.iter().enumerate().filter_map(move |(i, p)| p.body.map(|b| (b, r, i))))
        .collect();
    on.sort_unstable();
    let mut k = DMatrix::zeros(n, n);
    for (r, parts) in rows.iter().enumerate() {
        for p in parts {
            let Some(body) = p.body else { continue };
            let from = on.partition_point(|&(b, c, _)| (b, c) < (body, r));
            for &(_, c, i) in on[from..].iter().take_while(|&&(b, _, _)| b == body) {
                let q = &rows[c][i];
                k[(r, c)] += p.inv_mass * p.lin.dot(&q.lin) + p.ang.dot(&q.weighted);
            }
        }
    }
    for r in 0..n {
        for c in r + 1..n {
            k[(c, r)] = k[(r, c)];
        }
    }
    k
}

/// A pivot of K's Cholesky factor (squared) below this share of K's largest diagonal entry means K is singular to
/// rounding: the rows are redundant (joints that close a loop, as a glued object's welds do).
const REDUNDANT: f64 = 1e-9;
/// The regularisation of a singular K, as a share of its largest diagonal entry: the impulses come out those of
/// least size that do the work, to that share (redundant rows otherwise carry impulses of any size that cancel,
/// rounding's share of the right-hand side over the smallest pivot: the welds of a glued wall in free fall carried
/// their bricks' weight and broke).
const REGULARISE: f64 = 1e-8;

/// The Cholesky factor L L^T of a principal part of K.
#[derive(Clone, Debug)]
pub struct Factor(Llt<f64>);

impl Factor {
    /// x with L L^T x = rhs.
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let x = self.0.solve(faer::Col::<f64>::from_fn(rhs.len(), |i| rhs[i]));
        (0..rhs.len()).map(|i| x[i]).collect()
    }
}

/// The Cholesky factor of K's rows and columns `at`, regularised by `REGULARISE` of its largest diagonal entry if it
/// is singular (redundant joints); `None` if `at` is empty or it does not factor even so.
pub fn factor(k: &DMatrix<f64>, at: &[usize]) -> Option<Factor> {
    if at.is_empty() {
        return None;
    }
    let n = at.len();
    let mut sub = faer::Mat::<f64>::from_fn(n, n, |i, j| k[(at[i], at[j])]);
    let scale = (0..n).map(|i| sub[(i, i)].abs()).fold(0.0, f64::max).max(1e-300);
    let plain = Llt::new(sub.as_ref(), Side::Lower).ok().filter(|c| {
        let l = c.L();
        (0..n).all(|i| l[(i, i)] * l[(i, i)] > REDUNDANT * scale)
    });
    plain
        .or_else(|| {
            for i in 0..n {
                sub[(i, i)] += REGULARISE * scale;
            }
            Llt::new(sub.as_ref(), Side::Lower).ok()
        })
        .map(Factor)
}

/// A bounded solve of K x = want: each row's accumulated value `base + x` kept within its bounds (`(-inf, inf)`:
/// unbounded), by the active set described at the top of this file.
pub struct BoundedSolve<'a> {
    pub k: &'a DMatrix<f64>,
    pub want: &'a [f64],
    pub bounds: &'a [(f64, f64)],
    /// What each row has accumulated already (the bounds hold for it plus x); zeros when x is the whole value.
    pub base: &'a [f64],
    /// Rounds of the active set.
    pub rounds: usize,
}

impl BoundedSolve<'_> {
    /// The solution, starting from the rows `active` (the others stay at zero); `cached` is a factorization of K's
    /// rows `cached.0`, used when the active rows are those and none is held. Rows whose part of K does not factor
    /// are left at zero.
    pub fn solve(&self, mut active: Vec<usize>, cached: Option<(&[usize], &Factor)>) -> Vec<f64> {
        let n = self.want.len();
        let mut x = vec![0.0; n];
        let mut held: Vec<usize> = Vec::new();
        for round in 0..self.rounds {
            let owned;
            let factor = match cached {
                Some((rows, f)) if held.is_empty() && rows == &active[..] => f,
                _ => match factor(self.k, &active) {
                    Some(f) => {
                        owned = f;
                        &owned
                    }
                    None => break,
                },
            };
            let rhs: Vec<f64> = active
                .iter()
                .map(|&r| self.want[r] - held.iter().map(|&h| self.k[(r, h)] * x[h]).sum::<f64>())
                .collect();
            let solved = factor.solve(&rhs);
            for (&r, &v) in active.iter().zip(solved.iter()) {
                x[r] = v;
            }
            let mut broke = Vec::new();
            for &r in &active {
                let (lo, hi) = self.bounds[r];
                let total = self.base[r] + x[r];
                if total < lo || total > hi {
                    x[r] = total.clamp(lo, hi) - self.base[r];
                    broke.push(r);
                }
            }
            if broke.is_empty() || round + 1 == self.rounds {
                break;
            }
            active.retain(|r| !broke.contains(r));
            held.extend(broke);
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(body: usize, lin: [f64; 3], ang: [f64; 3]) -> RowPart {
        let ang = Vector3::from(ang);
        RowPart { body: Some(body), inv_mass: 0.5, lin: Vector3::from(lin), ang, weighted: ang * 2.0 }
    }

    #[test]
    fn delassus_sums_the_parts_on_shared_moving_bodies() {
        let fixed = RowPart { body: None, ..part(9, [1.0, 0.0, 0.0], [0.0; 3]) };
        // row 0 pushes body 0 along x; row 1 pushes bodies 0 (along x, turning about z) and 1 (along y)
        let rows = [
            [fixed, part(0, [1.0, 0.0, 0.0], [0.0; 3])],
            [part(0, [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]), part(1, [0.0, 1.0, 0.0], [0.0; 3])],
        ];
        let k = delassus(&rows);
        // K_00 = 0.5; K_01 = 0.5 (x . x on body 0); K_11 = 0.5 + 1 * 2 (body 0's turn) + 0.5 (body 1)
        assert_eq!(k, DMatrix::from_row_slice(2, 2, &[0.5, 0.5, 0.5, 3.0]));
    }

    #[test]
    fn a_row_that_breaks_its_bound_is_held_there_and_the_rest_solved_again() {
        // K = [[2, 1], [1, 2]], want (3, -3): unbounded x = (3, -3); row 1 may not go below -1 (its base is 1, so
        // the accumulated value 1 + x_1 >= 0): held at x_1 = -1, row 0 then solves 2 x_0 = 3 + 1
        let k = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let bounds = [(f64::NEG_INFINITY, f64::INFINITY), (0.0, f64::INFINITY)];
        let solve = BoundedSolve { k: &k, want: &[3.0, -3.0], bounds: &bounds, base: &[0.0, 1.0], rounds: 4 };
        // (to a few ulps: the factor takes a square root)
        let x = solve.solve(vec![0, 1], None);
        assert!((x[0] - 2.0).abs() < 1e-15 && x[1] == -1.0, "{x:?}");
        let free = BoundedSolve { bounds: &[(f64::NEG_INFINITY, f64::INFINITY); 2], ..solve };
        let x = free.solve(vec![0, 1], None);
        assert!((x[0] - 3.0).abs() < 1e-15 && (x[1] + 3.0).abs() < 1e-15, "{x:?}");
    }

    #[test]
    fn a_redundant_row_is_solved_regularised() {
        // two copies of one row: K singular; the regularised solve shares the wanted value between them
        let k = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        let bounds = [(f64::NEG_INFINITY, f64::INFINITY); 2];
        let x = BoundedSolve { k: &k, want: &[1.0, 1.0], bounds: &bounds, base: &[0.0; 2], rounds: 1 }
            .solve(vec![0, 1], None);
        // to the regularisation's share, x0 + x1 = 2 / (2 + 1e-8), and alike to rounding times the regularised
        // system's condition (2e8): 1e-7
        assert!((x[0] + x[1] - 1.0).abs() < 1e-8 && (x[0] - x[1]).abs() < 1e-7, "{x:?}");
    }

    #[test]
    fn redundant_rows_asked_for_a_rounding_s_worth_of_the_impossible_carry_no_phantom_load() {
        // two copies of one row asked for values 1e-12 apart (rounding, as a loop of welds asks): no impulses make
        // both, and the regularised solve's difference between the rows stays that over the regularisation
        // (1e-12 / 1e-8), where the regularisation of 1e-12 it replaced made the rows differ by 1
        let k = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        let bounds = [(f64::NEG_INFINITY, f64::INFINITY); 2];
        let x = BoundedSolve { k: &k, want: &[1.0, 1.0 + 1e-12], bounds: &bounds, base: &[0.0; 2], rounds: 1 }
            .solve(vec![0, 1], None);
        assert!((x[0] + x[1] - 1.0).abs() < 1e-8 && (x[0] - x[1]).abs() < 1e-3, "{x:?}");
    }
}

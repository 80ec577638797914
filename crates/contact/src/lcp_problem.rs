//! A linear complementarity problem's data, free of any solver: its matrix by upper-triangle triplets, and the
//! residual by which an answer is judged.

/// A symmetric matrix by its upper-triangle entries (i <= j; repeats add up).
#[derive(Clone, Debug, Default)]
pub(crate) struct Triplets {
    pub n: usize,
    pub rows: Vec<usize>,
    pub cols: Vec<usize>,
    pub vals: Vec<f64>,
}

impl Triplets {
    pub fn new(n: usize) -> Self {
        Triplets { n, ..Default::default() }
    }

    /// Adds v at (i, j) of the symmetric matrix (stored at the upper of (i, j), (j, i)).
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        self.rows.push(i.min(j));
        self.cols.push(i.max(j));
        self.vals.push(v);
    }

    /// y = A x.
    pub fn mul(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for ((&i, &j), &v) in self.rows.iter().zip(&self.cols).zip(&self.vals) {
            y[i] += v * x[j];
            if i != j {
                y[j] += v * x[i];
            }
        }
        y
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.n];
        for ((&i, &j), &v) in self.rows.iter().zip(&self.cols).zip(&self.vals) {
            if i == j {
                d[i] += v;
            }
        }
        d
    }
}

/// The relative complementarity residual of (f, w = A f + q): the largest of -f_i / F, -w_i / W and |f_i w_i| / (F W),
/// with W the largest of |q| and |A f|, and F the largest of the forces and of |q_i| / A_ii (the force that would
/// cancel q_i alone), so that an all-zero answer is measured on the problem's own scale.
pub(crate) fn residual(f: &[f64], w: &[f64], q: &[f64], diagonal: &[f64]) -> f64 {
    let big = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let natural = q.iter().zip(diagonal).filter(|(_, &d)| d > 0.0).fold(0.0f64, |m, (qi, d)| m.max(qi.abs() / d));
    let fs = big(f).max(natural).max(f64::MIN_POSITIVE);
    let ws = big(q).max(big(w)).max(f64::MIN_POSITIVE);
    f.iter().zip(w).map(|(&fi, &wi)| (-fi / fs).max(-wi / ws).max((fi * wi).abs() / (fs * ws))).fold(0.0, f64::max)
}

//! Polishing an LCP answer: after the interior point, the contacts it left pushing are solved exactly as equations
//! (A_SS f_S = -q_S), by the smallest correction to its forces. Accelerations then hold to rounding, not to the
//! solver's tolerance, and vary smoothly with the state while the active set stays: what an error-controlled
//! integrator needs from forces inside its right-hand side, above all with a light body under a heavy one.

use crate::lcp_problem::{residual, Triplets};
use nalgebra::{DMatrix, DVector};

/// Active sets larger than this are left as the interior point gave them (the dense eigendecomposition is O(n^3):
/// at 100 active contacts it doubled the resting solve, 1.2 to 2.4 ms; at 16 it adds 9%).
const MAX_ACTIVE: usize = 64;

/// The polished (f, w), or None when the correction would break f >= 0 or w >= 0 or not lower the residual.
pub(crate) fn polish(a: &Triplets, q: &[f64], f: &[f64], w: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
    let diagonal = a.diagonal();
    // Active: the force is larger than the acceleration, each measured on the contact's own scale.
    let active: Vec<usize> = (0..q.len()).filter(|&i| f[i] * diagonal[i] > w[i]).collect();
    if active.is_empty() || active.len() > MAX_ACTIVE {
        return None;
    }
    let mut slot = vec![usize::MAX; q.len()];
    for (k, &i) in active.iter().enumerate() {
        slot[i] = k;
    }
    let n = active.len();
    let mut dense = DMatrix::<f64>::zeros(n, n);
    for ((&i, &j), &v) in a.rows.iter().zip(&a.cols).zip(&a.vals) {
        let (si, sj) = (slot[i], slot[j]);
        if si != usize::MAX && sj != usize::MAX {
            dense[(si, sj)] += v;
            if si != sj {
                dense[(sj, si)] += v;
            }
        }
    }
    // Forces off the active set drop to zero; the active ones move by the least-norm correction that zeroes their
    // accelerations (A_SS is singular when contacts are redundant: that leaves the split among them as it was).
    let mut start = vec![0.0; q.len()];
    for &i in &active {
        start[i] = f[i];
    }
    let w_start = a.mul(&start);
    let rhs = DVector::from_iterator(n, active.iter().map(|&i| -(w_start[i] + q[i])));
    // A_SS is symmetric positive semidefinite: its pseudo-inverse from the eigenvalues above rounding.
    let eigen = dense.symmetric_eigen();
    let cut = eigen.eigenvalues.amax() * n as f64 * f64::EPSILON;
    let along = eigen.eigenvectors.transpose() * rhs;
    let scaled = DVector::from_iterator(
        n,
        along.iter().zip(eigen.eigenvalues.iter()).map(|(c, &l)| if l > cut { c / l } else { 0.0 }),
    );
    let delta = &eigen.eigenvectors * scaled;
    let mut polished = start;
    for (k, &i) in active.iter().enumerate() {
        polished[i] += delta[k];
    }
    let w_new: Vec<f64> = a.mul(&polished).iter().zip(q).map(|(x, y)| x + y).collect();
    let before = residual(f, w, q, &diagonal);
    let after = residual(&polished, &w_new, q, &diagonal);
    (after <= before).then(|| (polished.iter().map(|v| v.max(0.0)).collect(), w_new))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_inexact_answer_becomes_exact_and_the_idle_contact_stays_off() {
        // A = [[2, 1, 0], [1, 2, 0], [0, 0, 1]], q = (-3, -3, 1): exact answer f = (1, 1, 0), w = (0, 0, 1).
        let mut a = Triplets::new(3);
        for (i, j, v) in [(0, 0, 2.0), (0, 1, 1.0), (1, 1, 2.0), (2, 2, 1.0)] {
            a.add(i, j, v);
        }
        let q = [-3.0, -3.0, 1.0];
        let f = [1.0 + 1e-7, 1.0 - 2e-7, 1e-9];
        let w: Vec<f64> = a.mul(&f).iter().zip(&q).map(|(x, y)| x + y).collect();
        let (pf, pw) = polish(&a, &q, &f, &w).expect("a better answer");
        assert!((pf[0] - 1.0).abs() < 1e-15 && (pf[1] - 1.0).abs() < 1e-15 && pf[2] == 0.0, "{pf:?}");
        assert!(pw[0].abs() < 1e-15 && pw[1].abs() < 1e-15 && (pw[2] - 1.0).abs() < 1e-15, "{pw:?}");
    }

    #[test]
    fn redundant_contacts_keep_their_split() {
        // Two identical contacts (A = [[1, 1], [1, 1]], q = (-2, -2)): any f1 + f2 = 2 solves it; the interior
        // point's split (here 0.7 / 1.3, slightly off) is kept and only the total corrected.
        let mut a = Triplets::new(2);
        for (i, j, v) in [(0, 0, 1.0), (0, 1, 1.0), (1, 1, 1.0)] {
            a.add(i, j, v);
        }
        let q = [-2.0, -2.0];
        let f = [0.7, 1.3 + 1e-6];
        let w: Vec<f64> = a.mul(&f).iter().zip(&q).map(|(x, y)| x + y).collect();
        let (pf, _) = polish(&a, &q, &f, &w).expect("a better answer");
        assert!((pf[0] + pf[1] - 2.0).abs() < 1e-14 && (pf[0] - pf[1] - (0.7 - 1.3 - 1e-6)).abs() < 1e-12, "{pf:?}");
    }
}

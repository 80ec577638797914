//! LU with partial pivoting for small dense matrices, where faer's blocked kernels cost more than the
//! arithmetic (measured: on ROBER's 3x3 system they took over half of Rodas4's time). Column-major storage.

/// Largest dimension factored here; larger dense matrices go to faer.
pub(crate) const SMALL: usize = 16;

/// Factors the column-major n x n matrix `a` in place (unit lower L below the diagonal, U on and above),
/// recording row interchanges in `piv` and the reciprocals of U's diagonal in `inv_diag`. Returns false if a
/// pivot is zero or not finite.
pub(crate) fn factor(a: &mut [f64], piv: &mut [usize], inv_diag: &mut [f64], n: usize) -> bool {
    // A constant n lets the compiler unroll the loops completely (tiny loops are otherwise dominated by the
    // bookkeeping of vectorised loops and their remainders).
    match n {
        1 => factor_n(a, piv, inv_diag, 1),
        2 => factor_n(a, piv, inv_diag, 2),
        3 => factor_n(a, piv, inv_diag, 3),
        4 => factor_n(a, piv, inv_diag, 4),
        5 => factor_n(a, piv, inv_diag, 5),
        6 => factor_n(a, piv, inv_diag, 6),
        7 => factor_n(a, piv, inv_diag, 7),
        8 => factor_n(a, piv, inv_diag, 8),
        _ => factor_n(a, piv, inv_diag, n),
    }
}

#[inline(always)]
fn factor_n(a: &mut [f64], piv: &mut [usize], inv_diag: &mut [f64], n: usize) -> bool {
    let (a, piv, inv_diag) = (&mut a[..n * n], &mut piv[..n], &mut inv_diag[..n]);
    for k in 0..n {
        let col = k * n;
        let mut p = k;
        let mut best = a[col + k].abs();
        for i in k + 1..n {
            let v = a[col + i].abs();
            if v > best {
                best = v;
                p = i;
            }
        }
        if !(best > 0.0 && best.is_finite()) {
            return false;
        }
        piv[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(j * n + k, j * n + p);
            }
        }
        let inv = 1.0 / a[col + k];
        inv_diag[k] = inv;
        for i in k + 1..n {
            a[col + i] *= inv;
        }
        for j in k + 1..n {
            // No test for akj == 0: for small n a mispredicted branch costs more than the arithmetic it saves.
            let akj = a[j * n + k];
            for i in k + 1..n {
                a[j * n + i] -= a[col + i] * akj;
            }
        }
    }
    true
}

/// Solves A x = b in place with the factors from [`factor`].
pub(crate) fn solve(a: &[f64], piv: &[usize], inv_diag: &[f64], b: &mut [f64], n: usize) {
    match n {
        1 => solve_n(a, piv, inv_diag, b, 1),
        2 => solve_n(a, piv, inv_diag, b, 2),
        3 => solve_n(a, piv, inv_diag, b, 3),
        4 => solve_n(a, piv, inv_diag, b, 4),
        5 => solve_n(a, piv, inv_diag, b, 5),
        6 => solve_n(a, piv, inv_diag, b, 6),
        7 => solve_n(a, piv, inv_diag, b, 7),
        8 => solve_n(a, piv, inv_diag, b, 8),
        _ => solve_n(a, piv, inv_diag, b, n),
    }
}

#[inline(always)]
fn solve_n(a: &[f64], piv: &[usize], inv_diag: &[f64], b: &mut [f64], n: usize) {
    let (a, piv, inv_diag, b) = (&a[..n * n], &piv[..n], &inv_diag[..n], &mut b[..n]);
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    for k in 0..n {
        let bk = b[k];
        for i in k + 1..n {
            b[i] -= a[k * n + i] * bk;
        }
    }
    for k in (0..n).rev() {
        b[k] *= inv_diag[k];
        let bk = b[k];
        for i in 0..k {
            b[i] -= a[k * n + i] * bk;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random 7x7 system: the solution's residual |A x - b| is at round-off level (1e-12 for entries O(1)).
    #[test]
    fn solves_a_random_system() {
        let n = 7;
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let a: Vec<f64> = (0..n * n).map(|_| rnd()).collect();
        let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let (mut lu, mut piv, mut inv, mut x) = (a.clone(), vec![0; n], vec![0.0; n], b.clone());
        assert!(factor(&mut lu, &mut piv, &mut inv, n));
        solve(&lu, &piv, &inv, &mut x, n);
        for i in 0..n {
            let ax: f64 = (0..n).map(|j| a[j * n + i] * x[j]).sum();
            assert!((ax - b[i]).abs() < 1e-12, "row {i}: {ax} vs {}", b[i]);
        }
    }

    #[test]
    fn singular_matrix_is_detected() {
        let mut a = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!factor(&mut a, &mut [0, 0], &mut [0.0, 0.0], 2));
    }
}

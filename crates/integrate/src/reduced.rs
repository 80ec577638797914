//! The linearised implicit Euler step of a system with dq/dt = p, in the velocities alone (Baraff and Witkin's
//! form): with J = [[0, I], [A_q, A_p]], the step (I/h - J)(dq, dp) = f is equivalent to
//! (I - h A_p - h^2 A_q) dp = h (a + h A_q p) and dq = h (p + dp). Half the unknowns, no position-velocity
//! coupling; solved by sparse LU or by BiCGSTAB with a diagonal preconditioner.

use crate::error::OdeError;
use crate::report::Report;
use crate::scratch::Scratch;
use crate::settings::LinearSolver;
use faer::dyn_stack::MemStack;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::{Pair, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};

/// Where a Jacobian entry goes in the reduced matrix.
#[derive(Clone, Copy)]
enum Target {
    /// A kinematic row (dq/dt = p): not used.
    Skip,
    /// A velocity row: slot in W, and whether the column is a position (coefficient -h^2) or velocity (-h).
    Slot { slot: usize, position_col: bool, row: usize, col: usize },
}

#[allow(clippy::large_enum_variant)]
#[derive(Clone)]
enum Solve {
    Direct {
        lu: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
        factor_mem: Scratch,
        solve_mem: Scratch,
    },
    /// The matrix is kept by rows (the compressed columns of its transpose), so products gather; `guess` is the
    /// last solution, the start of the next solve.
    Iterative {
        rtol: f64,
        max_iter: usize,
        work: [Vec<f64>; 7],
        guess: Vec<f64>,
    },
}

#[derive(Clone)]
pub(crate) struct Reduced {
    m: usize,
    q_len: usize,
    symbolic: SymbolicSparseColMat<usize>,
    targets: Vec<Target>,
    diag: Vec<usize>,
    w: Vec<f64>,
    b: Vec<f64>,
    solve: Solve,
}

impl Reduced {
    /// For a system of dimension `n` whose first `q_len` rates are the last `n - q_len` states.
    pub fn new(n: usize, q_len: usize, pattern: &[(usize, usize)], solver: LinearSolver) -> Result<Self, OdeError> {
        let m = n - q_len;
        // The iterative solver stores W by rows: the compressed columns of W^T.
        let by_rows = matches!(solver, LinearSolver::Iterative { .. });
        let entry = |row: usize, col: usize| if by_rows { Pair { row: col, col: row } } else { Pair { row, col } };
        let mut pairs: Vec<Pair<usize, usize>> = (0..m).map(|i| Pair { row: i, col: i }).collect();
        for &(r, c) in pattern {
            if r >= q_len {
                pairs.push(entry(r - q_len, if c < q_len { c } else { c - q_len }));
            }
        }
        let (symbolic, _) = SymbolicSparseColMat::try_new_from_indices(m, m, &pairs)
            .map_err(|e| OdeError::invalid("jacobian pattern", format!("{e:?}")))?;
        let slot = |row: usize, col: usize| {
            let Pair { row, col } = entry(row, col);
            let start = symbolic.col_ptr()[col];
            start + symbolic.row_idx()[start..symbolic.col_ptr()[col + 1]].binary_search(&row).expect("in the pattern")
        };
        let targets = pattern
            .iter()
            .map(|&(r, c)| {
                if r < q_len {
                    return Target::Skip;
                }
                let (row, position_col) = (r - q_len, c < q_len);
                let col = if position_col { c } else { c - q_len };
                Target::Slot { slot: slot(row, col), position_col, row, col }
            })
            .collect();
        let diag = (0..m).map(|i| slot(i, i)).collect();
        let solve = match solver {
            LinearSolver::Direct => {
                let lu = factorize_symbolic_lu(symbolic.as_ref(), Default::default())
                    .map_err(|e| OdeError::invalid("jacobian pattern", format!("symbolic LU failed: {e:?}")))?;
                let factor_mem = Scratch::new(lu.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()));
                let solve_mem = Scratch::new(lu.solve_in_place_scratch::<f64>(1, Par::Seq));
                Solve::Direct { lu, numeric: NumericLu::new(), factor_mem, solve_mem }
            }
            LinearSolver::Iterative { rtol, max_iter } => {
                Solve::Iterative { rtol, max_iter, work: std::array::from_fn(|_| vec![0.0; m]), guess: vec![0.0; m] }
            }
        };
        let nnz = symbolic.row_idx().len();
        Ok(Reduced { m, q_len, symbolic, targets, diag, w: vec![0.0; nnz], b: vec![0.0; m], solve })
    }

    /// Given the Jacobian's values (pattern order), the state y and its derivative f, writes the step's dp.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_step(
        &mut self,
        values: &[f64],
        y: &[f64],
        f: &[f64],
        h: f64,
        dp: &mut [f64],
        t: f64,
        report: &mut Report,
    ) -> Result<(), OdeError> {
        let (m, q) = (self.m, self.q_len);
        self.w.fill(0.0);
        for &d in &self.diag {
            self.w[d] = 1.0;
        }
        for (i, b) in self.b.iter_mut().enumerate() {
            *b = h * f[q + i];
        }
        for (target, &v) in self.targets.iter().zip(values) {
            if let Target::Slot { slot, position_col, row, col } = *target {
                if position_col {
                    self.w[slot] -= h * h * v;
                    self.b[row] += h * h * v * y[q + col];
                } else {
                    self.w[slot] -= h * v;
                }
            }
        }
        report.linear_solves += 1;
        let w = SparseColMatRef::new(self.symbolic.as_ref(), &self.w);
        match &mut self.solve {
            Solve::Direct { lu, numeric, factor_mem, solve_mem } => {
                report.factorizations += 1;
                lu.factorize_numeric_lu(numeric, w, Par::Seq, MemStack::new(factor_mem), Default::default())
                    .map_err(|_| OdeError::SingularMatrix { t, h })?;
                dp.copy_from_slice(&self.b);
                LuRef::new_unchecked(lu, numeric).solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(dp, m, 1),
                    Par::Seq,
                    MemStack::new(solve_mem),
                );
                Ok(())
            }
            Solve::Iterative { rtol, max_iter, work, guess } => {
                let inv_diag: Vec<f64> = self.diag.iter().map(|&d| 1.0 / self.w[d]).collect();
                dp.copy_from_slice(guess);
                let (iterations, residual) = bicgstab(w, &inv_diag, &self.b, dp, *rtol, *max_iter, work);
                report.krylov_iterations += iterations;
                if residual <= *rtol {
                    guess.copy_from_slice(dp);
                    Ok(())
                } else {
                    guess.fill(0.0);
                    Err(OdeError::LinearSolve { t, h, iterations, residual })
                }
            }
        }
    }
}

/// y = A x for A stored by rows (`at` holds the compressed columns of A^T).
fn matvec(at: SparseColMatRef<'_, usize, f64>, x: &[f64], y: &mut [f64]) {
    let (sym, val) = at.parts();
    let (ptr, cols) = (sym.col_ptr(), sym.row_idx());
    for (i, yi) in y.iter_mut().enumerate() {
        let (start, end) = (ptr[i], ptr[i + 1]);
        *yi = val[start..end].iter().zip(&cols[start..end]).map(|(v, &c)| v * x[c]).sum();
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Right-preconditioned BiCGSTAB from the guess in `x`; returns (iterations, final relative residual).
fn bicgstab(
    a: SparseColMatRef<'_, usize, f64>,
    inv_diag: &[f64],
    b: &[f64],
    x: &mut [f64],
    rtol: f64,
    max_iter: usize,
    work: &mut [Vec<f64>; 7],
) -> (usize, f64) {
    let [r, r0, p, v, s, t, z] = work;
    let bnorm = dot(b, b).sqrt();
    if bnorm == 0.0 {
        x.fill(0.0);
        return (0, 0.0);
    }
    matvec(a, x, t);
    for i in 0..r.len() {
        r[i] = b[i] - t[i];
    }
    if dot(r, r).sqrt() / bnorm <= rtol {
        return (0, dot(r, r).sqrt() / bnorm);
    }
    r0.copy_from_slice(r);
    p.fill(0.0);
    v.fill(0.0);
    let (mut rho, mut alpha, mut omega) = (1.0, 1.0, 1.0);
    for it in 1..=max_iter {
        let rho_new = dot(r0, r);
        if rho_new == 0.0 || !rho_new.is_finite() {
            return (it, dot(r, r).sqrt() / bnorm);
        }
        let beta = (rho_new / rho) * (alpha / omega);
        for i in 0..p.len() {
            p[i] = r[i] + beta * (p[i] - omega * v[i]);
        }
        for i in 0..z.len() {
            z[i] = p[i] * inv_diag[i];
        }
        matvec(a, z, v);
        alpha = rho_new / dot(r0, v);
        for i in 0..s.len() {
            x[i] += alpha * z[i];
            s[i] = r[i] - alpha * v[i];
        }
        let snorm = dot(s, s).sqrt() / bnorm;
        if snorm <= rtol {
            return (it, snorm);
        }
        for i in 0..z.len() {
            z[i] = s[i] * inv_diag[i];
        }
        matvec(a, z, t);
        omega = dot(t, s) / dot(t, t);
        for i in 0..x.len() {
            x[i] += omega * z[i];
            r[i] = s[i] - omega * t[i];
        }
        let rnorm = dot(r, r).sqrt() / bnorm;
        if rnorm <= rtol || !rnorm.is_finite() || omega == 0.0 {
            return (it, rnorm);
        }
        rho = rho_new;
    }
    (max_iter, dot(r, r).sqrt() / bnorm)
}

impl Reduced {
    /// Writes the iterative solver's last solution (its next start); the direct solver keeps nothing between
    /// steps (`memory.rs`).
    pub fn save(&self, out: &mut crate::memory::MemoryWriter) {
        if let Solve::Iterative { guess, .. } = &self.solve {
            out.numbers(guess);
        }
    }

    pub fn load(&mut self, input: &mut crate::memory::MemoryReader) -> Result<(), String> {
        if let Solve::Iterative { guess, .. } = &mut self.solve {
            input.numbers("krylov guess", guess)?;
        }
        Ok(())
    }
}

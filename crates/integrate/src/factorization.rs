//! LU factors of the iteration matrices built from a Jacobian J: W = a I - J (Rosenbrock, implicit Euler, Radau's
//! real eigenvalue), or the real 2n x 2n form [[a I - J, -b I], [b I, a I - J]] of (a + i b) I - J (Radau's complex
//! pair). Dense matrices up to `small_lu::SMALL` use a plain kernel, larger ones faer's partial-pivoting LU;
//! sparse Jacobians use faer's sparse LU, whose symbolic analysis is done once for the fixed pattern.

use crate::error::OdeError;
use crate::jacobian::{Jacobian, Values};
use crate::report::Report;
use crate::scratch::Scratch;
use crate::small_lu::{self, SMALL};
use faer::dyn_stack::MemStack;
use faer::linalg::lu::partial_pivoting::{factor as dense_factor, solve as dense_solve};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::{Pair, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, MatRef, Par};

/// Which matrix is factored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shift {
    /// a I - J, n x n.
    Real,
    /// (a + i b) I - J as a real 2n x 2n matrix.
    Complex,
}

/// Dense factors. For the complex shift of a small matrix, `lu` and `lu_im` hold the real and imaginary parts of
/// the n x n complex factors (half the arithmetic of the 2n x 2n real form); otherwise `lu` holds real factors.
#[derive(Clone)]
struct DenseLu {
    lu: Vec<f64>,
    lu_im: Vec<f64>,
    inv_im: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    inv_diag: Vec<f64>,
    mem: Scratch,
}

#[derive(Clone)]
struct SparseLu {
    symbolic: SymbolicSparseColMat<usize>,
    /// Slots of each Jacobian entry in W: one per diagonal block.
    jac_slots: Vec<[usize; 2]>,
    /// Slots of the diagonal entries (i, i) of every diagonal block.
    diag_slots: Vec<usize>,
    /// Slots of (i, n + i) (gets -b) and (n + i, i) (gets +b) for the complex form.
    coupling_slots: Vec<(usize, usize)>,
    w: Vec<f64>,
    lu_symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    factor_mem: Scratch,
    solve_mem: Scratch,
}

#[derive(Clone)]
enum Storage {
    Dense(Box<DenseLu>),
    Sparse(Box<SparseLu>),
}

#[derive(Clone)]
pub(crate) struct Factorization {
    shift: Shift,
    n: usize,
    dim: usize,
    storage: Storage,
    /// (Jacobian version, a, b) of the factors held.
    factored: Option<(u64, f64, f64)>,
}

impl Factorization {
    pub fn new(jac: &Jacobian, shift: Shift) -> Result<Self, OdeError> {
        let n = jac.n;
        let dim = if shift == Shift::Complex { 2 * n } else { n };
        let storage = match &jac.values {
            Values::Dense { .. } => {
                let req = dense_factor::lu_in_place_scratch::<usize, f64>(dim, dim, Par::Seq, Default::default())
                    .or(dense_solve::solve_in_place_scratch::<usize, f64>(dim, 1, Par::Seq));
                Storage::Dense(Box::new(DenseLu {
                    lu: vec![0.0; dim * dim],
                    lu_im: if shift == Shift::Complex && n <= SMALL { vec![0.0; n * n] } else { Vec::new() },
                    inv_im: vec![0.0; n],
                    perm: vec![0; dim],
                    perm_inv: vec![0; dim],
                    inv_diag: vec![0.0; dim],
                    mem: Scratch::new(req),
                }))
            }
            Values::Sparse { pattern, .. } => Storage::Sparse(Box::new(SparseLu::new(n, pattern, shift)?)),
        };
        Ok(Factorization { shift, n, dim, storage, factored: None })
    }

    /// Forgets the factors.
    pub fn invalidate(&mut self) {
        self.factored = None;
    }

    /// Factors the matrix for shift a (+ i b) with the Jacobian's current values, unless already done.
    pub fn factor(
        &mut self,
        jac: &Jacobian,
        a: f64,
        b: f64,
        t: f64,
        h: f64,
        report: &mut Report,
    ) -> Result<(), OdeError> {
        let key = (jac.version, a, b);
        if self.factored == Some(key) {
            return Ok(());
        }
        self.factored = None;
        report.factorizations += 1;
        let ok = match &mut self.storage {
            Storage::Dense(d) => d.factor(jac, self.shift, self.n, self.dim, a, b),
            Storage::Sparse(s) => s.factor(jac, self.shift, a, b),
        };
        if !ok {
            return Err(OdeError::SingularMatrix { t, h });
        }
        self.factored = Some(key);
        Ok(())
    }

    /// Solves with the factors in place (`x.len()` is n, or 2n for the complex form: real parts then imaginary).
    pub fn solve(&mut self, x: &mut [f64], report: &mut Report) {
        report.linear_solves += 1;
        let dim = self.dim;
        let n = self.n;
        match &mut self.storage {
            Storage::Dense(d) if self.shift == Shift::Complex && n <= SMALL => {
                let (br, bi) = x.split_at_mut(n);
                small_lu::solve_complex(&d.lu, &d.lu_im, &d.perm, &d.inv_diag, &d.inv_im, br, bi, n);
            }
            Storage::Dense(d) if dim <= SMALL => small_lu::solve(&d.lu, &d.perm, &d.inv_diag, x, dim),
            Storage::Dense(d) => {
                let perm = faer::perm::PermRef::new_checked(&d.perm, &d.perm_inv, dim);
                let lu = MatRef::from_column_major_slice(&d.lu, dim, dim);
                let rhs = MatMut::from_column_major_slice_mut(x, dim, 1);
                dense_solve::solve_in_place(lu, lu, perm, rhs, Par::Seq, MemStack::new(&mut d.mem));
            }
            Storage::Sparse(s) => {
                let rhs = MatMut::from_column_major_slice_mut(x, dim, 1);
                LuRef::new_unchecked(&s.lu_symbolic, &s.numeric).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    Par::Seq,
                    MemStack::new(&mut s.solve_mem),
                );
            }
        }
    }
}

impl DenseLu {
    fn factor(&mut self, jac: &Jacobian, shift: Shift, n: usize, dim: usize, a: f64, b: f64) -> bool {
        let Values::Dense { values: j, .. } = &jac.values else { unreachable!("dense factors of a dense Jacobian") };
        let lu = &mut self.lu;
        match shift {
            Shift::Real => {
                for (l, v) in lu.iter_mut().zip(j) {
                    *l = -v;
                }
                for i in 0..n {
                    lu[i * n + i] += a;
                }
            }
            Shift::Complex if n <= SMALL => {
                for (l, v) in lu.iter_mut().zip(j) {
                    *l = -v;
                }
                self.lu_im.fill(0.0);
                for i in 0..n {
                    lu[i * n + i] += a;
                    self.lu_im[i * n + i] = b;
                }
                return small_lu::factor_complex(
                    &mut lu[..n * n],
                    &mut self.lu_im,
                    &mut self.perm,
                    &mut self.inv_diag,
                    &mut self.inv_im,
                    n,
                );
            }
            Shift::Complex => {
                lu.fill(0.0);
                for col in 0..n {
                    for row in 0..n {
                        let v = -j[col * n + row];
                        lu[col * dim + row] = v;
                        lu[(n + col) * dim + n + row] = v;
                    }
                }
                for i in 0..n {
                    lu[i * dim + i] += a;
                    lu[(n + i) * dim + n + i] += a;
                    lu[(n + i) * dim + i] = -b;
                    lu[i * dim + n + i] = b;
                }
            }
        }
        if dim <= SMALL {
            return small_lu::factor(lu, &mut self.perm, &mut self.inv_diag, dim);
        }
        dense_factor::lu_in_place(
            MatMut::from_column_major_slice_mut(lu, dim, dim),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        (0..dim).all(|i| lu[i * dim + i] != 0.0) && lu.iter().all(|v| v.is_finite())
    }
}

impl SparseLu {
    fn new(n: usize, pattern: &[(usize, usize)], shift: Shift) -> Result<Self, OdeError> {
        let blocks = if shift == Shift::Complex { 2 } else { 1 };
        let mut pairs: Vec<Pair<usize, usize>> = Vec::new();
        for k in 0..blocks {
            let o = k * n;
            pairs.extend(pattern.iter().map(|&(row, col)| Pair { row: row + o, col: col + o }));
            pairs.extend((0..n).map(|i| Pair { row: i + o, col: i + o }));
        }
        if shift == Shift::Complex {
            pairs.extend((0..n).flat_map(|i| [Pair { row: i, col: n + i }, Pair { row: n + i, col: i }]));
        }
        let dim = blocks * n;
        let (symbolic, _) = SymbolicSparseColMat::try_new_from_indices(dim, dim, &pairs)
            .map_err(|e| OdeError::invalid("jacobian pattern", format!("{e:?}")))?;
        let slot = |row: usize, col: usize| -> usize {
            let start = symbolic.col_ptr()[col];
            let rows = &symbolic.row_idx()[start..symbolic.col_ptr()[col + 1]];
            start + rows.binary_search(&row).expect("every entry is in the pattern")
        };
        let second = |row: usize, col: usize| {
            if blocks == 2 {
                slot(row + n, col + n)
            } else {
                usize::MAX
            }
        };
        let jac_slots = pattern.iter().map(|&(i, j)| [slot(i, j), second(i, j)]).collect();
        let diag_slots = (0..dim).map(|i| slot(i, i)).collect();
        let coupling_slots =
            if blocks == 2 { (0..n).map(|i| (slot(i, n + i), slot(n + i, i))).collect() } else { Vec::new() };
        let nnz = symbolic.row_idx().len();
        let lu_symbolic = factorize_symbolic_lu(symbolic.as_ref(), Default::default())
            .map_err(|e| OdeError::invalid("jacobian pattern", format!("symbolic LU failed: {e:?}")))?;
        let factor_mem = Scratch::new(lu_symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()));
        let solve_mem = Scratch::new(lu_symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(SparseLu {
            symbolic,
            jac_slots,
            diag_slots,
            coupling_slots,
            w: vec![0.0; nnz],
            lu_symbolic,
            numeric: NumericLu::new(),
            factor_mem,
            solve_mem,
        })
    }

    fn factor(&mut self, jac: &Jacobian, shift: Shift, a: f64, b: f64) -> bool {
        let Values::Sparse { values, .. } = &jac.values else { unreachable!("sparse factors of a sparse Jacobian") };
        self.w.fill(0.0);
        for (slots, &v) in self.jac_slots.iter().zip(values) {
            self.w[slots[0]] -= v;
            if shift == Shift::Complex {
                self.w[slots[1]] -= v;
            }
        }
        for &d in &self.diag_slots {
            self.w[d] += a;
        }
        for &(upper, lower) in &self.coupling_slots {
            self.w[upper] -= b;
            self.w[lower] += b;
        }
        let w = SparseColMatRef::new(self.symbolic.as_ref(), &self.w);
        self.lu_symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                w,
                Par::Seq,
                MemStack::new(&mut self.factor_mem),
                Default::default(),
            )
            .is_ok()
    }
}

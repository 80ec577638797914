//! The iteration matrix W = c I - J of the implicit methods: Jacobian evaluation (analytic dense or sparse, or
//! dense finite differences), LU factorization with faer (dense partial pivoting, or sparse LU whose symbolic
//! analysis is done once for the fixed pattern), and solves.

use crate::error::OdeError;
use crate::point::{eval, Point};
use crate::report::Report;
use crate::system::{JacobianStructure, OdeSystem};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor as dense_factor, solve as dense_solve};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::{Pair, SparseColMatRef, SymbolicSparseColMat};
use crate::small_lu::{self, SMALL};
use faer::{Conj, MatMut, MatRef, Par};

/// Dense storage: the Jacobian and its LU factors, column-major. Matrices up to `small_lu::SMALL` are factored
/// by a plain kernel, larger ones by faer.
struct Dense {
    n: usize,
    analytic: bool,
    jac: Vec<f64>,
    lu: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    inv_diag: Vec<f64>,
    mem: MemBuffer,
}

/// Sparse storage: the Jacobian values in the system's pattern, and W in compressed columns.
struct Sparse {
    symbolic: SymbolicSparseColMat<usize>,
    /// For each pattern entry, its slot in W's values.
    slots: Vec<usize>,
    /// For each row i, the slot of W's diagonal entry (i, i).
    diag_slots: Vec<usize>,
    jac_values: Vec<f64>,
    w_values: Vec<f64>,
    lu_symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
}

enum Storage {
    Dense(Box<Dense>),
    Sparse(Box<Sparse>),
}

/// W = c I - J, its factors, and the point its Jacobian belongs to.
pub(crate) struct IterationMatrix {
    n: usize,
    storage: Storage,
    jac_point: Option<u64>,
    factored_c: Option<f64>,
    work_y: Vec<f64>,
    work_f: Vec<f64>,
}

impl IterationMatrix {
    pub fn new<S: OdeSystem + ?Sized>(sys: &S) -> Result<Self, OdeError> {
        let n = sys.dim();
        let storage = match sys.jacobian_structure() {
            JacobianStructure::FiniteDifference => Storage::Dense(Box::new(Dense::new(n, false))),
            JacobianStructure::Dense => Storage::Dense(Box::new(Dense::new(n, true))),
            JacobianStructure::Sparse(pattern) => Storage::Sparse(Box::new(Sparse::new(n, &pattern)?)),
        };
        Ok(IterationMatrix { n, storage, jac_point: None, factored_c: None, work_y: vec![0.0; n], work_f: vec![0.0; n] })
    }

    /// Forgets the Jacobian (the system changed behind the integrator's back).
    pub fn invalidate(&mut self) {
        self.jac_point = None;
        self.factored_c = None;
    }

    /// Evaluates J at the point (reused if the point has not changed). Finite differences need `p.f`.
    pub fn update_jacobian<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        p: &mut Point,
        report: &mut Report,
    ) -> Result<(), OdeError> {
        if self.jac_point == Some(p.id) {
            return Ok(());
        }
        let t = p.t;
        let sys_err = |e: crate::SystemError| OdeError::System { t, message: e.message };
        match &mut self.storage {
            Storage::Dense(d) if d.analytic => {
                d.jac.fill(0.0);
                let n = d.n;
                sys.dense_jacobian(t, &p.y, MatMut::from_column_major_slice_mut(&mut d.jac, n, n)).map_err(sys_err)?;
            }
            Storage::Dense(d) => {
                p.ensure_f(sys, report)?;
                self.work_y.copy_from_slice(&p.y);
                for j in 0..self.n {
                    let yj = p.y[j];
                    let delta = (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
                    self.work_y[j] = yj + delta;
                    eval(sys, t, &self.work_y, &mut self.work_f, report)?;
                    self.work_y[j] = yj;
                    let inv = 1.0 / delta;
                    for i in 0..self.n {
                        d.jac[j * self.n + i] = (self.work_f[i] - p.f[i]) * inv;
                    }
                }
            }
            Storage::Sparse(s) => {
                s.jac_values.fill(0.0);
                sys.sparse_jacobian(t, &p.y, &mut s.jac_values).map_err(sys_err)?;
            }
        }
        if !self.jacobian_is_finite() {
            return Err(OdeError::NonFinite { t, what: "Jacobian entry", index: 0 });
        }
        report.jacobians += 1;
        self.jac_point = Some(p.id);
        self.factored_c = None;
        Ok(())
    }

    fn jacobian_is_finite(&self) -> bool {
        match &self.storage {
            Storage::Dense(d) => d.jac.iter().all(|v| v.is_finite()),
            Storage::Sparse(s) => s.jac_values.iter().all(|v| v.is_finite()),
        }
    }

    /// Factors W = c I - J (skipped when the same c was factored for the same Jacobian).
    pub fn factor(&mut self, c: f64, t: f64, h: f64, report: &mut Report) -> Result<(), OdeError> {
        if self.factored_c == Some(c) {
            return Ok(());
        }
        self.factored_c = None;
        report.factorizations += 1;
        let ok = match &mut self.storage {
            Storage::Dense(d) => d.factor(c),
            Storage::Sparse(s) => s.factor(c),
        };
        if !ok {
            return Err(OdeError::SingularMatrix { t, h });
        }
        self.factored_c = Some(c);
        Ok(())
    }

    /// Solves W x = b in place.
    pub fn solve(&mut self, b: &mut [f64], report: &mut Report) {
        report.linear_solves += 1;
        let n = self.n;
        match &mut self.storage {
            Storage::Dense(d) if n <= SMALL => small_lu::solve(&d.lu, &d.perm, &d.inv_diag, b, n),
            Storage::Dense(d) => {
                let perm = faer::perm::PermRef::new_checked(&d.perm, &d.perm_inv, n);
                let lu = MatRef::from_column_major_slice(&d.lu, n, n);
                let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
                dense_solve::solve_in_place(lu, lu, perm, rhs, Par::Seq, MemStack::new(&mut d.mem));
            }
            Storage::Sparse(s) => {
                let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
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

impl Dense {
    fn new(n: usize, analytic: bool) -> Self {
        let req = dense_factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())
            .or(dense_solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq));
        Dense {
            n,
            analytic,
            jac: vec![0.0; n * n],
            lu: vec![0.0; n * n],
            perm: vec![0; n],
            perm_inv: vec![0; n],
            inv_diag: vec![0.0; n],
            mem: MemBuffer::new(req),
        }
    }

    fn factor(&mut self, c: f64) -> bool {
        let n = self.n;
        for (l, j) in self.lu.iter_mut().zip(&self.jac) {
            *l = -j;
        }
        for i in 0..n {
            self.lu[i * n + i] += c;
        }
        if n <= SMALL {
            return small_lu::factor(&mut self.lu, &mut self.perm, &mut self.inv_diag, n);
        }
        dense_factor::lu_in_place(
            MatMut::from_column_major_slice_mut(&mut self.lu, n, n),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        (0..n).all(|i| {
            let u = self.lu[i * n + i];
            u.is_finite() && u != 0.0
        }) && self.lu.iter().all(|v| v.is_finite())
    }
}

impl Sparse {
    fn new(n: usize, pattern: &[(usize, usize)]) -> Result<Self, OdeError> {
        if let Some(&(i, j)) = pattern.iter().find(|&&(i, j)| i >= n || j >= n) {
            return Err(OdeError::invalid(
                "jacobian pattern",
                format!("entry ({i}, {j}) is outside the {n}x{n} Jacobian"),
            ));
        }
        let mut pairs: Vec<Pair<usize, usize>> = pattern.iter().map(|&(row, col)| Pair { row, col }).collect();
        pairs.extend((0..n).map(|i| Pair { row: i, col: i }));
        let (symbolic, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| OdeError::invalid("jacobian pattern", format!("{e:?}")))?;
        let slot_of = |row: usize, col: usize| -> usize {
            let start = symbolic.col_ptr()[col];
            let rows = &symbolic.row_idx()[start..symbolic.col_ptr()[col + 1]];
            start + rows.binary_search(&row).expect("every pattern entry is in W's pattern")
        };
        let slots = pattern.iter().map(|&(i, j)| slot_of(i, j)).collect();
        let diag_slots = (0..n).map(|i| slot_of(i, i)).collect();
        let nnz = symbolic.row_idx().len();
        let lu_symbolic = factorize_symbolic_lu(symbolic.as_ref(), Default::default())
            .map_err(|e| OdeError::invalid("jacobian pattern", format!("symbolic LU failed: {e:?}")))?;
        let factor_mem = MemBuffer::new(lu_symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()));
        let solve_mem = MemBuffer::new(lu_symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(Sparse {
            symbolic,
            slots,
            diag_slots,
            jac_values: vec![0.0; pattern.len()],
            w_values: vec![0.0; nnz],
            lu_symbolic,
            numeric: NumericLu::new(),
            factor_mem,
            solve_mem,
        })
    }

    fn factor(&mut self, c: f64) -> bool {
        self.w_values.fill(0.0);
        for (&slot, &v) in self.slots.iter().zip(&self.jac_values) {
            self.w_values[slot] -= v;
        }
        for &slot in &self.diag_slots {
            self.w_values[slot] += c;
        }
        let w = SparseColMatRef::new(self.symbolic.as_ref(), &self.w_values);
        self.lu_symbolic
            .factorize_numeric_lu(&mut self.numeric, w, Par::Seq, MemStack::new(&mut self.factor_mem), Default::default())
            .is_ok()
    }
}

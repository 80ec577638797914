//! The Jacobian df/dy of a system at a point: analytic dense, analytic sparse, or dense forward differences. It is
//! evaluated at most once per point, and a method may keep using it at later points (Radau does).

use crate::error::{OdeError, SystemError};
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{eval, Point};
use crate::report::Report;
use crate::system::{JacobianStructure, OdeSystem};
use faer::MatMut;

/// Where the values live.
#[derive(Clone)]
pub(crate) enum Values {
    /// Column-major n x n.
    Dense { analytic: bool, values: Vec<f64> },
    /// Values in the order of the system's pattern (repeated entries are summed by the factorizations); filled
    /// by the system, or by coloured finite differences when `coloring` is present.
    Sparse { pattern: Vec<(usize, usize)>, values: Vec<f64>, coloring: Option<Coloring> },
}

/// Columns grouped so that no two columns of a group share a row; for each column, the pattern entries (index,
/// row) its difference quotient fills (each (row, column) pair once, so repeated pattern entries are not counted
/// twice).
#[derive(Clone)]
pub(crate) struct Coloring {
    groups: Vec<Vec<usize>>,
    entries: Vec<Vec<(usize, usize)>>,
}

impl Coloring {
    /// Greedy colouring of the column intersection graph, columns taken in order.
    fn new(n: usize, pattern: &[(usize, usize)]) -> Self {
        let mut entries: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut cols_of_row: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, &(row, col)) in pattern.iter().enumerate() {
            if !rows_of[col].contains(&row) {
                rows_of[col].push(row);
                entries[col].push((k, row));
                cols_of_row[row].push(col);
            }
        }
        let mut color = vec![usize::MAX; n];
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut forbidden: Vec<usize> = Vec::new();
        for c in 0..n {
            forbidden.clear();
            for &row in &rows_of[c] {
                forbidden.extend(cols_of_row[row].iter().map(|&o| color[o]).filter(|&k| k != usize::MAX));
            }
            let k = (0..).find(|k| !forbidden.contains(k)).expect("a free colour exists");
            color[c] = k;
            if k == groups.len() {
                groups.push(Vec::new());
            }
            groups[k].push(c);
        }
        Coloring { groups, entries }
    }
}

#[derive(Clone)]
pub(crate) struct Jacobian {
    pub n: usize,
    pub values: Values,
    /// The point the values belong to.
    point: Option<u64>,
    /// Bumped at every evaluation, so factorizations know when they are stale.
    pub version: u64,
    work_y: Vec<f64>,
    work_f: Vec<f64>,
}

impl Jacobian {
    pub fn new<S: OdeSystem + ?Sized>(sys: &S) -> Result<Self, OdeError> {
        let n = sys.dim();
        let values = match sys.jacobian_structure() {
            JacobianStructure::FiniteDifference => Values::Dense { analytic: false, values: vec![0.0; n * n] },
            JacobianStructure::Dense => Values::Dense { analytic: true, values: vec![0.0; n * n] },
            JacobianStructure::Sparse(pattern) | JacobianStructure::SparseFiniteDifference(pattern) => {
                if let Some(&(i, j)) = pattern.iter().find(|&&(i, j)| i >= n || j >= n) {
                    return Err(OdeError::invalid(
                        "jacobian pattern",
                        format!("entry ({i}, {j}) is outside the {n}x{n} Jacobian"),
                    ));
                }
                let values = vec![0.0; pattern.len()];
                let coloring = matches!(sys.jacobian_structure(), JacobianStructure::SparseFiniteDifference(_))
                    .then(|| Coloring::new(n, &pattern));
                Values::Sparse { pattern, values, coloring }
            }
        };
        Ok(Jacobian { n, values, point: None, version: 0, work_y: vec![0.0; n], work_f: vec![0.0; n] })
    }

    /// The sparse pattern and its values, for a sparse Jacobian.
    #[allow(clippy::type_complexity)]
    pub fn sparse(&self) -> Option<(&[(usize, usize)], &[f64])> {
        match &self.values {
            Values::Sparse { pattern, values, .. } => Some((pattern, values)),
            Values::Dense { .. } => None,
        }
    }

    /// Whether the values were evaluated at this point.
    pub fn is_at(&self, p: &Point) -> bool {
        self.point == Some(p.id)
    }

    /// Whether any values exist yet.
    pub fn is_evaluated(&self) -> bool {
        self.version > 0
    }

    /// Forgets the values (the state changed behind the integrator's back).
    pub fn invalidate(&mut self) {
        self.point = None;
        self.version += 1;
        let (Values::Dense { values, .. } | Values::Sparse { values, .. }) = &mut self.values;
        values.fill(f64::NAN);
    }

    /// Evaluates J at the point unless it already holds it. Finite differences use `p.f`.
    pub fn update<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        p: &mut Point,
        report: &mut Report,
    ) -> Result<(), OdeError> {
        if self.is_at(p) {
            return Ok(());
        }
        let t = p.t;
        let sys_err = |e: SystemError| OdeError::System { t, message: e.message };
        let n = self.n;
        match &mut self.values {
            Values::Dense { analytic: true, values } => {
                values.fill(0.0);
                sys.dense_jacobian(t, &p.y, MatMut::from_column_major_slice_mut(values, n, n)).map_err(sys_err)?;
            }
            Values::Dense { analytic: false, values } => {
                p.ensure_f(sys, report)?;
                self.work_y.copy_from_slice(&p.y);
                for j in 0..n {
                    let yj = p.y[j];
                    let delta = (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
                    self.work_y[j] = yj + delta;
                    eval(sys, t, &self.work_y, &mut self.work_f, report)?;
                    self.work_y[j] = yj;
                    for i in 0..n {
                        values[j * n + i] = (self.work_f[i] - p.f[i]) / delta;
                    }
                }
            }
            Values::Sparse { values, coloring: None, .. } => {
                values.fill(0.0);
                sys.sparse_jacobian(t, &p.y, values).map_err(sys_err)?;
            }
            Values::Sparse { values, coloring: Some(coloring), .. } => {
                p.ensure_f(sys, report)?;
                values.fill(0.0);
                self.work_y.copy_from_slice(&p.y);
                for group in &coloring.groups {
                    for &c in group {
                        self.work_y[c] = p.y[c] + (f64::EPSILON * p.y[c].abs().max(1e-5)).sqrt();
                    }
                    eval(sys, t, &self.work_y, &mut self.work_f, report)?;
                    for &c in group {
                        let delta = self.work_y[c] - p.y[c];
                        self.work_y[c] = p.y[c];
                        for &(k, row) in &coloring.entries[c] {
                            values[k] = (self.work_f[row] - p.f[row]) / delta;
                        }
                    }
                }
            }
        }
        let (Values::Dense { values, .. } | Values::Sparse { values, .. }) = &self.values;
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(OdeError::NonFinite { t, what: "Jacobian entry", index: i });
        }
        report.jacobians += 1;
        self.point = Some(p.id);
        self.version += 1;
        Ok(())
    }
}

impl Jacobian {
    /// Writes the values, the point they belong to and the version (`memory.rs`).
    pub fn save(&self, out: &mut MemoryWriter) {
        let (Values::Dense { values, .. } | Values::Sparse { values, .. }) = &self.values;
        out.numbers(values);
        out.id(self.point);
        out.count(self.version);
    }

    /// Reads back what `save` wrote; the factorizations built on it must be invalidated by the caller.
    pub fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        let (Values::Dense { values, .. } | Values::Sparse { values, .. }) = &mut self.values;
        input.numbers("jacobian", values)?;
        self.point = input.id("jacobian point")?;
        self.version = input.count("jacobian version")?;
        Ok(())
    }
}

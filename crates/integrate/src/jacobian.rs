//! The Jacobian df/dy of a system at a point: analytic dense, analytic sparse, or dense forward differences. It is
//! evaluated at most once per point, and a method may keep using it at later points (Radau does).

use crate::error::{OdeError, SystemError};
use crate::point::{eval, Point};
use crate::report::Report;
use crate::system::{JacobianStructure, OdeSystem};
use faer::MatMut;

/// Where the values live.
pub(crate) enum Values {
    /// Column-major n x n.
    Dense { analytic: bool, values: Vec<f64> },
    /// Values in the order of the system's pattern (repeated entries are summed by the factorizations).
    Sparse { pattern: Vec<(usize, usize)>, values: Vec<f64> },
}

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
            JacobianStructure::Sparse(pattern) => {
                if let Some(&(i, j)) = pattern.iter().find(|&&(i, j)| i >= n || j >= n) {
                    return Err(OdeError::invalid(
                        "jacobian pattern",
                        format!("entry ({i}, {j}) is outside the {n}x{n} Jacobian"),
                    ));
                }
                let values = vec![0.0; pattern.len()];
                Values::Sparse { pattern, values }
            }
        };
        Ok(Jacobian { n, values, point: None, version: 0, work_y: vec![0.0; n], work_f: vec![0.0; n] })
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
            Values::Sparse { values, .. } => {
                values.fill(0.0);
                sys.sparse_jacobian(t, &p.y, values).map_err(sys_err)?;
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

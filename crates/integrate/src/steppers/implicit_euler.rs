//! Implicit Euler X' = X + h f(X', t + h): the chapter's linearised step dX = (I/h - J)^-1 f(X), or full Newton
//! iteration on the same system with the Jacobian re-evaluated at every iterate. Dense or sparse LU; a sparse
//! mechanical system (dq/dt = p) takes the linearised step in its velocities alone (`reduced.rs`), by sparse LU
//! or BiCGSTAB.

use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::factorization::{Factorization, Shift};
use crate::jacobian::Jacobian;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{max_norm, Point};
use crate::reduced::Reduced;
use crate::settings::{LinearSolver, NewtonMode};
use crate::system::OdeSystem;

#[derive(Clone)]
pub(crate) struct ImplicitEuler {
    jac: Jacobian,
    matrix: Factorization,
    /// The velocity-only form, when the system allows it.
    reduced: Option<Reduced>,
    iterate: Point,
    delta: Vec<f64>,
}

impl ImplicitEuler {
    pub fn new<S: OdeSystem + ?Sized>(sys: &S, solver: LinearSolver) -> Result<Self, OdeError> {
        let n = sys.dim();
        let jac = Jacobian::new(sys)?;
        let matrix = Factorization::new(&jac, Shift::Real)?;
        let reduced = match (sys.split(), jac.sparse()) {
            (Some(split), Some((pattern, _))) if split.kinematic_identity && 2 * split.positions == n => {
                Some(Reduced::new(n, split.positions, pattern, solver)?)
            }
            _ => None,
        };
        Ok(ImplicitEuler { jac, matrix, reduced, iterate: Point::new(0.0, &vec![0.0; n]), delta: vec![0.0; n] })
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for ImplicitEuler {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        match ctx.newton {
            NewtonMode::Linearised if self.reduced.is_some() => {
                from.ensure_f(sys, &mut ctx.report)?;
                self.jac.update(sys, from, &mut ctx.report)?;
                let q = from.y.len() / 2;
                let (_, values) = self.jac.sparse().expect("the reduced form needs a sparse Jacobian");
                let reduced = self.reduced.as_mut().expect("checked");
                reduced.solve_step(values, &from.y, &from.f, h, &mut self.delta[q..], from.t, &mut ctx.report)?;
                for i in 0..q {
                    to.y[i] = from.y[i] + h * (from.y[q + i] + self.delta[q + i]);
                    to.y[q + i] = from.y[q + i] + self.delta[q + i];
                }
            }
            NewtonMode::Linearised => {
                from.ensure_f(sys, &mut ctx.report)?;
                self.jac.update(sys, from, &mut ctx.report)?;
                self.matrix.factor(&self.jac, 1.0 / h, 0.0, from.t, h, &mut ctx.report)?;
                self.delta.copy_from_slice(&from.f);
                self.matrix.solve(&mut self.delta, &mut ctx.report);
                for ((o, y), d) in to.y.iter_mut().zip(&from.y).zip(&self.delta) {
                    *o = y + d;
                }
            }
            NewtonMode::Newton { tol, max_iter } => {
                // G(X) = X - X_i - h f(X, t + h) = 0; (I/h - J(X)) dX = (X_i - X)/h + f(X).
                let t1 = from.t + h;
                let it = &mut self.iterate;
                it.y.copy_from_slice(&from.y);
                it.renew(t1);
                let mut previous = f64::INFINITY;
                let mut converged = false;
                let mut norm = f64::INFINITY;
                for k in 1..=max_iter {
                    ctx.report.newton_iterations += 1;
                    it.ensure_f(sys, &mut ctx.report)?;
                    self.jac.update(sys, it, &mut ctx.report)?;
                    self.matrix.factor(&self.jac, 1.0 / h, 0.0, t1, h, &mut ctx.report)?;
                    for i in 0..self.delta.len() {
                        self.delta[i] = (from.y[i] - it.y[i]) / h + it.f[i];
                    }
                    self.matrix.solve(&mut self.delta, &mut ctx.report);
                    norm = max_norm(&self.delta) / (1.0 + max_norm(&it.y));
                    for (x, d) in it.y.iter_mut().zip(&self.delta) {
                        *x += d;
                    }
                    it.renew(t1);
                    if !norm.is_finite() || (k > 1 && norm > 2.0 * previous) {
                        break;
                    }
                    if norm <= tol {
                        converged = true;
                        break;
                    }
                    previous = norm;
                }
                if !converged {
                    return Err(OdeError::NewtonFailure {
                        t: from.t,
                        h,
                        iterations: max_iter.min(ctx.report.newton_iterations),
                        residual: norm,
                    });
                }
                to.y.copy_from_slice(&it.y);
            }
        }
        Ok(Estimate::default())
    }

    fn reset(&mut self) {
        self.jac.invalidate();
        self.matrix.invalidate();
    }
}

impl Remember for ImplicitEuler {
    fn save(&self, out: &mut MemoryWriter) {
        self.jac.save(out);
        if let Some(r) = &self.reduced {
            r.save(out);
        }
        out.point(&self.iterate);
        out.numbers(&self.delta);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        self.jac.load(input)?;
        self.matrix.invalidate();
        if let Some(r) = &mut self.reduced {
            r.load(input)?;
        }
        input.point("newton iterate", &mut self.iterate)?;
        input.numbers("delta", &mut self.delta)
    }
}

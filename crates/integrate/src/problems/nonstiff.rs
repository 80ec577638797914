//! Non-stiff reference problems: Lotka-Volterra populations and the Arenstorf orbit.

use super::{ErrorNorm, Problem, ProblemKind};
use crate::error::SystemError;
use crate::system::{JacobianStructure, OdeSystem};
use faer::MatMut;

/// u1' = a u1 - b u1 u2, u2' = -c u2 + d u1 u2.
#[derive(Clone, Copy, Debug)]
pub struct LotkaVolterra {
    /// (a, b, c, d).
    pub p: [f64; 4],
}

impl LotkaVolterra {
    /// p = (1.5, 1, 3, 1), u0 = (1, 1), t in [0, 10]; no closed form: the reference is computed.
    pub fn problem() -> Problem {
        Problem {
            name: "lotka-volterra",
            t0: 0.0,
            t_end: 10.0,
            y0: vec![1.0, 1.0],
            reference: None,
            kind: ProblemKind::NonStiff,
            atol_scale: 1.0,
            norm: ErrorNorm::Relative,
            make: || Box::new(LotkaVolterra { p: [1.5, 1.0, 3.0, 1.0] }),
        }
    }
}

impl OdeSystem for LotkaVolterra {
    fn dim(&self) -> usize {
        2
    }
    #[inline]
    fn rhs(&mut self, _t: f64, u: &[f64], du: &mut [f64]) -> Result<(), SystemError> {
        let [a, b, c, d] = self.p;
        du[0] = a * u[0] - b * u[0] * u[1];
        du[1] = -c * u[1] + d * u[0] * u[1];
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, u: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        let [a, b, c, d] = self.p;
        jac[(0, 0)] = a - b * u[1];
        jac[(0, 1)] = -b * u[0];
        jac[(1, 0)] = d * u[1];
        jac[(1, 1)] = -c + d * u[0];
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

/// The restricted three-body problem in rotating coordinates, u = (x, y, x', y').
#[derive(Clone, Copy, Debug)]
pub struct Arenstorf {
    /// Mass ratio mu.
    pub mu: f64,
}

impl Arenstorf {
    /// mu = 0.012277471 and the periodic Arenstorf orbit: after one period T the state returns to u0.
    pub fn problem() -> Problem {
        let y0 = vec![0.994, 0.0, 0.0, -2.00158510637908252240537862224];
        Problem {
            name: "arenstorf",
            t0: 0.0,
            t_end: 17.0652165601579625588917206249,
            reference: Some(y0.clone()),
            y0,
            kind: ProblemKind::NonStiff,
            atol_scale: 1.0,
            norm: ErrorNorm::Relative,
            make: || Box::new(Arenstorf { mu: 0.012277471 }),
        }
    }
}

impl OdeSystem for Arenstorf {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, u: &[f64], du: &mut [f64]) -> Result<(), SystemError> {
        let mu = self.mu;
        let mu1 = 1.0 - mu;
        let (x, y) = (u[0], u[1]);
        let d1 = ((x + mu).powi(2) + y * y).powf(1.5);
        let d2 = ((x - mu1).powi(2) + y * y).powf(1.5);
        du[0] = u[2];
        du[1] = u[3];
        du[2] = x + 2.0 * u[3] - mu1 * (x + mu) / d1 - mu * (x - mu1) / d2;
        du[3] = y - 2.0 * u[2] - mu1 * y / d1 - mu * y / d2;
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

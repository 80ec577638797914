//! Problems with closed-form solutions: Dahlquist's y' = lambda y, the damped oscillator of the chapter's particle
//! equation, the Kepler orbit and the stiff spring.

use super::{ErrorNorm, Problem, ProblemKind};
use crate::error::SystemError;
use crate::system::{JacobianStructure, OdeSystem, Split};
use faer::MatMut;

/// y' = lambda y; y(t) = y0 exp(lambda t). Stiff for lambda = -1e6.
#[derive(Clone, Copy, Debug)]
pub struct Dahlquist {
    /// The eigenvalue.
    pub lambda: f64,
}

impl OdeSystem for Dahlquist {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = self.lambda * y[0];
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, _y: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        jac[(0, 0)] = self.lambda;
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

/// The chapter's particle equation in one dimension, m x'' + d x' + k x = 0, as y = (x, v).
#[derive(Clone, Copy, Debug)]
pub struct DampedOscillator {
    /// Mass m.
    pub mass: f64,
    /// Damping d.
    pub damping: f64,
    /// Restoring stiffness (the chapter's h).
    pub stiffness: f64,
}

impl DampedOscillator {
    /// The exact (x(t), v(t)) from (x0, v0): under-damped, critically damped or over-damped.
    pub fn exact(&self, t: f64, x0: f64, v0: f64) -> (f64, f64) {
        let (m, d, k) = (self.mass, self.damping, self.stiffness);
        let w0 = (k / m).sqrt();
        let zeta = d / (2.0 * (m * k).sqrt());
        if (zeta - 1.0).abs() < 1e-12 {
            let (a, b) = (x0, v0 + w0 * x0);
            let e = (-w0 * t).exp();
            ((a + b * t) * e, (b - w0 * (a + b * t)) * e)
        } else if zeta < 1.0 {
            let wd = w0 * (1.0 - zeta * zeta).sqrt();
            let s = zeta * w0;
            let (a, b) = (x0, (v0 + s * x0) / wd);
            let e = (-s * t).exp();
            let (c, sn) = ((wd * t).cos(), (wd * t).sin());
            let x = e * (a * c + b * sn);
            let v = e * (-s * (a * c + b * sn) + wd * (-a * sn + b * c));
            (x, v)
        } else {
            let root = (zeta * zeta - 1.0).sqrt();
            let (r1, r2) = (-w0 * (zeta - root), -w0 * (zeta + root));
            let c1 = (v0 - r2 * x0) / (r1 - r2);
            let c2 = x0 - c1;
            let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
            (c1 * e1 + c2 * e2, r1 * c1 * e1 + r2 * c2 * e2)
        }
    }
}

impl OdeSystem for DampedOscillator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = y[1];
        dy[1] = -(self.damping * y[1] + self.stiffness * y[0]) / self.mass;
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, _y: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        jac[(0, 1)] = 1.0;
        jac[(1, 0)] = -self.stiffness / self.mass;
        jac[(1, 1)] = -self.damping / self.mass;
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
    fn split(&self) -> Option<Split> {
        Some(Split { positions: 1, force_depends_on_velocity: self.damping != 0.0, kinematic_identity: true })
    }
    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        dq[0] = y[1];
        Ok(())
    }
    fn velocity_rate(&mut self, _t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        dp[0] = -(self.damping * y[1] + self.stiffness * y[0]) / self.mass;
        Ok(())
    }
}

/// The Kepler problem q'' = -q / |q|^3 in the plane, y = (q1, q2, p1, p2); H = |p|^2/2 - 1/|q|.
#[derive(Clone, Copy, Debug, Default)]
pub struct Kepler;

impl Kepler {
    /// Eccentricity 0.6: q0 = (0.4, 0), p0 = (0, 2), H = -1/2, period 2 pi; after one period the state returns.
    pub fn problem() -> Problem {
        let y0 = vec![0.4, 0.0, 0.0, 2.0];
        Problem {
            name: "kepler",
            t0: 0.0,
            t_end: 2.0 * std::f64::consts::PI,
            reference: Some(y0.clone()),
            y0,
            kind: ProblemKind::NonStiff,
            atol_scale: 1.0,
            norm: ErrorNorm::Relative,
            make: || Box::new(Kepler),
        }
    }

    /// The Hamiltonian (total energy) of a state.
    pub fn energy(y: &[f64]) -> f64 {
        0.5 * (y[2] * y[2] + y[3] * y[3]) - 1.0 / (y[0] * y[0] + y[1] * y[1]).sqrt()
    }

    fn force(y: &[f64], dp: &mut [f64]) {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let inv_r3 = 1.0 / (r2 * r2.sqrt());
        dp[0] = -y[0] * inv_r3;
        dp[1] = -y[1] * inv_r3;
    }
}

impl OdeSystem for Kepler {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = y[2];
        dy[1] = y[3];
        Kepler::force(y, &mut dy[2..]);
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, y: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        let (x, z) = (y[0], y[1]);
        let r2 = x * x + z * z;
        let r = r2.sqrt();
        let (r3, r5) = (r2 * r, r2 * r2 * r);
        jac[(0, 2)] = 1.0;
        jac[(1, 3)] = 1.0;
        jac[(2, 0)] = -1.0 / r3 + 3.0 * x * x / r5;
        jac[(2, 1)] = 3.0 * x * z / r5;
        jac[(3, 0)] = 3.0 * x * z / r5;
        jac[(3, 1)] = -1.0 / r3 + 3.0 * z * z / r5;
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
    fn split(&self) -> Option<Split> {
        Some(Split { positions: 2, force_depends_on_velocity: false, kinematic_identity: true })
    }
    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        dq.copy_from_slice(&y[2..]);
        Ok(())
    }
    fn velocity_rate(&mut self, _t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        Kepler::force(y, dp);
        Ok(())
    }
}

/// A stiff spring x'' = -k x / m with m = 1, k = 1e8 (eigenvalues +-1e4 i), y = (x, v), x(0) = 1, v(0) = 0:
/// x = cos(w t), v = -w sin(w t), w = 1e4. Explicit Euler is unstable for every h; RK4 needs h <= 2.83e-4.
#[derive(Clone, Copy, Debug)]
pub struct StiffSpring {
    /// Stiffness k (mass 1).
    pub stiffness: f64,
}

impl StiffSpring {
    /// k = 1e8 on [0, 0.01] (about 16 periods).
    pub fn problem() -> Problem {
        let w: f64 = 1e4;
        let t_end = 0.01;
        Problem {
            name: "stiff-spring",
            t0: 0.0,
            t_end,
            y0: vec![1.0, 0.0],
            reference: Some(vec![(w * t_end).cos(), -w * (w * t_end).sin()]),
            kind: ProblemKind::NonStiff,
            atol_scale: 1.0,
            norm: ErrorNorm::Relative,
            make: || Box::new(StiffSpring { stiffness: 1e8 }),
        }
    }
}

impl OdeSystem for StiffSpring {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = y[1];
        dy[1] = -self.stiffness * y[0];
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, _y: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        jac[(0, 1)] = 1.0;
        jac[(1, 0)] = -self.stiffness;
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
    fn split(&self) -> Option<Split> {
        Some(Split { positions: 1, force_depends_on_velocity: false, kinematic_identity: true })
    }
    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        dq[0] = y[1];
        Ok(())
    }
    fn velocity_rate(&mut self, _t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        dp[0] = -self.stiffness * y[0];
        Ok(())
    }
}

//! Stiff reference problems from the Bari/Hairer IVP test set, with analytic Jacobians and the published
//! reference values (RADAU5 at rtol = atol = 1.1e-18).

use super::{ErrorNorm, Problem, ProblemKind};
use crate::error::SystemError;
use crate::system::{JacobianStructure, OdeSystem};
use faer::MatMut;

/// Van der Pol in the test-set form: y1' = y2, y2' = ((1 - y1^2) y2 - y1) / eps.
#[derive(Clone, Copy, Debug)]
pub struct VanDerPol {
    /// The stiffness parameter eps.
    pub eps: f64,
}

impl VanDerPol {
    /// eps = 1e-6, y0 = (2, 0), t in [0, 2].
    pub fn problem() -> Problem {
        Problem {
            name: "van-der-pol",
            t0: 0.0,
            t_end: 2.0,
            y0: vec![2.0, 0.0],
            reference: Some(vec![1.706167732170483, -0.8928097010247975]),
            kind: ProblemKind::Stiff,
            atol_scale: 1.0,
            norm: ErrorNorm::Componentwise,
            make: || Box::new(VanDerPol { eps: 1e-6 }),
        }
    }
}

impl OdeSystem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = y[1];
        dy[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / self.eps;
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, y: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        jac[(0, 1)] = 1.0;
        jac[(1, 0)] = (-2.0 * y[0] * y[1] - 1.0) / self.eps;
        jac[(1, 1)] = (1.0 - y[0] * y[0]) / self.eps;
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

/// Robertson's chemical kinetics (ROBER).
#[derive(Clone, Copy, Debug, Default)]
pub struct Rober;

impl Rober {
    /// y0 = (1, 0, 0), t in [0, 1e11].
    pub fn problem() -> Problem {
        Problem {
            name: "rober",
            t0: 0.0,
            t_end: 1e11,
            y0: vec![1.0, 0.0, 0.0],
            reference: Some(vec![0.2083340149701255e-7, 0.8333360770334713e-13, 0.9999999791665050]),
            kind: ProblemKind::Stiff,
            atol_scale: 1e-10,
            norm: ErrorNorm::Componentwise,
            make: || Box::new(Rober),
        }
    }
}

impl OdeSystem for Rober {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
        dy[2] = 3e7 * y[1] * y[1];
        dy[1] = -dy[0] - dy[2];
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, y: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        jac[(0, 0)] = -0.04;
        jac[(0, 1)] = 1e4 * y[2];
        jac[(0, 2)] = 1e4 * y[1];
        jac[(1, 0)] = 0.04;
        jac[(1, 1)] = -1e4 * y[2] - 6e7 * y[1];
        jac[(1, 2)] = -1e4 * y[1];
        jac[(2, 1)] = 6e7 * y[1];
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

/// HIRES: eight species of a plant-physiology reaction network.
#[derive(Clone, Copy, Debug, Default)]
pub struct Hires;

impl Hires {
    /// The test-set initial state, t in [0, 321.8122].
    pub fn problem() -> Problem {
        Problem {
            name: "hires",
            t0: 0.0,
            t_end: 321.8122,
            y0: vec![1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057],
            reference: Some(vec![
                0.7371312573325668e-3,
                0.1442485726316185e-3,
                0.5888729740967575e-4,
                0.1175651343283149e-2,
                0.2386356198831331e-2,
                0.6238968252742796e-2,
                0.2849998395185769e-2,
                0.2850001604814231e-2,
            ]),
            kind: ProblemKind::Stiff,
            atol_scale: 1e-4,
            norm: ErrorNorm::Componentwise,
            make: || Box::new(Hires),
        }
    }
}

impl OdeSystem for Hires {
    fn dim(&self) -> usize {
        8
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007;
        dy[1] = 1.71 * y[0] - 8.75 * y[1];
        dy[2] = -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4];
        dy[3] = 8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3];
        dy[4] = -1.745 * y[4] + 0.43 * y[5] + 0.43 * y[6];
        dy[5] = -280.0 * y[5] * y[7] + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6];
        dy[6] = 280.0 * y[5] * y[7] - 1.81 * y[6];
        dy[7] = -280.0 * y[5] * y[7] + 1.81 * y[6];
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, y: &[f64], mut j: MatMut<'_, f64>) -> Result<(), SystemError> {
        j[(0, 0)] = -1.71;
        j[(0, 1)] = 0.43;
        j[(0, 2)] = 8.32;
        j[(1, 0)] = 1.71;
        j[(1, 1)] = -8.75;
        j[(2, 2)] = -10.03;
        j[(2, 3)] = 0.43;
        j[(2, 4)] = 0.035;
        j[(3, 1)] = 8.32;
        j[(3, 2)] = 1.71;
        j[(3, 3)] = -1.12;
        j[(4, 4)] = -1.745;
        j[(4, 5)] = 0.43;
        j[(4, 6)] = 0.43;
        j[(5, 3)] = 0.69;
        j[(5, 4)] = 1.71;
        j[(5, 5)] = -280.0 * y[7] - 0.43;
        j[(5, 6)] = 0.69;
        j[(5, 7)] = -280.0 * y[5];
        j[(6, 5)] = 280.0 * y[7];
        j[(6, 6)] = -1.81;
        j[(6, 7)] = 280.0 * y[5];
        j[(7, 5)] = -280.0 * y[7];
        j[(7, 6)] = 1.81;
        j[(7, 7)] = -280.0 * y[5];
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

/// OREGO: the Oregonator model of the Belousov-Zhabotinskii reaction.
#[derive(Clone, Copy, Debug, Default)]
pub struct Orego;

impl Orego {
    /// y0 = (1, 2, 3), t in [0, 360].
    pub fn problem() -> Problem {
        Problem {
            name: "orego",
            t0: 0.0,
            t_end: 360.0,
            y0: vec![1.0, 2.0, 3.0],
            reference: Some(vec![1.000814870318523, 1228.178521549917, 132.0554942846706]),
            kind: ProblemKind::Stiff,
            atol_scale: 1.0,
            norm: ErrorNorm::Componentwise,
            make: || Box::new(Orego),
        }
    }
}

impl OdeSystem for Orego {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = 77.27 * (y[1] + y[0] * (1.0 - 8.375e-6 * y[0] - y[1]));
        dy[1] = (y[2] - (1.0 + y[0]) * y[1]) / 77.27;
        dy[2] = 0.161 * (y[0] - y[2]);
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::Dense
    }
    fn dense_jacobian(&mut self, _t: f64, y: &[f64], mut j: MatMut<'_, f64>) -> Result<(), SystemError> {
        j[(0, 0)] = 77.27 * (1.0 - 2.0 * 8.375e-6 * y[0] - y[1]);
        j[(0, 1)] = 77.27 * (1.0 - y[0]);
        j[(1, 0)] = -y[1] / 77.27;
        j[(1, 1)] = -(1.0 + y[0]) / 77.27;
        j[(1, 2)] = 1.0 / 77.27;
        j[(2, 0)] = 0.161;
        j[(2, 2)] = -0.161;
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

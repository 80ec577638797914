//! Second-order mechanical systems x'' = a(t, x, v) and their reduction to first order, y = (x, v), as the chapter
//! shows: d/dt (x, v) = (v, a(t, x, v)).

use crate::error::SystemError;
use crate::system::{OdeSystem, Split};

/// A second-order system x'' = a(t, x, v) with `dof` coordinates.
pub trait SecondOrderSystem {
    /// Number of coordinates (length of x and of v).
    fn dof(&self) -> usize;

    /// Writes the acceleration a(t, x, v) into `a`.
    fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) -> Result<(), SystemError>;

    /// Whether the acceleration depends on v (damping, gyroscopic terms). Default: true, the safe answer.
    fn depends_on_velocity(&self) -> bool {
        true
    }

    /// True when the acceleration ignores t. Default: false.
    fn is_autonomous(&self) -> bool {
        false
    }
}

/// The first-order form of a [`SecondOrderSystem`]: state y = (x, v) of length `2 dof`, with the (q, p) split that
/// the symplectic methods use. Its Jacobian comes from finite differences.
pub struct FirstOrder<S>(pub S);

impl<S: SecondOrderSystem> OdeSystem for FirstOrder<S> {
    fn dim(&self) -> usize {
        2 * self.0.dof()
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        let n = self.0.dof();
        let (x, v) = y.split_at(n);
        let (dx, dv) = dy.split_at_mut(n);
        dx.copy_from_slice(v);
        self.0.acceleration(t, x, v, dv)
    }

    fn is_autonomous(&self) -> bool {
        self.0.is_autonomous()
    }

    fn split(&self) -> Option<Split> {
        Some(Split {
            positions: self.0.dof(),
            force_depends_on_velocity: self.0.depends_on_velocity(),
            kinematic_identity: true,
        })
    }

    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        dq.copy_from_slice(&y[self.0.dof()..]);
        Ok(())
    }

    fn velocity_rate(&mut self, t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        let (x, v) = y.split_at(self.0.dof());
        self.0.acceleration(t, x, v, dp)
    }
}

//! The first-order system y' = f(t, y) that every integrator solves, and how it offers its Jacobian.

use crate::error::SystemError;
use faer::MatMut;

/// How a system offers its Jacobian df/dy.
#[derive(Clone, Debug, PartialEq)]
pub enum JacobianStructure {
    /// No analytic Jacobian: the crate forms a dense one by forward differences (`dim` extra evaluations).
    FiniteDifference,
    /// An analytic dense Jacobian, filled by [`OdeSystem::dense_jacobian`].
    Dense,
    /// An analytic sparse Jacobian with this fixed pattern of `(row, column)` entries, filled by
    /// [`OdeSystem::sparse_jacobian`] in the same order. Repeated entries are summed. Implicit methods then use a
    /// sparse LU whose symbolic analysis is done once.
    Sparse(Vec<(usize, usize)>),
    /// A sparse Jacobian with this pattern (a superset of the nonzeros), formed by finite differences: columns
    /// that share no row are perturbed together (Curtis-Powell-Reid colouring), so a banded or mesh-like system
    /// costs a few dozen evaluations whatever its size.
    SparseFiniteDifference(Vec<(usize, usize)>),
}

/// A partition y = (q, p) for the symplectic methods: the first `positions` components are positions (their rate
/// comes from [`OdeSystem::position_rate`]) and the rest are velocities or momenta ([`OdeSystem::velocity_rate`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Split {
    /// Number of leading position components.
    pub positions: usize,
    /// Whether the velocity rate (the force) depends on the velocities (damping, Coriolis). When it does not,
    /// velocity Verlet reuses the last force evaluation of a step as the first of the next.
    pub force_depends_on_velocity: bool,
    /// Whether dq/dt = p exactly (as for particles, not for quaternions): then the linearised implicit Euler step
    /// reduces to a system in the velocities alone, half the size (Baraff and Witkin's form).
    pub kinematic_identity: bool,
}

/// A first-order system y' = f(t, y) of fixed dimension.
///
/// Only [`dim`](OdeSystem::dim) and [`rhs`](OdeSystem::rhs) are required. A system may add an analytic Jacobian
/// (dense or sparse, used by the implicit methods), declare itself autonomous (saves the Rosenbrock method a
/// time-derivative evaluation), and offer a (q, p) split for the symplectic methods.
pub trait OdeSystem {
    /// Length of the state vector.
    fn dim(&self) -> usize;

    /// Writes f(t, y) into `dy` (`y.len() == dy.len() == dim()`).
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError>;

    /// How the Jacobian is available. Default: finite differences.
    fn jacobian_structure(&self) -> JacobianStructure {
        JacobianStructure::FiniteDifference
    }

    /// Fills the dense Jacobian df/dy at (t, y); called only when the structure is [`JacobianStructure::Dense`].
    fn dense_jacobian(&mut self, _t: f64, _y: &[f64], _jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        Err(SystemError::new("dense_jacobian is not implemented by this system"))
    }

    /// Writes the values of the sparse Jacobian at (t, y), in the order of the pattern given by
    /// [`JacobianStructure::Sparse`]; called only for that structure.
    fn sparse_jacobian(&mut self, _t: f64, _y: &[f64], _values: &mut [f64]) -> Result<(), SystemError> {
        Err(SystemError::new("sparse_jacobian is not implemented by this system"))
    }

    /// True when f does not depend on t explicitly.
    fn is_autonomous(&self) -> bool {
        false
    }

    /// The (q, p) split for the symplectic methods, if the system has one.
    fn split(&self) -> Option<Split> {
        None
    }

    /// Writes dq/dt (length `split().positions`); called only when [`split`](OdeSystem::split) is `Some`.
    fn position_rate(&mut self, _t: f64, _y: &[f64], _dq: &mut [f64]) -> Result<(), SystemError> {
        Err(SystemError::new("position_rate is not implemented by this system"))
    }

    /// Writes dp/dt (length `dim() - split().positions`); called only when [`split`](OdeSystem::split) is `Some`.
    fn velocity_rate(&mut self, _t: f64, _y: &[f64], _dp: &mut [f64]) -> Result<(), SystemError> {
        Err(SystemError::new("velocity_rate is not implemented by this system"))
    }

    /// Called after every accepted step with the new state, so a system can project it back onto its manifold
    /// (tumble renormalises orientation quaternions). Returns whether `y` was changed.
    fn project(&mut self, _t: f64, _y: &mut [f64]) -> bool {
        false
    }
}

/// Forwards every method of [`OdeSystem`] through a pointer type (`&mut S`, `Box<S>`).
macro_rules! forward_ode_system {
    ($($pointer:ty),*) => {$(
        impl<S: OdeSystem + ?Sized> OdeSystem for $pointer {
            fn dim(&self) -> usize {
                (**self).dim()
            }
            fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
                (**self).rhs(t, y, dy)
            }
            fn jacobian_structure(&self) -> JacobianStructure {
                (**self).jacobian_structure()
            }
            fn dense_jacobian(&mut self, t: f64, y: &[f64], jac: MatMut<'_, f64>) -> Result<(), SystemError> {
                (**self).dense_jacobian(t, y, jac)
            }
            fn sparse_jacobian(&mut self, t: f64, y: &[f64], values: &mut [f64]) -> Result<(), SystemError> {
                (**self).sparse_jacobian(t, y, values)
            }
            fn is_autonomous(&self) -> bool {
                (**self).is_autonomous()
            }
            fn split(&self) -> Option<Split> {
                (**self).split()
            }
            fn position_rate(&mut self, t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
                (**self).position_rate(t, y, dq)
            }
            fn velocity_rate(&mut self, t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
                (**self).velocity_rate(t, y, dp)
            }
            fn project(&mut self, t: f64, y: &mut [f64]) -> bool {
                (**self).project(t, y)
            }
        }
    )*};
}

forward_ode_system!(&mut S, Box<S>);

/// A system from a closure: `FnSystem::new(dim, |t, y, dy| { ... })`. Its Jacobian comes from finite differences.
pub struct FnSystem<F> {
    dim: usize,
    f: F,
    autonomous: bool,
}

impl<F: FnMut(f64, &[f64], &mut [f64])> FnSystem<F> {
    /// A non-autonomous system of dimension `dim` with right-hand side `f`.
    pub fn new(dim: usize, f: F) -> Self {
        Self { dim, f, autonomous: false }
    }

    /// Declares that `f` ignores its time argument.
    pub fn autonomous(mut self) -> Self {
        self.autonomous = true;
        self
    }
}

impl<F: FnMut(f64, &[f64], &mut [f64])> OdeSystem for FnSystem<F> {
    fn dim(&self) -> usize {
        self.dim
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        (self.f)(t, y, dy);
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        self.autonomous
    }
}

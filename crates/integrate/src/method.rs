//! The integration methods by name (the names of the public contract) and what each one is.

use crate::error::OdeError;
use std::fmt;
use std::str::FromStr;

/// An integration method. Names (`Method::name`, `FromStr`) are those of tumble's public contract.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Method {
    /// Explicit Euler, order 1: X' = X + h f(X, t).
    Euler,
    /// The chapter's variable-step Euler: h = sqrt(2 eps / ||df/dt||), with df/dt = (df/dX) f + df/dt.
    EulerVariable,
    /// The midpoint rule (RK2), order 2.
    Midpoint,
    /// Classical Runge-Kutta, order 4 (with the chapter's K4 typo corrected).
    Rk4,
    /// Adams-Bashforth 4 (explicit multistep), started by RK4, restarted when h changes.
    Ab4,
    /// Adams-Moulton 4 predictor-corrector (PECE, AB4 predictor) with Milne's error estimate.
    Am4,
    /// Implicit Euler: the chapter's linearised step or full Newton iteration; dense or sparse LU.
    ImplicitEuler,
    /// Dormand-Prince 5(4) with PI step control and 4th-order dense output.
    Dopri5,
    /// Symplectic Euler (kick then drift) for split (q, p) systems, order 1.
    SymplecticEuler,
    /// Velocity Verlet (kick-drift-kick) for split (q, p) systems, order 2.
    Verlet,
    /// Rodas4: L-stable, stiffly accurate Rosenbrock method of order 4(3) with 3rd-order dense output.
    Rodas4,
    /// Radau IIA of order 5 (RADAU5): L-stable collocation, stage order 3, simplified Newton, dense output.
    Radau5,
    /// Dormand-Prince 8(5,3): explicit, order 8, for tight tolerances on non-stiff problems (no dense output).
    Dop853,
}

impl Method {
    /// Every method, in the order the reports list them.
    pub const ALL: [Method; 13] = [
        Method::Euler,
        Method::EulerVariable,
        Method::Midpoint,
        Method::Rk4,
        Method::Ab4,
        Method::Am4,
        Method::ImplicitEuler,
        Method::Dopri5,
        Method::SymplecticEuler,
        Method::Verlet,
        Method::Rodas4,
        Method::Radau5,
        Method::Dop853,
    ];

    /// The public name (`"rk4"`, `"dopri5"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Method::Euler => "euler",
            Method::EulerVariable => "euler-variable",
            Method::Midpoint => "midpoint",
            Method::Rk4 => "rk4",
            Method::Ab4 => "ab4",
            Method::Am4 => "am4",
            Method::ImplicitEuler => "implicit-euler",
            Method::Dopri5 => "dopri5",
            Method::SymplecticEuler => "symplectic-euler",
            Method::Verlet => "verlet",
            Method::Rodas4 => "rodas4",
            Method::Radau5 => "radau5",
            Method::Dop853 => "dop853",
        }
    }

    /// Order of accuracy of the solution.
    pub fn order(self) -> u32 {
        match self {
            Method::Euler | Method::EulerVariable | Method::ImplicitEuler | Method::SymplecticEuler => 1,
            Method::Midpoint | Method::Verlet => 2,
            Method::Rk4 | Method::Ab4 | Method::Am4 | Method::Rodas4 => 4,
            Method::Dopri5 | Method::Radau5 => 5,
            Method::Dop853 => 8,
        }
    }

    /// One-step methods can be wrapped in step doubling; multistep methods (AB4, AM4) cannot.
    pub fn is_one_step(self) -> bool {
        !matches!(self, Method::Ab4 | Method::Am4 | Method::EulerVariable)
    }

    /// Methods that solve linear systems with the Jacobian.
    pub fn uses_jacobian(self) -> bool {
        matches!(self, Method::ImplicitEuler | Method::Rodas4 | Method::Radau5)
    }

    /// Methods that need the system's (q, p) split.
    pub fn needs_split(self) -> bool {
        matches!(self, Method::SymplecticEuler | Method::Verlet)
    }

    /// Methods with their own error estimate, usable with `Control::Tolerances`.
    pub fn has_error_estimate(self) -> bool {
        matches!(self, Method::Dopri5 | Method::Rodas4 | Method::Am4 | Method::Radau5 | Method::Dop853)
    }

    /// Methods meant for stiff problems (A- or L-stable).
    pub fn is_stiff(self) -> bool {
        matches!(self, Method::ImplicitEuler | Method::Rodas4 | Method::Radau5)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = OdeError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Method::ALL.iter().copied().find(|m| m.name() == s).ok_or_else(|| {
            let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
            OdeError::invalid("integrator", format!("unknown method {s:?}; expected one of {}", names.join(", ")))
        })
    }
}

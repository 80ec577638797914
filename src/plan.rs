//! The plan: which stages a world runs, decided from its contents, so a scene pays only for what it uses.

use std::fmt;

/// The stages a world runs and the length of its state vector.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    /// Active stages in pipeline order: "particles", "rigid-bodies", "rotation", "gravity", "damping",
    /// "springs", "loads", "callbacks", then with colliders that can touch "collision-detection" and either
    /// (accurate mode) "bisection", "impulses", "resting-contact" or (fast mode) "contact-cone-program" and
    /// "sleeping"; then "integrate", "jacobian".
    pub stages: Vec<&'static str>,
    /// Length of the state vector (6 a particle, 13 a dynamic body).
    pub state_len: usize,
    /// "accurate" or "fast".
    pub mode: &'static str,
    /// The integration method.
    pub method: &'static str,
    /// How the Jacobian is formed, when the method needs one: "analytic-sparse", "analytic-sparse-definite" (the
    /// springs' semidefinite approximation) or "colored-finite-differences".
    pub jacobian: Option<&'static str>,
}

impl Plan {
    /// Whether a stage is active.
    pub fn has(&self, stage: &str) -> bool {
        self.stages.contains(&stage)
    }
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ({} state variables, {} mode, method {}",
            self.stages.join(" -> "),
            self.state_len,
            self.mode,
            self.method
        )?;
        if let Some(j) = self.jacobian {
            write!(f, ", jacobian {j}")?;
        }
        write!(f, ")")
    }
}

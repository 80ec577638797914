//! The velocity step: one time step of every body's velocities with contact, Coulomb friction, restitution and joint
//! rows, as a convex program per island. What it solves and gives back (`problem.rs`), its settings
//! (`settings.rs`), the step over islands (`run.rs`), each island's shared data (`island.rs`), which method answers
//! it (`dispatch.rs`): tumble's Newton method (`newton/`) or clarabel (`clarabel.rs`, the one file behind the
//! `clarabel` feature), and the check every answer passes (`check.rs`).

mod check;
#[cfg(feature = "clarabel")]
mod clarabel;
mod dispatch;
mod island;
mod newton;
mod problem;
mod resistance;
mod run;
mod settings;

pub use problem::{free_velocity, BilateralKind, BilateralRow, VelocityProblem, VelocityStep};
pub use run::velocity_step;
pub use settings::{StepMethod, StepSettings};

//! tumble-contact: what happens when bodies touch. The chapter's classification of contacts by relative normal
//! velocity, its impulse formula (and the particle form), simultaneous impulses under Newton's restitution law,
//! Baraff's resting-contact forces as a QP, and beyond the chapter Coulomb friction as a velocity-level conic
//! program; contacts are split into islands and every island is solved on its own, by tumble's Newton method or by
//! clarabel. The `clarabel` feature (on by default) brings clarabel: its island programs, and the chapter's QPs
//! (simultaneous impulses, resting forces, position correction); without it the velocity step is the Newton
//! method's alone, and the soft step, the joint rows and the spring law remain.
//! Every function is pure: it returns impulses, forces and velocities and changes nothing, so a failure leaves
//! every body as it was.
//!
//! Conventions: a contact's normal points from body A to body B; forces and impulses push B along it and A against
//! it; the relative normal velocity n . (v_B - v_A) is positive when the bodies part.
//!
//! ```
//! # #[cfg(feature = "clarabel")]
//! # fn main() -> Result<(), tumble_contact::ContactError> {
//! use nalgebra::{Matrix3, Point3, Vector3};
//! use tumble_contact::{resting_forces, BodyState, Contact, SolverSettings};
//!
//! // A 2 kg box on the ground, touching it at four corners: together they carry m g, each m g / 4 (the split among
//! // redundant corners is not fixed by the equations; the solver lands on the symmetric one to about 1e-8).
//! let ground = BodyState::fixed(Point3::origin());
//! let mut block = BodyState::rigid(2.0, Matrix3::identity() * 0.1, Point3::new(0.0, 0.0, 0.5));
//! block.force = Vector3::new(0.0, 0.0, -2.0 * 9.81);
//! let corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
//!     .map(|(x, y)| Contact::new(0, 1, Point3::new(x, y, 0.0), Vector3::z_axis()));
//! let out = resting_forces(&[ground, block], &corners, &SolverSettings::default())?;
//! assert!((out.forces.iter().sum::<f64>() - 2.0 * 9.81).abs() < 1e-9);
//! assert!(out.forces.iter().all(|f| (f - 2.0 * 9.81 / 4.0).abs() < 1e-6));
//! # Ok(())
//! # }
//! # #[cfg(not(feature = "clarabel"))]
//! # fn main() {} // resting_forces is clarabel's
//! ```

#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod body;
mod classify;
mod contact;
#[cfg(feature = "clarabel")]
mod delassus;
mod error;
mod impulse;
mod islands;
mod jacobian;
mod joint;
#[cfg(feature = "clarabel")]
mod lcp;
#[cfg(feature = "clarabel")]
mod lcp_problem;
#[cfg(feature = "clarabel")]
mod polish;
#[cfg(feature = "clarabel")]
mod projection;
#[cfg(feature = "clarabel")]
mod resting;
#[cfg(feature = "clarabel")]
mod simultaneous;
mod soft;
mod solver_settings;
mod spring;
mod step;
mod threads;
mod union_find;

pub use body::BodyState;
pub use classify::{classify, velocity_tolerance, ContactClass};
pub use contact::{Contact, NormalMotion};
pub use error::ContactError;
pub use impulse::{impulse_magnitude, reflect, velocities_after, BodyVelocity};
pub use islands::{body_islands, islands};
pub use joint::{
    across, delassus, factor, joint_rows, BoundedSolve, JointConstraint, JointFrame, JointImpulse, JointKind,
    JointMotor, JointRow, JointSpring, RowKind, RowPart, MAX_ROWS,
};
#[cfg(feature = "clarabel")]
pub use projection::{position_correction, Correction};
#[cfg(feature = "clarabel")]
pub use resting::{contact_wrenches, resting_forces, RestingForces};
#[cfg(feature = "clarabel")]
pub use simultaneous::{collision_impulses, Impulses};
pub use soft::{
    soft_solve, soft_step, ColourGraph, SoftImpulse, SoftLinks, SoftManifold, SoftPoint, SoftProblem, SoftSettings,
    SoftSpring, SoftStep, COLOURS, MANIFOLD_POINTS, OVERFLOW, UNCOLOURED,
};
pub use solver_settings::SolverSettings;
pub use spring::{SpringLaw, COINCIDENT};
pub use step::{
    free_velocity, velocity_step, BilateralKind, BilateralRow, StepMethod, StepSettings, VelocityProblem, VelocityStep,
};
pub use threads::{cores, Workers};
pub use union_find::UnionFind;

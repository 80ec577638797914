//! tumble-contact: what happens when bodies touch. The chapter's classification of contacts by relative normal
//! velocity, its impulse formula (and the particle form), simultaneous impulses under Newton's restitution law,
//! Baraff's resting-contact forces as a QP, and beyond the chapter Coulomb friction as a velocity-level conic
//! program; contacts are split into islands and every island is solved on its own with clarabel. Every function is
//! pure: it returns impulses, forces and velocities and changes nothing, so a failure leaves every body as it was.

mod body;
mod classify;
mod contact;
mod delassus;
mod error;
mod friction;
mod impulse;
mod islands;
mod jacobian;
mod lcp;
mod resting;
mod simultaneous;

pub use body::BodyState;
pub use classify::{classify, velocity_tolerance, ContactClass};
pub use contact::{Contact, NormalMotion};
pub use error::ContactError;
pub use friction::{velocity_step, StepSettings, VelocityStep};
pub use impulse::{impulse_magnitude, reflect, velocities_after, BodyVelocity};
pub use islands::islands;
pub use lcp::SolverSettings;
pub use resting::{contact_wrenches, resting_forces, RestingForces};
pub use simultaneous::{collision_impulses, Impulses};

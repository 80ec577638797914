//! The crate's integration tests, linked as one binary: each file a module, those that need clarabel behind a file-level `cfg(feature = "clarabel")`; `common` what they share.

mod common;
mod errors;
mod friction;
mod gyroscopic;
mod impulses;
mod joint_rows;
mod manifold_impulses;
mod newton;
mod resting;
mod soft_step;

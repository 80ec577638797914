//! The crate's integration tests, linked as one binary: each file a module; `common` what they share.

mod common;
mod control;
mod convergence;
mod errors;
mod events;
mod geometric;
mod memory;
mod references;
mod second_order;
mod stability;

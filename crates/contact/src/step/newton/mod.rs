//! tumble's own method for one island of the velocity step: the program's rows and blocks (`program.rs`), its
//! Hessian and factorisation (`hessian.rs`), and the multiplier iteration with Newton's method (`solve.rs`).

mod hessian;
mod program;
mod solve;

pub(crate) use program::Island;
pub(crate) use solve::solve_island_newton;

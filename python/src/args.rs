//! Keyword arguments turned into the root crate's types: integrator options, force targets, spring ends.

use crate::convert::invalid;
use crate::handles::{PyBodyHandle, PyParticleHandle};
use nalgebra::Vector3;
use pyo3::prelude::*;
use tumble::{Attachment, IntegratorOptions, Target};

/// The integrator options from keyword arguments (the rules and defaults live in `tumble::IntegratorOptions`).
#[allow(clippy::too_many_arguments)]
pub fn integrator_options(
    integrator: Option<String>,
    rtol: Option<f64>,
    atol: Option<f64>,
    dt: Option<f64>,
    step_doubling: bool,
    tolerance: Option<f64>,
    linear_solver: Option<String>,
    newton: bool,
    max_steps: Option<usize>,
) -> IntegratorOptions {
    IntegratorOptions { integrator, rtol, atol, dt, step_doubling, tolerance, linear_solver, newton, max_steps }
}

pub fn to_target(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Target> {
    if let Ok(p) = obj.extract::<PyParticleHandle>() {
        return Ok(Target::Particle(p.into()));
    }
    if let Ok(b) = obj.extract::<PyBodyHandle>() {
        return Ok(Target::Body(b.into()));
    }
    Err(invalid(name, "expected a ParticleHandle or a BodyHandle"))
}

pub fn attachment(
    obj: Option<&Bound<'_, PyAny>>,
    anchor: Option<Vector3<f64>>,
    point: Option<Vector3<f64>>,
    name: &str,
) -> PyResult<Attachment> {
    match obj.filter(|o| !o.is_none()) {
        Some(o) => match to_target(o, name)? {
            Target::Particle(p) => {
                if anchor.is_some_and(|a| a != Vector3::zeros()) {
                    return Err(invalid(&format!("anchor_{name}"), "a particle has no body frame"));
                }
                Ok(Attachment::Particle(p))
            }
            Target::Body(b) => Ok(Attachment::Body(b, anchor.unwrap_or_else(Vector3::zeros))),
        },
        None => point
            .map(Attachment::Point)
            .ok_or_else(|| invalid("world_point", format!("`{name}` is None, so the spring needs a world_point"))),
    }
}

//! Reports, plans and runs as Python dicts of plain values and numpy arrays (the package wraps them in
//! `tumble.Report` and `tumble.Run`); the field lists come from the root crate.

use crate::convert::array;
use crate::handles::{PyBodyHandle, PyJointHandle, PyParticleHandle};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use tumble::{Plan, ReportValue, Run, WorldReport};

/// The report as a plain dict of its fields (the package wraps it in `tumble.Report`), with the stages that ran
/// under "stages_ran", the report's text under "_text" and its long form under "_details".
pub fn report_dict<'py>(py: Python<'py>, r: &WorldReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, value) in r.fields() {
        match value {
            ReportValue::Count(n) => d.set_item(name, n)?,
            ReportValue::Number(x) => d.set_item(name, x)?,
            ReportValue::Optional(x) => d.set_item(name, x)?,
            ReportValue::Text(t) => d.set_item(name, t)?,
        }
    }
    d.set_item("stages_ran", r.stages.ran())?;
    d.set_item("_text", r.to_string())?;
    d.set_item("_details", format!("{r:#}"))?;
    Ok(d)
}

/// A run's arrays as a dict: frames (F, ...) and steps, with the report and the handles of its columns.
pub fn run_arrays<'py>(py: Python<'py>, run: Run) -> PyResult<Bound<'py, PyDict>> {
    let particles: Vec<PyParticleHandle> = run.particles.iter().map(|&h| h.into()).collect();
    let bodies: Vec<PyBodyHandle> = run.bodies.iter().map(|&h| h.into()).collect();
    let broken: Vec<PyJointHandle> = run.joint_breaks.iter().map(|&(_, h)| h.into()).collect();
    let interrupted = run.interrupted;
    let (a, report) = run.into_arrays();
    let report = &report;
    let (f, p, b) = (a.times.len(), a.particle_count, a.body_count);
    let steps = a.step_times.len();
    let d = PyDict::new(py);
    d.set_item("times", array(py, a.times, &[f])?)?;
    d.set_item("particle_positions", array(py, a.particle_positions, &[f, p, 3])?)?;
    d.set_item("particle_velocities", array(py, a.particle_velocities, &[f, p, 3])?)?;
    d.set_item("body_positions", array(py, a.body_positions, &[f, b, 3])?)?;
    d.set_item("body_orientations", array(py, a.body_orientations, &[f, b, 4])?)?;
    d.set_item("body_velocities", array(py, a.body_velocities, &[f, b, 3])?)?;
    d.set_item("body_angular_velocities", array(py, a.body_angular_velocities, &[f, b, 3])?)?;
    d.set_item("kinetic_energy", array(py, a.kinetic_energy, &[f])?)?;
    d.set_item("potential_energy", array(py, a.potential_energy, &[f])?)?;
    d.set_item("energy", array(py, a.energy, &[f])?)?;
    d.set_item("momentum", array(py, a.momentum, &[f, 3])?)?;
    d.set_item("angular_momentum", array(py, a.angular_momentum, &[f, 3])?)?;
    d.set_item("step_times", array(py, a.step_times, &[steps])?)?;
    d.set_item("step_sizes", array(py, a.step_sizes, &[steps])?)?;
    let events = a.contact_events.len();
    d.set_item("penetration", array(py, a.penetration, &[f])?)?;
    d.set_item("contact_events", array(py, a.contact_events, &[events])?)?;
    let breaks = a.joint_break_times.len();
    d.set_item("joint_break_times", array(py, a.joint_break_times, &[breaks])?)?;
    d.set_item("joint_breaks", PyList::new(py, broken)?)?;
    let points = a.contact_points.len() / 6;
    let counts = a.contact_counts.iter().map(|&c| c as f64).collect();
    d.set_item("contact_counts", array(py, counts, &[f])?)?;
    d.set_item("contact_points", array(py, a.contact_points, &[points, 2, 3])?)?;
    d.set_item("report", report_dict(py, report)?)?;
    d.set_item("interrupted", interrupted)?;
    d.set_item("particles", PyList::new(py, particles)?)?;
    d.set_item("bodies", PyList::new(py, bodies)?)?;
    Ok(d)
}

/// The plan as a dict: stages, state length, mode, method and how the Jacobian is formed.
pub fn plan_dict<'py>(py: Python<'py>, p: Plan) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("stages", p.stages)?;
    d.set_item("state_len", p.state_len)?;
    d.set_item("method", p.method)?;
    d.set_item("mode", p.mode)?;
    d.set_item("jacobian", p.jacobian)?;
    Ok(d)
}

//! Joints from Python: `World._add_joint` takes a joint's kind and fields as the Python classes (`tumble.Hinge`,
//! `tumble.Ball`, ...) hold them and forwards them to `JointBuilder`; the checks and defaults are the library's.

use crate::convert::{opt_vec3, world_error};
use crate::handles::{PyBodyHandle, PyJointHandle};
use crate::world::PyWorld;
use pyo3::prelude::*;
use tumble::JointBuilder;

#[pymethods]
impl PyWorld {
    /// Adds a joint of `kind` ("ball", "hinge", "slider", "piston", "spin-drive", "slide-drive", "weld",
    /// "distance", "rope") between bodies `a` and `b`
    /// (None: the world, whose anchor is then a world point). Use `World.add_joint` with a joint object.
    #[pyo3(signature = (kind, a, b, anchor_a = None, anchor_b = None, axis = None, limits = None, motor = None,
                        spring = None, softness = None, length = None, breaking = None, break_window = 0.0,
                        collide = false, turn_limits = None, cluster = false))]
    #[allow(clippy::too_many_arguments)]
    fn _add_joint(
        &mut self,
        kind: &str,
        a: Option<PyBodyHandle>,
        b: Option<PyBodyHandle>,
        anchor_a: Option<&Bound<'_, PyAny>>,
        anchor_b: Option<&Bound<'_, PyAny>>,
        axis: Option<&Bound<'_, PyAny>>,
        limits: Option<(f64, f64)>,
        motor: Option<(f64, f64)>,
        spring: Option<(f64, f64, f64)>,
        softness: Option<(f64, f64)>,
        length: Option<f64>,
        breaking: Option<(f64, f64)>,
        break_window: f64,
        collide: bool,
        turn_limits: Option<(f64, f64)>,
        cluster: bool,
    ) -> PyResult<PyJointHandle> {
        let (a, b) = (a.map(Into::into), b.map(Into::into));
        let axis = opt_vec3("axis", axis)?.unwrap_or_else(nalgebra::Vector3::x);
        let mut j = match kind {
            "ball" => JointBuilder::ball(a, b),
            "hinge" => JointBuilder::hinge(a, b, axis),
            "slider" => JointBuilder::slider(a, b, axis),
            "piston" => JointBuilder::piston(a, b, axis),
            "spin-drive" => JointBuilder::spin_drive(a, b, axis),
            "slide-drive" => JointBuilder::slide_drive(a, b, axis),
            "weld" => JointBuilder::weld(a, b),
            "distance" => JointBuilder::distance(a, b, length),
            "rope" => JointBuilder::rope(a, b, length),
            other => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "invalid argument `kind`: unknown joint kind {other:?}"
                )))
            }
        };
        if let Some(p) = opt_vec3("anchor_a", anchor_a)? {
            j = j.anchor_a(p);
        }
        if let Some(p) = opt_vec3("anchor_b", anchor_b)? {
            j = j.anchor_b(p);
        }
        if let Some((lo, hi)) = limits {
            j = j.limits(lo, hi);
        }
        if let Some((speed, max_force)) = motor {
            j = j.motor(speed, max_force);
        }
        if let Some((k, c, target)) = spring {
            j = j.spring(k, c, target);
        }
        if let Some((hertz, zeta)) = softness {
            j = j.softness(hertz, zeta);
        }
        if let Some((force, torque)) = breaking {
            j = j.breaking_averaged(force, torque, break_window);
        } else if break_window != 0.0 {
            return Err(crate::convert::invalid("break_window", "applies to a joint given `breaking`"));
        }
        j = j.collide(collide).cluster(cluster);
        if let Some((lo, hi)) = turn_limits {
            j = j.turn_limits(lo, hi);
        }
        self.w().add_joint(j).map(Into::into).map_err(world_error)
    }

    /// Removes a joint.
    fn remove_joint(&mut self, joint: PyJointHandle) -> PyResult<()> {
        self.w().remove_joint(joint.into()).map(|_| ()).map_err(world_error)
    }

    /// Whether `joint` has broken (past its `breaking` bounds; it then holds nothing).
    fn joint_broken(&self, joint: PyJointHandle) -> PyResult<bool> {
        let h: tumble::JointHandle = joint.into();
        match self.r().joint(h) {
            Some(j) => Ok(j.is_broken()),
            None => Err(pyo3::exceptions::PyValueError::new_err(format!(
                "invalid argument `joint`: no joint {h:?} in this world"
            ))),
        }
    }

    /// When `joint` breaks: (force N, torque N m, window s) as given to `breaking` (a glued piece's bounds from
    /// its face, `add_fractured`), or None for a joint that never breaks.
    fn joint_breaking(&self, joint: PyJointHandle) -> PyResult<Option<(f64, f64, f64)>> {
        let h: tumble::JointHandle = joint.into();
        match self.r().joint(h) {
            Some(j) => Ok(j.breaking().map(|b| (b.force, b.torque, b.window))),
            None => Err(pyo3::exceptions::PyValueError::new_err(format!(
                "invalid argument `joint`: no joint {h:?} in this world"
            ))),
        }
    }

    /// The joints that have broken, in the order they were added.
    fn broken_joints(&self) -> Vec<PyJointHandle> {
        self.r().joints().filter(|(_, j)| j.is_broken()).map(|(h, _)| h.into()).collect()
    }

    /// The joints, in the order they were added (a fractured object's welds among them).
    #[getter]
    fn joint_handles(&self) -> Vec<PyJointHandle> {
        self.r().joints().map(|(h, _)| h.into()).collect()
    }

    /// The number of joints.
    #[getter]
    fn joint_count(&self) -> usize {
        self.r().joints().count()
    }
}

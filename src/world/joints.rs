//! Adding and removing joints: each joint is checked where it enters (ends that exist and differ, one of them
//! moving, finite anchors, a non-zero axis, options only where the kind has them, limits in order) and gets its
//! reference, the bodies' relative rotation as they are now. A joint the world's mode cannot hold is refused where
//! it meets the mode: adding the joint, or setting the mode.

use super::{unknown, World};
use crate::error::WorldError;
use crate::joint::{Joint, JointBuilder, JointHandle, JointKind};
use crate::limits;
use crate::mode::{FastSolver, Mode, Persistent};
use crate::spring::BodyHandle;
use nalgebra::{UnitQuaternion, Vector3};

impl World {
    /// An end's pose (the world's is the identity); `name` is the argument it came from.
    fn end_pose(
        &self,
        name: &'static str,
        end: Option<BodyHandle>,
    ) -> Result<(Vector3<f64>, UnitQuaternion<f64>, bool), WorldError> {
        match end {
            None => Ok((Vector3::zeros(), UnitQuaternion::identity(), false)),
            Some(h) => {
                let b = self.bodies.get(h).ok_or_else(|| unknown(name, h))?;
                Ok((b.position, b.orientation, !b.is_static))
            }
        }
    }

    /// Checks a joint description against the world; gives the joint with its reference.
    fn check_joint(&self, spec: JointBuilder) -> Result<Joint, WorldError> {
        let (xa, qa, moves_a) = self.end_pose("a", spec.a)?;
        let (xb, qb, moves_b) = self.end_pose("b", spec.b)?;
        if spec.a.is_some() && spec.a == spec.b {
            return Err(WorldError::invalid("b", "a joint needs two different bodies, got the same body twice"));
        }
        if !moves_a && !moves_b {
            return Err(WorldError::invalid("b", "a joint between the world and static bodies holds nothing"));
        }
        limits::vector("anchor_a", &spec.anchor_a, limits::COORDINATE, "m")?;
        limits::vector("anchor_b", &spec.anchor_b, limits::COORDINATE, "m")?;
        limits::vector("axis", &spec.axis, limits::COORDINATE, "")?;
        let n = spec.axis.norm();
        if !(n > 1e-12 * spec.axis.amax().max(1e-300) && n > 1e-150) {
            return Err(WorldError::invalid("axis", "must have a length > 0"));
        }
        let moving = matches!(spec.kind, JointKind::Hinge | JointKind::Slider | JointKind::Piston);
        let drive = matches!(spec.kind, JointKind::Drive { .. });
        if drive && (spec.motor.is_none() || spec.limits.is_some() || spec.spring.is_some()) {
            let name = if spec.motor.is_none() {
                "motor"
            } else if spec.limits.is_some() {
                "limits"
            } else {
                "spring"
            };
            return Err(WorldError::invalid(
                name,
                "a drive is its motor alone: give it a motor, and no limits or spring",
            ));
        }
        let moving = moving || drive;
        let what = |name: &'static str| {
            WorldError::invalid(name, format!("a {:?} joint has none: only hinges and sliders do", spec.kind))
        };
        if let Some((lo, hi)) = spec.limits {
            if !moving {
                return Err(what("limits"));
            }
            let bound = if spec.kind == JointKind::Hinge { std::f64::consts::PI } else { limits::COORDINATE };
            limits::in_range("limits", lo, -bound, bound, "")?;
            limits::in_range("limits", hi, -bound, bound, "")?;
            if lo > hi {
                return Err(WorldError::invalid("limits", format!("lower {lo} is above upper {hi}")));
            }
        }
        if let Some((lo, hi)) = spec.turn_limits {
            if spec.kind != JointKind::Piston {
                return Err(WorldError::invalid(
                    "turn_limits",
                    format!("a {:?} joint has none: only pistons do", spec.kind),
                ));
            }
            let pi = std::f64::consts::PI;
            limits::in_range("turn_limits", lo, -pi, pi, "rad")?;
            limits::in_range("turn_limits", hi, -pi, pi, "rad")?;
            if lo > hi {
                return Err(WorldError::invalid("turn_limits", format!("lower {lo} is above upper {hi}")));
            }
        }
        if let Some(m) = spec.motor {
            if !moving {
                return Err(what("motor"));
            }
            limits::in_range("motor", m.speed, -limits::SPEED, limits::SPEED, "(speed)")?;
            limits::non_negative("motor", m.max_force, limits::FORCE, "(max_force)")?;
        }
        if let Some(s) = spec.spring {
            if !moving {
                return Err(what("spring"));
            }
            limits::positive("spring", s.stiffness, limits::STIFFNESS, "(stiffness)")?;
            limits::non_negative("spring", s.damping, limits::STIFFNESS, "(damping)")?;
            limits::in_range("spring", s.target, -limits::COORDINATE, limits::COORDINATE, "(target)")?;
        }
        if let Some((hertz, zeta)) = spec.softness {
            limits::positive("softness", hertz, 1e12, "Hz")?;
            limits::non_negative("softness", zeta, 1e12, "(damping ratio)")?;
        }
        if let Some(b) = spec.breaking {
            for (v, what) in [(b.force, "force (N)"), (b.torque, "torque (N m)")] {
                if !(v > 0.0) {
                    return Err(WorldError::invalid(
                        "breaking",
                        format!("its {what} must be > 0 or infinite, got {v:e}"),
                    ));
                }
            }
            if b.force.is_infinite() && b.torque.is_infinite() {
                return Err(WorldError::invalid("breaking", "a joint that breaks needs a finite force or torque"));
            }
            limits::non_negative("window", b.window, limits::TIME, "s")?;
        }
        // the anchors in the world, for a distance joint's length
        let world_a = if spec.a.is_some() { xa + qa * spec.anchor_a } else { spec.anchor_a };
        let world_b = if spec.b.is_some() { xb + qb * spec.anchor_b } else { spec.anchor_b };
        let length = match spec.kind {
            JointKind::Distance { length: Some(l), .. } => {
                limits::non_negative("length", l, 4.0 * limits::COORDINATE, "m")?
            }
            _ => (world_a - world_b).norm(),
        };
        let axis_b = qb.inverse() * (qa * (spec.axis / n));
        Ok(Joint { length, axis_b, reference: qa.inverse() * qb, spec, broken: false })
    }

    /// Adds a joint.
    pub fn add_joint(&mut self, joint: JointBuilder) -> Result<JointHandle, WorldError> {
        let j = self.check_joint(joint)?;
        joint_fits_mode(&self.mode, &j.spec).map_err(|(name, why)| WorldError::invalid(name, why))?;
        self.retire_engine();
        Ok(self.joints.insert(j))
    }

    /// Removes a joint.
    pub fn remove_joint(&mut self, h: JointHandle) -> Result<Joint, WorldError> {
        let j = self.joints.remove(h).ok_or_else(|| unknown("joint", h))?;
        self.retire_engine();
        Ok(j)
    }

    /// A joint.
    pub fn joint(&self, h: JointHandle) -> Option<&Joint> {
        self.joints.get(h)
    }

    /// The joints, with their handles.
    pub fn joints(&self) -> impl Iterator<Item = (JointHandle, &Joint)> {
        self.joints.iter()
    }
}

/// Whether `mode` can hold a joint like `spec`: else the argument at fault (on the joint's side) and why.
pub(crate) fn joint_fits_mode(mode: &Mode, spec: &JointBuilder) -> Result<(), (&'static str, &'static str)> {
    match mode {
        Mode::Fast(f) if matches!(f.solver, FastSolver::Exact { .. }) => {
            Err(("joint", "fast mode's exact solver has no joint rows: use solver=\"soft\" (the default) for joints"))
        }
        Mode::Fast(_) => Ok(()),
        Mode::Accurate(a) if a.persistent == Persistent::RestingForces => Err((
            "joint",
            "the chapter's resting forces know nothing of joints: use persistent contact steps (the default)",
        )),
        Mode::Accurate(_) if spec.softness.is_some() => {
            Err(("softness", "a joint's softness applies to fast mode (accurate mode holds joints exactly)"))
        }
        Mode::Accurate(_) => Ok(()),
    }
}

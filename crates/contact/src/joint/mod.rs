//! Joints between two bodies (or a body and the world) as the solvers see them: the kind and options
//! (`JointConstraint`), where the joint sits in world axes at the start of a step (`JointFrame`), and the constraint rows
//! its kind gives at a pose (`rows.rs`): the velocity Jacobian of each row, its position error and, for the
//! acceleration-level solve of accurate mode, the velocity product J' v. Fast mode's soft step solves the rows
//! with its contacts (`soft`); accurate mode's right-hand side solves them for forces.
//!
//! Conventions: a row's relative speed is J v = lin . (v_B - v_A) + ang_a . w_A + ang_b . w_B, a positive impulse
//! lambda adds lin lambda / m_B to B's velocity (and takes it from A's) and raises J v; a row's error C is zero
//! when the joint holds, and a one-sided row holds while C >= 0 with lambda >= 0.

mod rows;
mod solve;

pub use rows::{joint_rows, JointRow, RowKind, MAX_ROWS};
pub use solve::{delassus, factor, BoundedSolve, Factor, RowPart};

use nalgebra::{UnitQuaternion, Vector3};

/// What a joint allows (the user's word for it and the solvers': `JointBuilder` keeps one, the solvers read it).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// Spherical: the anchors coincide; any relative rotation.
    Ball,
    /// Revolute: the anchors coincide; rotation about the axis only.
    Hinge,
    /// Prismatic: no relative rotation; the anchors may part along the axis only.
    Slider,
    /// Fixed: no relative motion at all.
    Weld,
    /// Cylindrical (a piston): the anchors may part along the axis and B turn about it, nothing else.
    Piston,
    /// A drive alone (Bullet's motor constraint): nothing held, its motor drives B's spin about the axis relative
    /// to A (or, `linear`, B's anchor's slide along it).
    Drive { linear: bool },
    /// The anchors at `length` apart (None: their distance when the joint is added; the length in force is the
    /// constraint's `length`): a rigid rod, or a rope (`rope`) that only pulls and may slacken.
    Distance { length: Option<f64>, rope: bool },
}

/// A motor on a hinge (rad/s, N m) or a slider (m/s, N): it drives the joint's speed to `speed` with at most
/// `max_force`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointMotor {
    pub speed: f64,
    pub max_force: f64,
}

/// A spring on a hinge's angle (N m / rad, N m s / rad) or a slider's travel (N/m, N s/m) towards `target`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointSpring {
    pub stiffness: f64,
    pub damping: f64,
    pub target: f64,
}

/// A joint between bodies `a` and `b` (indices into the solver's bodies; a static body is the world).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointConstraint {
    pub a: usize,
    pub b: usize,
    pub kind: JointKind,
    /// The length a distance joint holds (m); the other kinds do not read it.
    pub length: f64,
    /// The joint's place at the step's start.
    pub frame: JointFrame,
    /// Lower and upper angle (hinge, rad) or travel (slider, piston, m).
    pub limits: Option<(f64, f64)>,
    /// A piston's lower and upper turn about its axis (rad).
    pub turn_limits: Option<(f64, f64)>,
    pub motor: Option<JointMotor>,
    pub spring: Option<JointSpring>,
    /// A soft joint's stiffness (Hz) and damping ratio; `None` is rigid.
    pub softness: Option<(f64, f64)>,
}

/// Where a joint sits, in world axes: arms from the centres of mass to the anchors, the axis and two directions
/// across it turning with A, the axis as B carries it, and the rotation error q_B (q_A q_ref)^-1 (identity when the
/// bodies are as they were when the joint was made).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointFrame {
    pub ra: Vector3<f64>,
    pub rb: Vector3<f64>,
    pub axis: Vector3<f64>,
    pub across: [Vector3<f64>; 2],
    pub axis_b: Vector3<f64>,
    pub error: UnitQuaternion<f64>,
}

impl JointFrame {
    /// The frame after A turned by `qa` and B by `qb` (world-frame rotations since the frame was taken).
    pub fn turned(&self, qa: &UnitQuaternion<f64>, qb: &UnitQuaternion<f64>) -> JointFrame {
        JointFrame {
            ra: qa * self.ra,
            rb: qb * self.rb,
            axis: qa * self.axis,
            across: [qa * self.across[0], qa * self.across[1]],
            axis_b: qb * self.axis_b,
            error: qb * self.error * qa.inverse(),
        }
    }
}

/// Accumulated impulses of a joint's rows, by row (`MAX_ROWS` slots; a kind uses the first few).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointImpulse(pub [f64; MAX_ROWS]);

/// Two unit directions across a unit axis, right-handed with it (across[0] x across[1] = axis).
pub fn across(axis: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let pick = if axis.x.abs() < 0.57735 { Vector3::x() } else { Vector3::y() };
    let p = axis.cross(&pick).normalize();
    let q = axis.cross(&p);
    [p, q]
}

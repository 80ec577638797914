//! Joints in the compiled model: each end resolved to a dynamic body's row or a fixed pose (the world, a static
//! body), the joint's frame at a state, and accurate mode's two uses of the rows: the constraint forces inside the
//! right-hand side (index-1: the accelerations keep every row's speed constant, K lambda = -(J a_free + J' v),
//! K = J M^-1 J^T), and the projection after each accepted step that puts positions and velocities back on the
//! joints (Gauss-Newton in the mass metric, then the velocity part), so that drift never builds up and the error
//! control keeps its meaning. Springs on hinges and sliders are forces (-k C - c C'). Fast mode's soft step reads
//! the same frames (`engine/fast/soft_solve.rs`).

use crate::model::layout::{get3, get_quat};
use crate::model::Model;
use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};
use tumble_contact::{joint_rows, Joint, JointFrame, JointRow, RowKind};

/// Where a joint end is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum JointEnd {
    /// A dynamic body (its row among the bodies).
    Body(usize),
    /// A fixed pose: the world (identity) or a static body.
    Fixed(Isometry3<f64>),
}

/// A joint resolved against the model: its ends, what it holds in each end's frame, and the solver's joint (whose
/// bodies and frame are filled in where it is used).
#[derive(Clone, Debug)]
pub(crate) struct CompiledJoint {
    pub a: JointEnd,
    pub b: JointEnd,
    pub anchor_a: Vector3<f64>,
    pub anchor_b: Vector3<f64>,
    pub axis_a: Vector3<f64>,
    pub across_a: [Vector3<f64>; 2],
    pub axis_b: Vector3<f64>,
    /// q_A^-1 q_B when the joint was made.
    pub reference: UnitQuaternion<f64>,
    pub joint: Joint,
}

/// A body's pose and velocities as the joint rows need them, with its world inverse inertia and mass.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EndState {
    pub x: Vector3<f64>,
    pub q: UnitQuaternion<f64>,
    pub v: Vector3<f64>,
    pub w: Vector3<f64>,
    pub inv_mass: f64,
    pub inv_inertia: Matrix3<f64>,
}

/// Rows with their joints' indices, and each joint's two ends.
type Rows = (Vec<(usize, JointRow)>, Vec<(EndState, EndState)>);

impl CompiledJoint {
    /// The joint's frame with its ends at `a` and `b`.
    pub fn frame(&self, a: &EndState, b: &EndState) -> JointFrame {
        JointFrame {
            ra: a.q * self.anchor_a,
            rb: b.q * self.anchor_b,
            axis: a.q * self.axis_a,
            across: [a.q * self.across_a[0], a.q * self.across_a[1]],
            axis_b: b.q * self.axis_b,
            error: b.q * (a.q * self.reference).inverse(),
        }
    }
}

impl Model {
    /// An end's state at y (the body kinematics of y computed afresh).
    pub(crate) fn end_state_of(&self, y: &[f64], end: JointEnd) -> EndState {
        match end {
            JointEnd::Body(j) => {
                let l = self.layout;
                let k = self.body_kin(y, j);
                let b = &self.bodies[j];
                EndState {
                    x: get3(y, l.bx(j)),
                    q: UnitQuaternion::new_normalize(get_quat(y, l.bq(j))),
                    v: k.velocity,
                    w: k.omega,
                    inv_mass: b.inv_mass,
                    inv_inertia: k.rot * b.inv_inertia * k.rot.transpose(),
                }
            }
            JointEnd::Fixed(p) => EndState {
                x: p.translation.vector,
                q: p.rotation,
                v: Vector3::zeros(),
                w: Vector3::zeros(),
                inv_mass: 0.0,
                inv_inertia: Matrix3::zeros(),
            },
        }
    }

    /// Every joint's rows at y (with velocity products when `velocity`), each with its joint's index.
    pub(crate) fn all_rows(&self, y: &[f64], velocity: bool) -> Rows {
        let mut rows = Vec::new();
        let mut ends = Vec::with_capacity(self.joints.len());
        let mut scratch = Vec::new();
        for (k, cj) in self.joints.iter().enumerate() {
            let (a, b) = (self.end_state_of(y, cj.a), self.end_state_of(y, cj.b));
            let frame = cj.frame(&a, &b);
            scratch.clear();
            let v = (a.v, a.w, b.v, b.w);
            joint_rows(&cj.joint, &frame, &a.x, &b.x, velocity.then_some(&v), &mut scratch);
            rows.extend(scratch.iter().map(|r| (k, *r)));
            ends.push((a, b));
        }
        (rows, ends)
    }

    /// The joints' rows at y and their largest errors: (rows, position error in m, angle error in rad), over the
    /// rows that hold the joints (one evaluation of the rows for both).
    pub(crate) fn joint_errors(&self, y: &[f64]) -> (usize, (f64, f64)) {
        let (rows, _) = self.all_rows(y, false);
        let (mut lin, mut ang) = (0.0f64, 0.0f64);
        for (_, r) in rows.iter().filter(|(_, r)| r.kind == RowKind::Equality) {
            if r.lin == Vector3::zeros() {
                ang = ang.max(r.error.abs());
            } else {
                lin = lin.max(r.error.abs());
            }
        }
        (rows.len(), (lin, ang))
    }
}

/// The world's joints resolved against the model's bodies (`b_index`: a dynamic body's row).
pub(crate) fn compile_joints(
    joints: &crate::handle::Arena<crate::joint::Joint>,
    bodies: &crate::handle::Arena<crate::body::RigidBody>,
    b_index: &std::collections::HashMap<crate::spring::BodyHandle, usize>,
) -> Vec<CompiledJoint> {
    use crate::joint::JointType;
    let end = |h: Option<crate::spring::BodyHandle>| match h {
        None => JointEnd::Fixed(Isometry3::identity()),
        Some(h) => match b_index.get(&h) {
            Some(&j) => JointEnd::Body(j),
            None => {
                let b = bodies.get(h).expect("validated on insertion");
                JointEnd::Fixed(Isometry3::from_parts(b.position.into(), b.orientation))
            }
        },
    };
    joints
        .iter()
        .map(|(_, j)| {
            let s = &j.spec;
            let axis_a = s.axis.normalize();
            let kind = match s.kind {
                JointType::Ball => tumble_contact::JointKind::Ball,
                JointType::Hinge => tumble_contact::JointKind::Hinge,
                JointType::Slider => tumble_contact::JointKind::Slider,
                JointType::Weld => tumble_contact::JointKind::Weld,
                JointType::Distance { rope, .. } => tumble_contact::JointKind::Distance { length: j.length, rope },
            };
            let joint = Joint {
                a: 0,
                b: 0,
                kind,
                frame: JointFrame {
                    ra: Vector3::zeros(),
                    rb: Vector3::zeros(),
                    axis: axis_a,
                    across: tumble_contact::across(&axis_a),
                    axis_b: axis_a,
                    error: UnitQuaternion::identity(),
                },
                limits: s.limits,
                motor: s.motor.map(|m| tumble_contact::JointMotor { speed: m.speed, max_force: m.max_force }),
                spring: s.spring.map(|p| tumble_contact::JointSpring {
                    stiffness: p.stiffness,
                    damping: p.damping,
                    target: p.target,
                }),
                softness: s.softness,
            };
            CompiledJoint {
                a: end(s.a),
                b: end(s.b),
                anchor_a: s.anchor_a,
                anchor_b: s.anchor_b,
                axis_a,
                across_a: tumble_contact::across(&axis_a),
                axis_b: j.axis_b,
                reference: j.reference,
                joint,
            }
        })
        .collect()
}

impl Model {
    /// The joints' rows for a velocity step of h from y (accurate mode's contact steps): holding rows J v = 0 at the
    /// step's end (the position error is projected away after the step, `project_joints`: a velocity that pulls it
    /// back would differ between a step and its two halves by the error itself, at any step size), limits and ropes
    /// J v >= what closes them within the step, motors their speed within their force over h; springs are forces.
    /// A dynamic end is its actor, a fixed end an extra fixed actor numbered from `first_extra` and returned.
    pub(crate) fn bilateral_rows(
        &self,
        y: &[f64],
        h: f64,
        first_extra: usize,
    ) -> (Vec<tumble_contact::BilateralRow>, Vec<tumble_contact::BodyState>) {
        let l = self.layout;
        let (mut out, mut extra) = (Vec::new(), Vec::new());
        let mut scratch = Vec::new();
        for cj in &self.joints {
            let mut index = |end: JointEnd| match end {
                JointEnd::Body(j) => l.particles + j,
                JointEnd::Fixed(p) => {
                    extra.push(tumble_contact::BodyState::fixed(nalgebra::Point3::from(p.translation.vector)));
                    first_extra + extra.len() - 1
                }
            };
            let (a, b) = (index(cj.a), index(cj.b));
            let (ea, eb) = (self.end_state_of(y, cj.a), self.end_state_of(y, cj.b));
            scratch.clear();
            joint_rows(&cj.joint, &cj.frame(&ea, &eb), &ea.x, &eb.x, None, &mut scratch);
            for r in &scratch {
                use tumble_contact::BilateralKind;
                let (kind, speed) = match r.kind {
                    RowKind::Equality => (BilateralKind::Equal, 0.0),
                    // a limit may close within the step, and holds at it (its overshoot is projected away)
                    RowKind::Lower => {
                        // only a limit the step can reach: one far from it would ask for a speed of its gap over h,
                        // which grows without bound as the steps shrink and swamps the program's scale
                        let closing = -(r.lin.dot(&(eb.v - ea.v)) + r.ang_a.dot(&ea.w) + r.ang_b.dot(&eb.w));
                        if r.error > 2.0 * h * closing.max(0.0) {
                            continue;
                        }
                        (BilateralKind::AtLeast, if r.error > 0.0 { -r.error / h } else { 0.0 })
                    }
                    RowKind::Motor { speed, max_force } => (BilateralKind::Motor { max_impulse: max_force * h }, speed),
                    RowKind::Spring { .. } => continue,
                };
                out.push(tumble_contact::BilateralRow {
                    a,
                    b,
                    lin: r.lin,
                    ang_a: r.ang_a,
                    ang_b: r.ang_b,
                    speed,
                    kind,
                });
            }
        }
        (out, extra)
    }
}

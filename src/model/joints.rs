//! Joints in the compiled model: each end resolved to a dynamic body's index or a fixed pose (the world, a static
//! body), the joint's frame at a state, its rows there and their errors. The engines solve the rows their own way:
//! accurate mode as forces in its equations of motion and a projection after each step
//! (`engine/accurate/joint_forces.rs`), fast mode's soft step as rows of its substeps (`engine/fast/soft_solve.rs`).

use crate::model::layout::{get3, get_quat, Layout};
use crate::model::{Model, ResolvedBody};
use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};
use tumble_collide::rotated_tensor;
use tumble_contact::{joint_rows, JointConstraint, JointFrame, JointRow, RowKind};

/// A joint resolved against the model: its ends, what it holds in each end's frame, and the solver's joint (whose
/// bodies and frame are filled in where it is used).
#[derive(Clone, Debug)]
pub(crate) struct CompiledJoint {
    pub a: ResolvedBody,
    pub b: ResolvedBody,
    pub anchor_a: Vector3<f64>,
    pub anchor_b: Vector3<f64>,
    pub axis_a: Vector3<f64>,
    pub across_a: [Vector3<f64>; 2],
    pub axis_b: Vector3<f64>,
    /// q_A^-1 q_B when the joint was made.
    pub reference: UnitQuaternion<f64>,
    pub joint: JointConstraint,
    /// When it breaks (`breaking.rs`), and whether it has: a broken joint gives no rows and joins nothing.
    pub breaking: Option<crate::joint::Breaking>,
    pub broken: bool,
    /// Whether its bodies collide with each other.
    pub collide: bool,
    /// Whether it binds its bodies into one piece with those other such joints bind (`JointBuilder::cluster`).
    pub cluster: bool,
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
    /// Its two ends' actor indices, when both are dynamic bodies.
    pub fn actors(&self, l: Layout) -> Option<(usize, usize)> {
        self.a.actor(l).zip(self.b.actor(l))
    }

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
    pub(crate) fn end_state_of(&self, y: &[f64], end: ResolvedBody) -> EndState {
        match end {
            ResolvedBody::Dynamic(j) => {
                let l = self.layout;
                let k = self.body_kin(y, j);
                let b = &self.bodies[j];
                EndState {
                    x: get3(y, l.bx(j)),
                    q: UnitQuaternion::new_normalize(get_quat(y, l.bq(j))),
                    v: k.velocity,
                    w: k.omega,
                    // a kinematic end moves but takes no push
                    inv_mass: if b.kinematic.is_some() { 0.0 } else { b.inv_mass },
                    inv_inertia: if b.kinematic.is_some() {
                        Matrix3::zeros()
                    } else {
                        rotated_tensor(&k.rot, &b.inv_inertia)
                    },
                }
            }
            ResolvedBody::Fixed(p) => EndState {
                x: p.translation.vector,
                q: p.rotation,
                v: Vector3::zeros(),
                w: Vector3::zeros(),
                inv_mass: 0.0,
                inv_inertia: Matrix3::zeros(),
            },
        }
    }

    /// The joints that hold (not broken), with their indices.
    pub(crate) fn holding_joints(&self) -> impl Iterator<Item = (usize, &CompiledJoint)> {
        self.joints.iter().enumerate().filter(|(_, j)| !j.broken)
    }

    /// Every holding joint's rows at y (with velocity products when `velocity`), each with its joint's index; the
    /// ends of every joint.
    pub(crate) fn all_rows(&self, y: &[f64], velocity: bool) -> Rows {
        let mut rows = Vec::new();
        let mut ends = Vec::with_capacity(self.joints.len());
        let mut scratch = Vec::new();
        for (k, cj) in self.joints.iter().enumerate() {
            let (a, b) = (self.end_state_of(y, cj.a), self.end_state_of(y, cj.b));
            ends.push((a, b));
            if cj.broken {
                continue;
            }
            let frame = cj.frame(&a, &b);
            scratch.clear();
            let v = (a.v, a.w, b.v, b.w);
            joint_rows(&cj.joint, &frame, &a.x, &b.x, velocity.then_some(&v), &mut scratch);
            rows.extend(scratch.iter().map(|r| (k, *r)));
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

/// The world's joints resolved against the model's bodies (`b_index`: a dynamic body's index).
pub(crate) fn compile_joints(
    joints: &crate::handle::Arena<crate::joint::Joint>,
    bodies: &crate::handle::Arena<crate::body::RigidBody>,
    b_index: &std::collections::HashMap<crate::spring::BodyHandle, usize>,
) -> Vec<CompiledJoint> {
    let end = |h: Option<crate::spring::BodyHandle>| match h {
        None => ResolvedBody::Fixed(Isometry3::identity()),
        Some(h) => ResolvedBody::of(bodies.get(h).expect("validated on insertion"), b_index.get(&h).copied()),
    };
    joints
        .iter()
        .map(|(_, j)| {
            let s = &j.spec;
            let axis_a = s.axis.normalize();
            let joint = JointConstraint {
                a: 0,
                b: 0,
                kind: s.kind,
                length: j.length,
                frame: JointFrame {
                    ra: Vector3::zeros(),
                    rb: Vector3::zeros(),
                    axis: axis_a,
                    across: tumble_contact::across(&axis_a),
                    axis_b: axis_a,
                    error: UnitQuaternion::identity(),
                },
                limits: s.limits,
                turn_limits: s.turn_limits,
                motor: s.motor,
                spring: s.spring,
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
                breaking: s.breaking,
                broken: j.broken,
                collide: s.collide,
                cluster: s.cluster,
            }
        })
        .collect()
}

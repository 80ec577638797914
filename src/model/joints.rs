//! Joints in the compiled model: each end resolved to a dynamic body's row or a fixed pose (the world, a static
//! body), the joint's frame at a state, and accurate mode's two uses of the rows: the constraint forces inside the
//! right-hand side (index-1: the accelerations keep every row's speed constant, K lambda = -(J a_free + J' v),
//! K = J M^-1 J^T), and the projection after each accepted step that puts positions and velocities back on the
//! joints (Gauss-Newton in the mass metric, then the velocity part), so that drift never builds up and the error
//! control keeps its meaning. Springs on hinges and sliders are forces (-k C - c C'). Fast mode's soft step reads
//! the same frames (`engine/fast/soft_solve.rs`).

use crate::model::layout::{add3, get3, get_quat, set_quat};
use crate::model::Model;
use nalgebra::{DMatrix, DVector, Isometry3, Matrix3, UnitQuaternion, Vector3};
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
/// A row's part on one end: the body (if it moves), linear and angular.
type Part = (Option<usize>, Vector3<f64>, Vector3<f64>);

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
    fn all_rows(&self, y: &[f64], velocity: bool) -> Rows {
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

    /// The largest joint errors at y: position (m) and angle (rad), over the rows that hold the joints.
    pub(crate) fn joint_errors(&self, y: &[f64]) -> (f64, f64) {
        let (rows, _) = self.all_rows(y, false);
        let (mut lin, mut ang) = (0.0f64, 0.0f64);
        for (_, r) in rows.iter().filter(|(_, r)| r.kind == RowKind::Equality) {
            if r.lin == Vector3::zeros() {
                ang = ang.max(r.error.abs());
            } else {
                lin = lin.max(r.error.abs());
            }
        }
        (lin, ang)
    }

    /// The number of rows the joints give.
    pub(crate) fn joint_row_count(&self, y: &[f64]) -> usize {
        self.all_rows(y, false).0.len()
    }

    /// The rows' K = J M^-1 J^T (rows of `rows`, over the ends of their joints).
    fn delassus(&self, rows: &[(usize, JointRow)], ends: &[(EndState, EndState)]) -> DMatrix<f64> {
        let n = rows.len();
        let mut k = DMatrix::zeros(n, n);
        // each row's parts on each dynamic body: (body, linear, angular)
        let parts: Vec<[Part; 2]> = rows
            .iter()
            .map(|(j, r)| {
                let cj = &self.joints[*j];
                let body = |e: JointEnd| match e {
                    JointEnd::Body(i) => Some(i),
                    JointEnd::Fixed(_) => None,
                };
                [(body(cj.a), -r.lin, r.ang_a), (body(cj.b), r.lin, r.ang_b)]
            })
            .collect();
        for i in 0..n {
            let (ji, _) = rows[i];
            for m in i..n {
                let mut sum = 0.0;
                for (side_i, (bi, li, ai)) in parts[i].iter().enumerate() {
                    let Some(bi) = bi else { continue };
                    for (bm, lm, am) in parts[m].iter() {
                        if *bm == Some(*bi) {
                            let e = if side_i == 0 { &ends[ji].0 } else { &ends[ji].1 };
                            sum += e.inv_mass * li.dot(lm) + ai.dot(&(e.inv_inertia * am));
                        }
                    }
                }
                k[(i, m)] = sum;
                k[(m, i)] = sum;
            }
        }
        k
    }

    /// Solves K x = r, K positive semidefinite (a redundant joint makes it singular: then the least-norm answer of
    /// a slightly regularised K).
    fn solve_rows(k: DMatrix<f64>, r: DVector<f64>) -> DVector<f64> {
        if let Some(c) = k.clone().cholesky() {
            return c.solve(&r);
        }
        let scale = k.diagonal().amax().max(1e-300);
        let n = k.nrows();
        let reg = k + DMatrix::identity(n, n) * (1e-12 * scale);
        match reg.clone().cholesky() {
            Some(c) => c.solve(&r),
            None => reg.pseudo_inverse(1e-14 * scale).map(|p| p * r).unwrap_or_else(|_| DVector::zeros(n)),
        }
    }

    /// Adds the joints' constraint forces and springs to the p rates `dp` (accurate mode's right-hand side).
    pub(crate) fn add_joint_forces(&self, y: &[f64], dp: &mut [f64]) {
        if self.joints.is_empty() {
            return;
        }
        let (l, q) = (self.layout, self.layout.positions());
        let (rows, ends) = self.all_rows(y, true);
        let apply = |dp: &mut [f64], j: usize, r: &JointRow, lambda: f64| {
            let cj = &self.joints[j];
            if let JointEnd::Body(i) = cj.a {
                add3(dp, l.bp(i) - q, &(-r.lin * lambda));
                add3(dp, l.bl(i) - q, &(r.ang_a * lambda));
            }
            if let JointEnd::Body(i) = cj.b {
                add3(dp, l.bp(i) - q, &(r.lin * lambda));
                add3(dp, l.bl(i) - q, &(r.ang_b * lambda));
            }
        };
        // springs: forces of the state alone
        let speed = |j: usize, r: &JointRow| {
            let (a, b) = &ends[j];
            r.lin.dot(&(b.v - a.v)) + r.ang_a.dot(&a.w) + r.ang_b.dot(&b.w)
        };
        for (j, r) in &rows {
            if let RowKind::Spring { stiffness, damping } = r.kind {
                apply(dp, *j, r, -stiffness * r.error - damping * speed(*j, r));
            }
        }
        let held: Vec<(usize, JointRow)> = rows.into_iter().filter(|(_, r)| r.kind == RowKind::Equality).collect();
        if held.is_empty() {
            return;
        }
        // each end's acceleration under the forces so far (Euler's equations with L = I w)
        let accel = |e: JointEnd, s: &EndState, dp: &[f64]| match e {
            JointEnd::Body(i) => {
                let f = get3(dp, l.bp(i) - q);
                let tau = get3(dp, l.bl(i) - q);
                let lw = s.inv_inertia.try_inverse().unwrap_or_else(Matrix3::zeros) * s.w;
                (f * s.inv_mass, s.inv_inertia * (tau - s.w.cross(&lw)))
            }
            JointEnd::Fixed(_) => (Vector3::zeros(), Vector3::zeros()),
        };
        let mut rhs = DVector::zeros(held.len());
        for (n, (j, r)) in held.iter().enumerate() {
            let cj = &self.joints[*j];
            let (aa, alpha_a) = accel(cj.a, &ends[*j].0, dp);
            let (ab, alpha_b) = accel(cj.b, &ends[*j].1, dp);
            rhs[n] = -(r.lin.dot(&(ab - aa)) + r.ang_a.dot(&alpha_a) + r.ang_b.dot(&alpha_b) + r.curvature);
        }
        let lambda = Self::solve_rows(self.delassus(&held, &ends), rhs);
        for ((j, r), &lam) in held.iter().zip(lambda.iter()) {
            apply(dp, *j, r, lam);
        }
    }

    /// Puts positions, then velocities, back on the joints (accurate mode, after an accepted step): at most four
    /// Gauss-Newton corrections in the mass metric while an error exceeds `tolerance` (m or rad), then the velocity
    /// correction that removes every row's speed at least kinetic energy. Returns whether y changed.
    pub(crate) fn project_joints(&self, y: &mut [f64], tolerance: f64) -> bool {
        if self.joints.is_empty() {
            return false;
        }
        let l = self.layout;
        let mut changed = false;
        for _ in 0..4 {
            let (rows, ends) = self.all_rows(y, false);
            let held: Vec<(usize, JointRow)> = rows.into_iter().filter(|(_, r)| r.kind == RowKind::Equality).collect();
            if held.iter().all(|(_, r)| r.error.abs() <= tolerance) {
                break;
            }
            let c = DVector::from_iterator(held.len(), held.iter().map(|(_, r)| -r.error));
            let delta = Self::solve_rows(self.delassus(&held, &ends), c);
            for ((j, r), &d) in held.iter().zip(delta.iter()) {
                let cj = &self.joints[*j];
                for (end, lin, ang, s) in [(cj.a, -r.lin, r.ang_a, &ends[*j].0), (cj.b, r.lin, r.ang_b, &ends[*j].1)] {
                    if let JointEnd::Body(i) = end {
                        add3(y, l.bx(i), &(lin * (d * s.inv_mass)));
                        let turn = UnitQuaternion::from_scaled_axis(s.inv_inertia * ang * d);
                        let qn = turn * UnitQuaternion::new_normalize(get_quat(y, l.bq(i)));
                        set_quat(y, l.bq(i), &qn);
                    }
                }
            }
            changed = true;
        }
        let (rows, ends) = self.all_rows(y, false);
        let held: Vec<(usize, JointRow)> = rows.into_iter().filter(|(_, r)| r.kind == RowKind::Equality).collect();
        let speeds: Vec<f64> = held
            .iter()
            .map(|(j, r)| {
                let (a, b) = &ends[*j];
                r.lin.dot(&(b.v - a.v)) + r.ang_a.dot(&a.w) + r.ang_b.dot(&b.w)
            })
            .collect();
        if speeds.iter().all(|s| s.abs() <= tolerance) {
            return changed;
        }
        let mu = Self::solve_rows(self.delassus(&held, &ends), -DVector::from_vec(speeds));
        for ((j, r), &m) in held.iter().zip(mu.iter()) {
            let cj = &self.joints[*j];
            for (end, lin, ang) in [(cj.a, -r.lin, r.ang_a), (cj.b, r.lin, r.ang_b)] {
                if let JointEnd::Body(i) = end {
                    add3(y, l.bp(i), &(lin * m));
                    add3(y, l.bl(i), &(ang * m));
                }
            }
        }
        true
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
    /// The rigid joints' holding rows for a velocity step from y (accurate mode's contact steps): J v = 0 at the
    /// step's end (the position error is projected away after the step, `project_joints`: a velocity that pulls it
    /// back would differ between a step and its two halves by the error itself, at any step size); a dynamic end is
    /// its actor, a fixed end an extra fixed actor numbered from `first_extra` and returned.
    pub(crate) fn bilateral_rows(
        &self,
        y: &[f64],
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
            for r in scratch.iter().filter(|r| r.kind == RowKind::Equality) {
                out.push(tumble_contact::BilateralRow { a, b, lin: r.lin, ang_a: r.ang_a, ang_b: r.ang_b, speed: 0.0 });
            }
        }
        (out, extra)
    }
}

//! A joint's constraint rows at a pose: for each row its Jacobian (lin, ang_a, ang_b), its position error, how it
//! is solved (`RowKind`) and, given the velocities, its velocity product J' v (the acceleration the row's speed
//! has with no acceleration of either body; accurate mode's forces need it). Rows come in a fixed order for each
//! kind and set of options, so that a row's slot names it from step to step (warm starts).
//!
//! The rows: a coinciding anchor (ball, hinge, weld) is three rows along the world axes; a hinge's axis is held by
//! two rows across it (A's directions against B's axis); weld and slider hold the rotation by three rows of relative
//! angular velocity along the world axes, their error the rotation vector of the frame's rotation error; a slider
//! holds its anchor on A's axis by two rows across it; a distance is one row along the line between the anchors.
//! Limits are one-sided rows on the hinge angle or slider travel (and a piston's turn); a motor is a row on their speed; a spring a soft
//! row on their value.

use super::{JointConstraint, JointFrame, JointKind};
use nalgebra::Vector3;

/// Most rows one joint gives (a piston with limits on its travel and its turn, a motor and a spring).
pub const MAX_ROWS: usize = 10;

/// How a row is solved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RowKind {
    /// J v = 0 and C = 0, any impulse.
    Equality,
    /// C >= 0, impulse >= 0 (a limit, a rope).
    Lower,
    /// J v = speed, |impulse| <= max_force h.
    Motor { speed: f64, max_force: f64 },
    /// A spring on C: force -stiffness C - damping J v.
    Spring { stiffness: f64, damping: f64 },
}

/// One constraint row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointRow {
    /// Its place among the joint's rows (warm-start slot).
    pub slot: usize,
    pub lin: Vector3<f64>,
    pub ang_a: Vector3<f64>,
    pub ang_b: Vector3<f64>,
    /// Position error C (zero when held).
    pub error: f64,
    pub kind: RowKind,
    /// J' v at the velocities given (zero without them).
    pub curvature: f64,
}

impl JointRow {
    /// The row's speed J v = lin . (v_B - v_A) + ang_a . w_A + ang_b . w_B.
    #[inline]
    pub fn speed(&self, va: &Vector3<f64>, wa: &Vector3<f64>, vb: &Vector3<f64>, wb: &Vector3<f64>) -> f64 {
        self.lin.dot(&(vb - va)) + self.ang_a.dot(wa) + self.ang_b.dot(wb)
    }
}

/// Velocities of A and B: (v_A, w_A, v_B, w_B).
pub type PairVelocity = (Vector3<f64>, Vector3<f64>, Vector3<f64>, Vector3<f64>);

/// The rows of `joint` placed at `frame`, with the centres of mass at `xa` and `xb`; with `velocity`, each row's
/// J' v as well. Rows are appended to `out`.
pub fn joint_rows(
    joint: &JointConstraint,
    frame: &JointFrame,
    xa: &Vector3<f64>,
    xb: &Vector3<f64>,
    velocity: Option<&PairVelocity>,
    out: &mut Vec<JointRow>,
) {
    let f = frame;
    let d = (xb + f.rb) - (xa + f.ra);
    let zero = Vector3::zeros();
    let (va, wa, vb, wb) = velocity.copied().unwrap_or((zero, zero, zero, zero));
    let with_velocity = velocity.is_some();
    // relative velocity of B's anchor against A's, and each anchor's centripetal acceleration
    let d_dot = vb + wb.cross(&f.rb) - va - wa.cross(&f.ra);
    let spin = wb.cross(&wb.cross(&f.rb)) - wa.cross(&wa.cross(&f.ra));
    let mut slot = 0usize;
    let mut push = |lin: Vector3<f64>, ang_a: Vector3<f64>, ang_b: Vector3<f64>, error: f64, kind: RowKind, k: f64| {
        out.push(JointRow { slot, lin, ang_a, ang_b, error, kind, curvature: if with_velocity { k } else { 0.0 } });
        slot += 1;
    };
    // a row along a world direction e at the anchors
    let point = |e: Vector3<f64>| (e, -f.ra.cross(&e), f.rb.cross(&e), e.dot(&d), e.dot(&spin));
    // a row along e turning with A (slider): A's arm reaches to B's anchor
    let carried = |e: Vector3<f64>| {
        let k = wa.cross(&wa.cross(&e)).dot(&d) + 2.0 * wa.cross(&e).dot(&d_dot) + e.dot(&spin);
        (e, -(f.ra + d).cross(&e), f.rb.cross(&e), e.dot(&d), k)
    };
    // rotation error as a rotation vector, and the hinge angle about the axis
    let angle = f.error.scaled_axis();
    let twist = |e: Vector3<f64>| {
        let q = f.error.quaternion();
        let s = q.imag().dot(&e);
        2.0 * s.atan2(q.w)
    };
    let kinds = match joint.kind {
        JointKind::Ball | JointKind::Hinge | JointKind::Weld => {
            for e in [Vector3::x(), Vector3::y(), Vector3::z()] {
                let (lin, a, b, c, k) = point(e);
                push(lin, a, b, c, RowKind::Equality, k);
            }
            joint.kind
        }
        JointKind::Slider | JointKind::Piston => {
            for e in f.across {
                let (lin, a, b, c, k) = carried(e);
                push(lin, a, b, c, RowKind::Equality, k);
            }
            joint.kind
        }
        JointKind::Drive { linear } => {
            // its motor's row alone: the slide along the axis, or the spin about it
            if let Some(m) = joint.motor {
                let kind = RowKind::Motor { speed: m.speed, max_force: m.max_force };
                if linear {
                    let (lin, a, b, travel, k) = carried(f.axis);
                    push(lin, a, b, travel, kind, k);
                } else {
                    let k = wa.cross(&f.axis).dot(&(wb - wa));
                    push(zero, -f.axis, f.axis, 0.0, kind, k);
                }
            }
            joint.kind
        }
        JointKind::Distance { rope, .. } => {
            let length = joint.length;
            let len = d.norm();
            let n = if len > 1e-12 * (1.0 + f.ra.norm() + f.rb.norm()) { d / len } else { f.axis };
            let bend = if len > 0.0 { (d_dot.norm_squared() - n.dot(&d_dot).powi(2)) / len } else { 0.0 };
            let k = n.dot(&spin) + bend;
            let (a, b) = (-f.ra.cross(&n), f.rb.cross(&n));
            if rope {
                push(-n, -a, -b, length - len, RowKind::Lower, -k);
            } else {
                push(n, a, b, len - length, RowKind::Equality, k);
            }
            joint.kind
        }
    };
    match kinds {
        JointKind::Hinge | JointKind::Piston => {
            for p in f.across {
                let g = p.cross(&f.axis_b);
                let k = wa.cross(&wa.cross(&p)).dot(&f.axis_b)
                    + 2.0 * wa.cross(&p).dot(&wb.cross(&f.axis_b))
                    + p.dot(&wb.cross(&wb.cross(&f.axis_b)));
                push(zero, g, -g, p.dot(&f.axis_b), RowKind::Equality, k);
            }
            if kinds == JointKind::Piston {
                // its options on the travel along the axis, as a slider's, then its turn's limits, as a hinge's
                let (lin, a, b, travel, k) = carried(f.axis);
                options(joint, travel, (lin, a, b), k, &mut push);
                if let Some((lo, hi)) = joint.turn_limits {
                    let (theta, k) = (twist(f.axis), wa.cross(&f.axis).dot(&(wb - wa)));
                    push(zero, -f.axis, f.axis, theta - lo, RowKind::Lower, k);
                    push(zero, f.axis, -f.axis, hi - theta, RowKind::Lower, -k);
                }
            } else {
                let theta = twist(f.axis);
                let k = wa.cross(&f.axis).dot(&(wb - wa));
                let row = (zero, -f.axis, f.axis);
                options(joint, theta, row, k, &mut push);
            }
        }
        JointKind::Slider | JointKind::Weld => {
            for (i, e) in [Vector3::x(), Vector3::y(), Vector3::z()].into_iter().enumerate() {
                push(zero, -e, e, angle[i], RowKind::Equality, 0.0);
            }
            if kinds == JointKind::Slider {
                let (lin, a, b, travel, k) = carried(f.axis);
                options(joint, travel, (lin, a, b), k, &mut push);
            }
        }
        _ => {}
    }
}

/// A hinge's or slider's limit, motor and spring rows on its value `x` along the row `(lin, ang_a, ang_b)` whose
/// velocity product is `k`.
fn options(
    joint: &JointConstraint,
    x: f64,
    (lin, a, b): (Vector3<f64>, Vector3<f64>, Vector3<f64>),
    k: f64,
    push: &mut impl FnMut(Vector3<f64>, Vector3<f64>, Vector3<f64>, f64, RowKind, f64),
) {
    if let Some((lo, hi)) = joint.limits {
        push(lin, a, b, x - lo, RowKind::Lower, k);
        push(-lin, -a, -b, hi - x, RowKind::Lower, -k);
    }
    if let Some(m) = joint.motor {
        push(lin, a, b, 0.0, RowKind::Motor { speed: m.speed, max_force: m.max_force }, k);
    }
    if let Some(s) = joint.spring {
        push(lin, a, b, x - s.target, RowKind::Spring { stiffness: s.stiffness, damping: s.damping }, k);
    }
}

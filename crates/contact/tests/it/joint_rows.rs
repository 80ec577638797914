//! Seeded random checks of the joint rows against their definitions: each row's J v is the time derivative of
//! its position error, and its velocity product J' v the time derivative of J v at constant velocities, both by
//! central differences along the motion, at random poses, arms, axes and velocities of every kind and option.

use nalgebra::{UnitQuaternion, Vector3};
use tumble_contact::{
    across, joint_rows, JointConstraint, JointFrame, JointKind, JointMotor, JointRow, JointSpring, RowKind, MAX_ROWS,
};

struct Rng(u64);
impl Rng {
    fn f(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn v(&mut self, s: f64) -> Vector3<f64> {
        Vector3::new(self.f(-s, s), self.f(-s, s), self.f(-s, s))
    }
}

/// A pose of both bodies after time t of constant velocities: centres and the frame.
fn at(
    t: f64,
    j: &JointConstraint,
    x: &[Vector3<f64>; 2],
    v: &(Vector3<f64>, Vector3<f64>, Vector3<f64>, Vector3<f64>),
) -> Vec<JointRow> {
    let (va, wa, vb, wb) = *v;
    let qa = UnitQuaternion::from_scaled_axis(wa * t);
    let qb = UnitQuaternion::from_scaled_axis(wb * t);
    let frame = j.frame.turned(&qa, &qb);
    let mut out = Vec::new();
    joint_rows(j, &frame, &(x[0] + va * t), &(x[1] + vb * t), Some(v), &mut out);
    out
}

fn speed(r: &JointRow, v: &(Vector3<f64>, Vector3<f64>, Vector3<f64>, Vector3<f64>)) -> f64 {
    r.lin.dot(&(v.2 - v.0)) + r.ang_a.dot(&v.1) + r.ang_b.dot(&v.3)
}

#[test]
fn rows_are_the_derivatives_of_their_errors() {
    let mut rng = Rng(2026);
    let kinds = [
        JointKind::Ball,
        JointKind::Hinge,
        JointKind::Slider,
        JointKind::Weld,
        JointKind::Piston,
        JointKind::Distance { length: Some(0.7), rope: false },
        JointKind::Distance { length: Some(0.7), rope: true },
    ];
    let mut checked = 0;
    for case in 0..600 {
        let kind = kinds[case % kinds.len()];
        let axis = rng.v(1.0).normalize();
        // even cases: bodies as the joint was made (a hinge turned about its axis), where the angular rows' errors
        // are exact; odd ones: anywhere (only the rows whose errors are exact everywhere are compared)
        let held = case % 2 == 0;
        let error = if held && matches!(kind, JointKind::Slider | JointKind::Weld) {
            UnitQuaternion::identity()
        } else if held {
            UnitQuaternion::from_scaled_axis(axis * rng.f(-2.5, 2.5))
        } else {
            UnitQuaternion::from_scaled_axis(rng.v(1.5))
        };
        let frame = JointFrame {
            ra: rng.v(1.0),
            rb: rng.v(1.0),
            axis,
            across: across(&axis),
            axis_b: if held { axis } else { (axis + rng.v(0.3)).normalize() },
            error,
        };
        let joint = JointConstraint {
            a: 0,
            b: 1,
            kind,
            length: 0.7,
            frame,
            limits: Some((-1.0, 1.0)),
            turn_limits: (kind == JointKind::Piston).then_some((-0.5, 0.7)),
            motor: Some(JointMotor { speed: 1.0, max_force: 5.0 }),
            spring: Some(JointSpring { stiffness: 3.0, damping: 0.1, target: 0.2 }),
            softness: None,
        };
        let x = [rng.v(2.0), rng.v(2.0)];
        let (wa, mut wb) = (rng.v(2.0), rng.v(2.0));
        if held && matches!(kind, JointKind::Slider | JointKind::Weld) {
            wb = wa;
        } else if held && matches!(kind, JointKind::Hinge | JointKind::Piston) {
            wb = wa + axis * rng.f(-2.0, 2.0);
        }
        let v = (rng.v(2.0), wa, rng.v(2.0), wb);
        let rows = at(0.0, &joint, &x, &v);
        assert!(rows.len() <= MAX_ROWS);
        let h = 1e-5;
        let (plus, minus) = (at(h, &joint, &x, &v), at(-h, &joint, &x, &v));
        for (k, r) in rows.iter().enumerate() {
            assert_eq!(r.slot, k);
            let angular_only = r.lin == Vector3::zeros();
            // (a piston's angular rows before its turn's limits are the hinge's two across the axis, exact everywhere;
            // its turn, like a hinge's angle, is the twist of the rotation error: exact when held to the axis)
            let exact_error =
                held || !angular_only || (kind == JointKind::Hinge && k < 5) || (kind == JointKind::Piston && k < 8);
            // central differences of smooth functions of size ~1 over h = 1e-5: truncation ~h^2 = 1e-10, rounding
            // ~1e-16 / 1e-5 = 1e-11; 1e-7 leaves room for the second derivatives' size (speeds up to ~6)
            if exact_error && !matches!(r.kind, RowKind::Motor { .. }) {
                let rate = (plus[k].error - minus[k].error) / (2.0 * h);
                assert!(
                    (rate - speed(r, &v)).abs() < 1e-7,
                    "case {case} {kind:?} row {k}: dC/dt {rate} vs J v {}",
                    speed(r, &v)
                );
                checked += 1;
            }
            let jv_rate = (speed(&plus[k], &v) - speed(&minus[k], &v)) / (2.0 * h);
            assert!(
                (jv_rate - r.curvature).abs() < 1e-6,
                "case {case} {kind:?} row {k}: d(Jv)/dt {jv_rate} vs {}",
                r.curvature
            );
        }
    }
    assert!(checked > 2000, "{checked}");
}

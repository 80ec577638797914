//! Rolling and torsional resistance as rows of the velocity step: each contact with a coefficient and a lagged
//! normal impulse p resists the bodies' relative turn with an angular impulse of at most the coefficient times p
//! times the rolling radius (`Contact::rolling_radius`), as far as it stops the turn (a motor row of target speed
//! zero, whose impulse is bounded, held in the same program as the contacts). Rolling is resisted along the axis
//! the bodies roll about at the step's start and across it, each bounded alone; torsion about the normal.

use super::problem::{BilateralKind, BilateralRow};
use crate::body::BodyState;
use crate::contact::{tangents, Contact};
use nalgebra::Vector3;

/// The rows of contact `c` at lagged normal impulse `bound` (none without a coefficient, a bound, or a body that
/// turns).
pub(crate) fn resistance_rows(c: &Contact, bodies: &[BodyState], bound: f64, out: &mut Vec<BilateralRow>) {
    if bound <= 0.0 || (c.rolling_resistance == 0.0 && c.torsional_resistance == 0.0) {
        return;
    }
    let radius = c.rolling_radius(bodies);
    if radius == 0.0 {
        return;
    }
    let n = c.normal.into_inner();
    let turn = bodies[c.b].angular_velocity - bodies[c.a].angular_velocity;
    let across = turn - n * n.dot(&turn);
    // the axis the bodies roll about, if they roll, else any two across the normal
    let (u1, u2) = match across.try_normalize(1e-300) {
        Some(u) => (u, n.cross(&u)),
        None => tangents(&n),
    };
    let row = |axis: Vector3<f64>, max_impulse: f64| BilateralRow {
        a: c.a,
        b: c.b,
        lin: Vector3::zeros(),
        ang_a: -axis,
        ang_b: axis,
        speed: 0.0,
        kind: BilateralKind::Motor { max_impulse },
    };
    let rolling = c.rolling_resistance * radius * bound;
    if rolling > 0.0 {
        out.extend([row(u1, rolling), row(u2, rolling)]);
    }
    let torsion = c.torsional_resistance * radius * bound;
    if torsion > 0.0 {
        out.push(row(n, torsion));
    }
}

#[cfg(test)]
mod tests {
    use super::resistance_rows;
    use crate::body::BodyState;
    use crate::contact::Contact;
    use crate::step::{velocity_step, BilateralKind, StepSettings, VelocityProblem};
    use nalgebra::{Matrix3, Point3, Unit, Vector3};

    const G: f64 = 9.81;

    /// A solid ball of radius 0.1 and mass 4.19 kg on a static ground (body 0), rolling along x at `v`, and its
    /// contact with resistances `rolling`, `torsional` and friction 0.5.
    fn ball(v: f64, spin: f64, rolling: f64, torsional: f64) -> (Vec<BodyState>, Contact) {
        let (r, m) = (0.1, 4.0 / 3.0 * std::f64::consts::PI * 1e-3 * 1000.0);
        let mut b = BodyState::rigid(m, Matrix3::identity() * (0.4 * m * r * r), Point3::new(0.0, 0.0, r));
        b.velocity = Vector3::new(v, 0.0, 0.0);
        b.angular_velocity = Vector3::new(0.0, v / r, spin);
        b.force = Vector3::new(0.0, 0.0, -G * m);
        let c = Contact::new(0, 1, Point3::origin(), Unit::new_normalize(Vector3::z()))
            .with_friction(0.5)
            .with_resistance(rolling, torsional);
        (vec![BodyState::fixed(Point3::origin()), b], c)
    }

    #[test]
    fn a_contact_gives_rows_along_the_rolling_axis_and_the_normal_bounded_by_its_normal_impulse() {
        let (bodies, c) = ball(1.0, 3.0, 0.2, 0.1);
        let mut rows = Vec::new();
        resistance_rows(&c, &bodies, 0.5, &mut rows);
        assert_eq!(rows.len(), 3);
        // the ball rolls about +y: the first row's axis; bounds c r p = 0.2 * 0.1 * 0.5 and 0.1 * 0.1 * 0.5
        assert!((rows[0].ang_b - Vector3::y()).norm() < 1e-15 && (rows[2].ang_b - Vector3::z()).norm() < 1e-15);
        let bound = |k: usize| match rows[k].kind {
            BilateralKind::Motor { max_impulse } => max_impulse,
            _ => panic!("a bounded row"),
        };
        assert!((bound(0) - 0.01).abs() < 1e-15 && (bound(1) - 0.01).abs() < 1e-15 && (bound(2) - 0.005).abs() < 1e-15);
        // none without a normal impulse or a coefficient
        for (bound, rolling, torsional) in [(0.0, 0.2, 0.1), (0.5, 0.0, 0.0)] {
            let (bodies, c) = ball(1.0, 3.0, rolling, torsional);
            let mut rows = Vec::new();
            resistance_rows(&c, &bodies, bound, &mut rows);
            assert!(rows.is_empty());
        }
    }

    #[test]
    fn one_step_slows_a_rolling_ball_by_five_sevenths_of_its_resistance_times_g_h() {
        // the step's velocity conditions: rolling without slip, the rolling torque at its bound c m g r; so
        // m dv = -f h, I dw = (f r - c m g r) h, dv = r dw give dv = -5/7 c g h. Answered to the solver's
        // tolerance (1e-8 of the island's speeds, well inside 1e-9 m/s here)
        let (h, c) = (1.0 / 240.0, 0.2);
        let (bodies, contact) = ball(1.0, 0.0, c, 0.0);
        let weight = bodies[1].force.norm() * h; // the lagged normal impulse: the weight over the step
        let problem = VelocityProblem::new(&bodies, std::slice::from_ref(&contact));
        let bounds = [weight];
        let settings = StepSettings { threads: 1, ..StepSettings::new(h) };
        let out = velocity_step(&problem.lagged(&bounds), &settings).unwrap();
        let v = out.velocities[1];
        let want = 1.0 - 5.0 / 7.0 * c * G * h;
        assert!((v.linear.x - want).abs() < 1e-9, "{} m/s, closed form {want}", v.linear.x);
        assert!((v.linear.x - v.angular.y * 0.1).abs() < 1e-9, "rolls without slipping");
    }
}

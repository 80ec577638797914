//! The time-stepping conic program: sticking and sliding on an incline (with the convex model's gliding error stated
//! and checked), a box resting on the ground, restitution and the penetration and speculative biases, impulses inside
//! the friction cone, and islands.
#![cfg(feature = "clarabel")]

use crate::common;

use nalgebra::{Matrix3, Point3, Unit, Vector3};
use tumble_contact::{islands, velocity_step, BodyState, Contact, StepSettings, VelocityProblem};

const G: f64 = 9.81;
const H: f64 = 1.0 / 60.0;

fn incline_normal(theta: f64) -> Unit<Vector3<f64>> {
    Unit::new_normalize(Vector3::new(theta.sin(), 0.0, theta.cos()))
}

fn downhill(theta: f64) -> Vector3<f64> {
    Vector3::new(theta.cos(), 0.0, -theta.sin())
}

/// A particle of mass m at rest on a plane tilted by theta (body 0, static), one step.
fn particle_on_incline(theta: f64, mu: f64) -> (Vector3<f64>, f64, Vector3<f64>) {
    let m = 2.0;
    let p = BodyState {
        force: Vector3::new(0.0, 0.0, -m * G),
        ..BodyState::particle(m, Point3::origin(), Vector3::zeros())
    };
    let c = Contact::new(0, 1, Point3::origin(), incline_normal(theta)).with_friction(mu);
    let out =
        velocity_step(&VelocityProblem::new(&[BodyState::fixed(Point3::origin()), p], &[c]), &StepSettings::new(H))
            .unwrap();
    (out.velocities[1].linear, out.normal_impulses[0], out.friction_impulses[0])
}

#[test]
fn a_particle_on_an_incline_sticks_exactly_when_tan_theta_is_at_most_mu() {
    let mu: f64 = 0.4;
    let critical = mu.atan();
    // Just below the friction angle: stuck. Tolerance: clarabel stops at a relative gap of 1e-10, which leaves the
    // velocities a few 1e-9 of g h from the exact projection; 1e-8 g h.
    for theta in [0.1, 0.3, critical * (1.0 - 1e-3)] {
        let (v, pn, pt) = particle_on_incline(theta, mu);
        assert!(v.norm() < 1e-8 * G * H, "theta {theta}: v = {v}");
        // the impulses hold the weight: p_n = m g h cos theta, |p_t| = m g h sin theta <= mu p_n
        assert!((pn - 2.0 * G * H * theta.cos()).abs() < 1e-8 && (pt.norm() - 2.0 * G * H * theta.sin()).abs() < 1e-8);
    }
    // Just above and well above: it slides.
    for theta in [critical * (1.0 + 1e-3), 0.6, 1.0] {
        let (v, _, _) = particle_on_incline(theta, mu);
        assert!(v.dot(&downhill(theta)) > 0.0, "theta {theta}: v = {v}");
    }
}

#[test]
fn sliding_speed_after_one_step_is_coulombs_reduced_by_the_convex_models_gliding_factor() {
    // Coulomb: the tangential velocity gains g (sin th - mu cos th) h in one step. The convex (Anitescu) model
    // projects v* onto the cone v_n >= mu |v_t| instead, which from rest gives v_t = that gain / (1 + mu^2) and a
    // separating v_n = mu v_t: the gliding error is the factor 1 / (1 + mu^2) (3.8% at mu = 0.2, 20% at mu = 0.5) and
    // the hop mu v_t. The test checks both closed forms to 1e-8 of g h (the solver's accuracy, as above).
    for (theta, mu) in [(0.5, 0.2), (0.7, 0.5), (1.2, 0.9), (0.3, 0.0)] {
        let (v, _, _) = particle_on_incline(theta, mu);
        let coulomb = G * H * (f64::sin(theta) - mu * f64::cos(theta));
        let convex = coulomb / (1.0 + mu * mu);
        let vt = v.dot(&downhill(theta));
        let vn = v.dot(&incline_normal(theta));
        assert!((vt - convex).abs() < 1e-8 * G * H, "theta {theta}, mu {mu}: v_t {vt} vs {convex} (Coulomb {coulomb})");
        assert!((vn - mu * convex).abs() < 1e-8 * G * H, "theta {theta}, mu {mu}: v_n {vn} vs {}", mu * convex);
    }
}

fn resting_box(mu: f64, e: f64) -> (Vec<BodyState>, Vec<Contact>) {
    let (m, h) = (3.0, Vector3::new(0.5, 0.3, 0.2));
    let inertia =
        Matrix3::from_diagonal(&Vector3::new(h.y * h.y + h.z * h.z, h.x * h.x + h.z * h.z, h.x * h.x + h.y * h.y))
            * (m / 3.0);
    let b =
        BodyState { force: Vector3::new(0.0, 0.0, -m * G), ..BodyState::rigid(m, inertia, Point3::new(0.0, 0.0, h.z)) };
    let contacts = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|(sx, sy)| {
            Contact::new(0, 1, Point3::new(sx * h.x, sy * h.y, 0.0), Vector3::z_axis())
                .with_friction(mu)
                .with_restitution(e)
        })
        .collect();
    (vec![BodyState::fixed(Point3::origin()), b], contacts)
}

#[test]
fn a_box_resting_on_the_ground_stays_put_and_its_impulses_carry_its_weight() {
    let (bodies, contacts) = resting_box(0.5, 0.0);
    let out = velocity_step(&VelocityProblem::new(&bodies, &contacts), &StepSettings::new(H)).unwrap();
    assert!(out.velocities[1].linear.norm() < 1e-9 && out.velocities[1].angular.norm() < 1e-9);
    let total: f64 = out.normal_impulses.iter().sum();
    // 1e-9 relative: the solver tolerance
    assert!((total - 3.0 * G * H).abs() < 1e-9 * 3.0 * G * H, "{total}");
    for p in &out.normal_impulses {
        assert!((p - 3.0 * G * H / 4.0).abs() < 1e-8, "{:?}", out.normal_impulses);
    }
}

#[test]
fn a_ball_bounces_with_e_and_slow_or_distant_contacts_do_not() {
    let ground = BodyState::fixed(Point3::origin());
    let ball = |v: f64, z: f64| BodyState {
        velocity: Vector3::new(0.0, 0.0, v),
        force: Vector3::new(0.0, 0.0, -G),
        ..BodyState::rigid(1.0, Matrix3::from_diagonal_element(0.004), Point3::new(0.0, 0.0, z))
    };
    let touch =
        |gap: f64| Contact::new(0, 1, Point3::origin(), Vector3::z_axis()).with_restitution(0.8).with_distance(gap);
    let s = StepSettings::new(H);
    // Closing at 3 m/s and touching: it leaves at 0.8 x 3 m/s, less what gravity takes over the rest of the step.
    let out = velocity_step(&VelocityProblem::new(&[ground, ball(-3.0, 0.1)], &[touch(0.0)]), &s).unwrap();
    assert!((out.velocities[1].linear.z - (2.4 - G * H)).abs() < 1e-8, "{}", out.velocities[1].linear.z);
    // Closing slower than the bounce threshold: it stops.
    let out = velocity_step(&VelocityProblem::new(&[ground, ball(-0.01, 0.1)], &[touch(0.0)]), &s).unwrap();
    assert!(out.velocities[1].linear.z.abs() < 1e-9);
    // 1 m away at 3 m/s: it will not reach the ground this step, so it just falls (v* = v - g h).
    let out = velocity_step(&VelocityProblem::new(&[ground, ball(-3.0, 1.1)], &[touch(1.0)]), &s).unwrap();
    assert!((out.velocities[1].linear.z - (-3.0 - G * H)).abs() < 1e-9 && out.normal_impulses[0] < 1e-9);
    // 5 mm into the ground at rest: pushed out at erp x depth / h.
    let out = velocity_step(&VelocityProblem::new(&[ground, ball(0.0, 0.095)], &[touch(-0.005)]), &s).unwrap();
    assert!((out.velocities[1].linear.z - 0.2 * 0.005 / H).abs() < 1e-9);
}

#[test]
fn friction_impulses_stay_inside_their_cones_on_random_scenes() {
    let mut rnd = common::uniform(11);
    let mut sliding = 0;
    for case in 0..100 {
        let (mut bodies, mut contacts) = resting_box(0.1 + rnd(), 0.3 * rnd());
        bodies[1].velocity = Vector3::new(4.0 * (rnd() - 0.5), 4.0 * (rnd() - 0.5), -rnd());
        bodies[1].angular_velocity = Vector3::new(rnd() - 0.5, rnd() - 0.5, 3.0 * (rnd() - 0.5));
        for c in &mut contacts {
            c.distance = 0.01 * (rnd() - 0.7);
        }
        let out = velocity_step(&VelocityProblem::new(&bodies, &contacts), &StepSettings::new(H)).unwrap();
        for (i, c) in contacts.iter().enumerate() {
            let (pn, pt) = (out.normal_impulses[i], out.friction_impulses[i]);
            // Coulomb's cone, to the solver's tolerance on impulses of order m g h
            assert!(
                pn >= 0.0 && pt.norm() <= c.friction * pn + 1e-8,
                "case {case} contact {i}: |p_t| {} > mu p_n {}",
                pt.norm(),
                c.friction * pn
            );
            assert!(pt.dot(&c.normal).abs() < 1e-12, "friction must be tangent");
            sliding += (pt.norm() > 0.99 * c.friction * pn && pn > 1e-6) as usize;
        }
    }
    assert!(sliding > 50, "only {sliding} contacts reached the cone's edge");
}

#[test]
fn islands_are_joined_by_moving_bodies_only() {
    // Two stacks of two boxes on one static ground, and a fifth box bridging the tops of both: one island; without
    // the bridge, two.
    let (bodies, mut contacts) = {
        let mut b = vec![BodyState::fixed(Point3::origin())];
        for k in 0..5 {
            b.push(BodyState::particle(1.0, Point3::new(k as f64, 0.0, 1.0), Vector3::zeros()));
        }
        let z = Vector3::z_axis();
        let c = |a, b| Contact::new(a, b, Point3::origin(), z);
        (b, vec![c(0, 1), c(1, 2), c(0, 3), c(3, 4)])
    };
    assert_eq!(islands(&bodies, &contacts), vec![vec![0, 1], vec![2, 3]]);
    contacts.push(Contact::new(2, 5, Point3::origin(), Vector3::z_axis()));
    contacts.push(Contact::new(4, 5, Point3::origin(), Vector3::z_axis()));
    assert_eq!(islands(&bodies, &contacts), vec![vec![0, 1, 2, 3, 4, 5]]);
}

#[test]
fn lagged_friction_slides_at_coulombs_rate_without_hopping() {
    // With the friction bound taken from the previous normal impulse (m g h cos theta on an incline), one step
    // gives Coulomb's v_t = v0 + g h (sin th - mu cos th) exactly, and no separating normal velocity: the remedy
    // for the convex model's gliding error. Stuck for tan th <= mu. Tolerance 1e-8 g h, as above.
    let m = 2.0;
    for (theta, mu, v0) in [(0.5, 0.2, 0.0), (0.7, 0.5, 0.0), (0.2, 0.5, 3.0), (0.3, 0.4, 0.0)] {
        let (th, mu): (f64, f64) = (theta, mu);
        let p = BodyState {
            force: Vector3::new(0.0, 0.0, -m * G),
            ..BodyState::particle(m, Point3::origin(), downhill(th) * v0)
        };
        let c = Contact::new(0, 1, Point3::origin(), incline_normal(th)).with_friction(mu);
        let previous = [m * G * H * th.cos()];
        let out = velocity_step(
            &VelocityProblem::new(&[BodyState::fixed(Point3::origin()), p], &[c]).lagged(&previous),
            &StepSettings::new(H),
        )
        .unwrap();
        let v = out.velocities[1].linear;
        let coulomb = (v0 + G * H * (th.sin() - mu * th.cos())).max(0.0);
        assert!((v.dot(&downhill(th)) - coulomb).abs() < 1e-8 * G * H, "theta {th}, mu {mu}, v0 {v0}: {v}");
        assert!(v.dot(&incline_normal(th)).abs() < 1e-8 * G * H, "theta {th}: hops at {}", v.dot(&incline_normal(th)));
    }
    // previous impulses must match the contacts
    let c = Contact::new(0, 1, Point3::origin(), Vector3::z_axis());
    let bodies = [BodyState::fixed(Point3::origin()), BodyState::particle(1.0, Point3::origin(), Vector3::zeros())];
    assert!(velocity_step(&VelocityProblem::new(&bodies, &[c]).lagged(&[]), &StepSettings::new(H)).is_err());
    assert!(velocity_step(&VelocityProblem::new(&bodies, &[c]).lagged(&[-1.0]), &StepSettings::new(H)).is_err());
}

#[test]
fn islands_solved_together_on_several_threads_match_each_solved_alone() {
    // Twelve sliding, spinning boxes on one ground: twelve islands and 48 contacts, enough for the step to spread
    // its islands over threads. Each island's program is the same whether solved with the others or alone, and the
    // answer must come back to the right bodies in the right order: equal to the last bit.
    let mut rnd = common::uniform(5);
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let mut contacts = Vec::new();
    let mut alone = Vec::new();
    for k in 0..12 {
        let (b, cs) = resting_box(0.2 + 0.5 * rnd(), 0.3 * rnd());
        let mut body = b[1];
        body.position.x += 2.0 * k as f64;
        body.velocity = Vector3::new(2.0 * (rnd() - 0.5), 2.0 * (rnd() - 0.5), -rnd());
        body.angular_velocity = Vector3::new(0.0, 0.0, rnd() - 0.5);
        let shift = Vector3::new(2.0 * k as f64, 0.0, 0.0);
        let cs: Vec<Contact> = cs.iter().map(|c| Contact { point: c.point + shift, ..*c }).collect();
        alone.push(velocity_step(&VelocityProblem::new(&[bodies[0], body], &cs), &StepSettings::new(H)).unwrap());
        let index = bodies.len();
        bodies.push(body);
        contacts.extend(cs.into_iter().map(|c| Contact { b: index, ..c }));
    }
    let together = velocity_step(&VelocityProblem::new(&bodies, &contacts), &StepSettings::new(H)).unwrap();
    assert_eq!(islands(&bodies, &contacts).len(), 12);
    for (k, one) in alone.iter().enumerate() {
        assert_eq!(together.velocities[k + 1], one.velocities[1], "box {k}");
        assert_eq!(&together.normal_impulses[4 * k..4 * k + 4], &one.normal_impulses[..], "box {k}");
    }
    assert_eq!(together.solver_calls, 12);
}

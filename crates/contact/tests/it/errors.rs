//! Every bad input is refused with an error that names it, and a solver that cannot deliver is an error too
//! (the functions are pure, so no body is ever changed by a failure).
#![cfg(feature = "clarabel")]

use nalgebra::{Matrix3, Point3, Unit, Vector3};
use tumble_contact::{
    collision_impulses, resting_forces, velocity_step, BodyState, Contact, ContactError, NormalMotion, SolverSettings,
    StepSettings, VelocityProblem,
};

fn name(e: ContactError) -> &'static str {
    match e {
        ContactError::InvalidArgument { name, .. } => name,
        other => panic!("expected an invalid argument, got {other}"),
    }
}

fn scene() -> (Vec<BodyState>, Vec<Contact>) {
    let ball = BodyState {
        force: Vector3::new(0.0, 0.0, -9.81),
        ..BodyState::rigid(1.0, Matrix3::identity() * 0.1, Point3::new(0.0, 0.0, 1.0))
    };
    (vec![BodyState::fixed(Point3::origin()), ball], vec![Contact::new(0, 1, Point3::origin(), Vector3::z_axis())])
}

/// Runs all three solvers on the scene and checks each refuses it naming `expected`.
fn refused(bodies: &[BodyState], contacts: &[Contact], expected: &str) {
    let s = SolverSettings::default();
    assert_eq!(name(resting_forces(bodies, contacts, &s).unwrap_err()), expected);
    assert_eq!(name(collision_impulses(bodies, contacts, &s).unwrap_err()), expected);
    assert_eq!(
        name(velocity_step(&VelocityProblem::new(bodies, contacts), &StepSettings::new(0.01)).unwrap_err()),
        expected
    );
}

#[test]
fn bad_bodies_are_refused() {
    let (bodies, contacts) = scene();
    let mut b = bodies.clone();
    b[1].inv_mass = -1.0;
    refused(&b, &contacts, "bodies");
    let mut b = bodies.clone();
    b[1].velocity.x = f64::NAN;
    refused(&b, &contacts, "bodies");
    let mut b = bodies.clone();
    b[1].inertia[(0, 1)] = 0.05;
    refused(&b, &contacts, "bodies");
    let mut b = bodies.clone();
    b[1].inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.1, -0.1));
    refused(&b, &contacts, "bodies");
    let mut b = bodies.clone();
    b[1].inv_inertia = Matrix3::identity();
    refused(&b, &contacts, "bodies");
}

#[test]
fn bad_contacts_are_refused() {
    let (bodies, contacts) = scene();
    let with = |f: &dyn Fn(&mut Contact)| {
        let mut c = contacts.clone();
        f(&mut c[0]);
        c
    };
    refused(&bodies, &with(&|c| c.b = 7), "contacts");
    refused(&bodies, &with(&|c| c.a = 1), "contacts");
    refused(&bodies, &with(&|c| c.normal = Unit::new_unchecked(Vector3::new(0.0, 0.0, 2.0))), "contacts");
    refused(&bodies, &with(&|c| c.point.x = f64::INFINITY), "contacts");
    refused(&bodies, &with(&|c| c.distance = f64::NAN), "contacts");
    refused(&bodies, &with(&|c| c.restitution = 1.5), "contacts");
    refused(&bodies, &with(&|c| c.friction = -0.1), "contacts");
    let parallel = NormalMotion::EdgeEdge { edge_a: Vector3::x_axis(), edge_b: -Vector3::x_axis() };
    refused(&bodies, &with(&|c| c.normal_motion = parallel), "contacts");
    let two_static = [bodies[0], BodyState::fixed(Point3::new(0.0, 0.0, 1.0))];
    refused(&two_static, &contacts, "contacts");
}

#[test]
fn bad_settings_are_refused() {
    let (bodies, contacts) = scene();
    for bad in [
        SolverSettings { tolerance: 0.0, ..SolverSettings::default() },
        SolverSettings { max_iterations: 0, ..SolverSettings::default() },
        SolverSettings { complementarity_tolerance: f64::NAN, ..SolverSettings::default() },
    ] {
        assert_eq!(name(resting_forces(&bodies, &contacts, &bad).unwrap_err()), "settings");
        assert_eq!(name(collision_impulses(&bodies, &contacts, &bad).unwrap_err()), "settings");
    }
    for (bad, expected) in [
        (StepSettings { dt: 0.0, ..StepSettings::new(0.01) }, "dt"),
        (StepSettings { dt: f64::NAN, ..StepSettings::new(0.01) }, "dt"),
        (StepSettings { erp: 1.5, ..StepSettings::new(0.01) }, "erp"),
        (StepSettings { bounce_threshold: -1.0, ..StepSettings::new(0.01) }, "bounce_threshold"),
    ] {
        assert_eq!(name(velocity_step(&VelocityProblem::new(&bodies, &contacts), &bad).unwrap_err()), expected);
    }
}

#[test]
fn a_solver_that_cannot_deliver_is_an_error() {
    // One interior-point iteration cannot solve a 20-box stack: the answer misses complementarity.
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let mut contacts = Vec::new();
    for j in 0..20 {
        bodies.push(BodyState {
            force: Vector3::new(0.0, 0.0, -9.81),
            ..BodyState::rigid(1.0, Matrix3::identity(), Point3::new(0.0, 0.0, j as f64 + 0.5))
        });
        for (x, y) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            contacts.push(Contact::new(j, j + 1, Point3::new(x, y, j as f64), Vector3::z_axis()));
        }
    }
    let one = SolverSettings { max_iterations: 1, ..SolverSettings::default() };
    assert!(matches!(resting_forces(&bodies, &contacts, &one).unwrap_err(), ContactError::Inaccurate { .. }));
    // A particle squeezed between two walls that each demand it move away at 1 m/s: no velocity satisfies both.
    let walls = [BodyState::fixed(Point3::new(-1.0, 0.0, 0.0)), BodyState::fixed(Point3::new(1.0, 0.0, 0.0))];
    let bodies = [walls[0], walls[1], BodyState::particle(1.0, Point3::origin(), Vector3::zeros())];
    let h = 0.01;
    let deep = -h / 0.2; // erp 0.2: a push-out of 1 m/s (1 m/s x h / erp deep)
    let contacts = [
        Contact::new(0, 2, Point3::origin(), Vector3::x_axis()).with_distance(deep),
        Contact::new(1, 2, Point3::origin(), -Vector3::x_axis()).with_distance(deep),
    ];
    let err = velocity_step(&VelocityProblem::new(&bodies, &contacts), &StepSettings::new(h)).unwrap_err();
    assert!(matches!(err, ContactError::Solver { .. }), "{err}");
    assert!(err.to_string().contains("Infeasible"), "{err}");
}

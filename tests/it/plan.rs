//! A world runs only the stages its contents need, and its reports show it.

use nalgebra::{Matrix3, Vector3};
use tumble::scenes::Cloth;
use tumble::{
    Attachment, Method, ParticleBuilder, RigidBodyBuilder, Settings, Shape, SpringBuilder, Target, World, Wrench,
};

#[test]
fn a_particle_world_carries_no_rotation_state() {
    let mut w = World::new();
    for i in 0..5 {
        w.add_particle(ParticleBuilder::new(1.0).position(Vector3::new(i as f64, 0.0, 0.0))).unwrap();
    }
    let plan = w.plan();
    assert_eq!(plan.state_len, 6 * 5);
    assert!(plan.has("particles") && plan.has("gravity") && plan.has("integrate"));
    for absent in ["rigid-bodies", "rotation", "springs", "loads", "callbacks", "damping", "jacobian"] {
        assert!(!plan.has(absent), "{absent} in {plan}");
    }
    for absent in ["collision-detection", "bisection", "impulses", "resting-contact", "contact-cone-program"] {
        assert!(!plan.has(absent), "{absent} in {plan}: nothing has a shape");
    }
    let b = w
        .add_body(RigidBodyBuilder::from_shape(Shape::sphere(1.0).unwrap(), 1.0).position(Vector3::new(0.0, 0.0, 5.0)))
        .unwrap();
    let plan = w.plan();
    assert_eq!(plan.state_len, 6 * 5 + 13);
    assert!(plan.has("rigid-bodies") && plan.has("rotation"));
    assert!(!plan.has("collision-detection"), "one shape alone touches nothing: {plan}");
    w.add_body(RigidBodyBuilder::fixed(Some(Shape::half_space(Vector3::z()).unwrap()))).unwrap();
    let plan = w.plan();
    assert_eq!(plan.state_len, 6 * 5 + 13, "a static body adds no state");
    for stage in ["collision-detection", "bisection", "impulses", "contact-cone-program"] {
        assert!(plan.has(stage), "{stage} missing from {plan}");
    }
    w.set_mode(tumble::Mode::fast(0.01)).unwrap();
    let fast = w.plan();
    assert!(fast.has("contact-soft-step") && fast.has("sleeping") && !fast.has("bisection"), "{fast}");
    assert!(!fast.has("contact-cone-program"), "the soft step's plan has no cone program: {fast}");
    let exact = tumble::FastSettings { solver: tumble::FastSolver::exact(), ..tumble::FastSettings::new(0.01) };
    w.set_mode(tumble::Mode::Fast(exact)).unwrap();
    let fast = w.plan();
    assert!(fast.has("contact-cone-program") && !fast.has("contact-soft-step"), "{fast}");
    w.set_mode(tumble::Mode::default()).unwrap();
    if !cfg!(feature = "clarabel") {
        // Built without clarabel, the chapter's resting-force QP is refused, naming the feature.
        let resting = tumble::AccurateSettings { persistent: tumble::Persistent::RestingForces, ..Default::default() };
        let e = w.set_mode(tumble::Mode::Accurate(resting)).unwrap_err();
        assert!(e.to_string().contains("`clarabel` feature"), "{e}");
    }
    w.step(0.1).unwrap();
    let z = w.body(b).unwrap().position().z;
    assert!((z - (5.0 - 0.5 * 9.81 * 0.01)).abs() < 1e-9, "falling freely: {z}");
}

/// Explicit methods never form a Jacobian; implicit ones do, analytically for particles and springs, by coloured
/// differences once a body or a callback is present.
#[test]
fn only_implicit_methods_form_jacobians() {
    for method in [Method::Euler, Method::Rk4, Method::Verlet] {
        let (mut w, _) = Cloth { n: 6, ..Cloth::default() }.build().unwrap();
        w.set_integrator(Settings::fixed(method, 1e-3)).unwrap();
        w.step(0.01).unwrap();
        let r = w.report();
        assert_eq!((r.integrator.jacobians, r.integrator.factorizations), (0, 0), "{method}");
        assert!(!w.plan().has("jacobian"));
    }
    let dopri = {
        let (mut w, _) = Cloth { n: 6, ..Cloth::default() }.build().unwrap();
        w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-6, 1e-9)).unwrap();
        w.step(0.01).unwrap();
        w.report()
    };
    assert_eq!(dopri.integrator.jacobians, 0);
    let (mut w, ps) = Cloth { n: 6, ..Cloth::default() }.build().unwrap();
    assert_eq!(w.plan().jacobian, Some("analytic-sparse-definite"));
    w.step(0.01).unwrap();
    assert!(w.report().integrator.jacobians > 0);
    w.add_force_callback(Target::Particle(ps[3]), |_, _| Ok(Wrench::default())).unwrap();
    assert_eq!(w.plan().jacobian, Some("colored-finite-differences"));
}

/// Force loops that a scene does not need never run: no springs, no spring evaluations; no callbacks, no calls.
/// With them, one evaluation each per right-hand side.
#[test]
fn force_loops_run_only_for_what_is_there() {
    let mut w = World::new();
    let a = w.add_particle(ParticleBuilder::new(1.0)).unwrap();
    w.step(0.5).unwrap();
    let r = w.report().forces;
    assert!(r.evaluations > 0);
    assert_eq!((r.spring_evaluations, r.load_evaluations, r.callback_calls), (0, 0, 0));

    let b = w.add_particle(ParticleBuilder::new(1.0).position(Vector3::new(1.0, 0.0, 0.0))).unwrap();
    w.add_spring(SpringBuilder::new(Attachment::Particle(a), Attachment::Particle(b)).stiffness(10.0)).unwrap();
    w.add_force_callback(Target::Particle(b), |_, _| {
        Ok(Wrench { force: Vector3::new(0.0, 0.0, 9.81), torque: Vector3::zeros() })
    })
    .unwrap();
    let before = w.report().forces;
    w.step(0.5).unwrap();
    let after = w.report().forces;
    let evaluations = after.evaluations - before.evaluations;
    assert_eq!(after.spring_evaluations - before.spring_evaluations, evaluations);
    assert_eq!(after.callback_calls - before.callback_calls, evaluations);
    assert_eq!(after.load_evaluations, before.load_evaluations);
}

/// Quaternions are renormalised after accepted steps only when they drift: a long tumbling run keeps every
/// orientation unit to 1e-12 and reports how often it had to.
#[test]
fn quaternions_stay_unit() {
    let mut w = World::new();
    w.set_gravity(Vector3::zeros()).unwrap();
    w.set_integrator(Settings::fixed(Method::Rk4, 0.01)).unwrap();
    w.add_body(
        RigidBodyBuilder::new(1.0, Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)))
            .angular_velocity(Vector3::new(1.0, 5.0, 0.2)),
    )
    .unwrap();
    let run = w.run(50.0, 0.5).unwrap();
    for f in 0..run.frames() {
        assert!((run.body_orientation(f, 0).quaternion().norm() - 1.0).abs() < 1e-12);
    }
    assert!(run.report.forces.projections > 0);
}

//! Bad input is refused with an error that names the argument; a failed step leaves the world as it was.

use nalgebra::{Matrix3, Vector3};
use tumble::{
    Attachment, BodyHandle, Method, ParticleBuilder, RigidBodyBuilder, Settings, Shape, SpringBuilder, Target, World,
    WorldError, Wrench,
};

fn name(e: WorldError) -> &'static str {
    e.argument().unwrap_or_else(|| panic!("expected a named argument error, got {e:?}"))
}

#[test]
fn bad_particles() {
    let mut w = World::new();
    for m in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(name(w.add_particle(ParticleBuilder::new(m)).unwrap_err()), "mass", "mass {m}");
    }
    let nan = Vector3::new(0.0, f64::NAN, 0.0);
    assert_eq!(name(w.add_particle(ParticleBuilder::new(1.0).position(nan)).unwrap_err()), "position");
    assert_eq!(name(w.add_particle(ParticleBuilder::new(1.0).velocity(nan)).unwrap_err()), "velocity");
    assert_eq!(name(w.add_particle(ParticleBuilder::new(1.0).damping(-1.0)).unwrap_err()), "damping");
    assert_eq!(name(w.add_particle(ParticleBuilder::new(1.0).stiffness(f64::NAN)).unwrap_err()), "stiffness");
    assert_eq!(w.particle_count(), 0, "nothing was added");
}

#[test]
fn bad_bodies() {
    let mut w = World::new();
    let i = Matrix3::identity();
    assert_eq!(name(w.add_body(RigidBodyBuilder::new(0.0, i)).unwrap_err()), "mass");
    assert_eq!(name(w.add_body(RigidBodyBuilder::new(-2.0, i)).unwrap_err()), "mass");
    let asymmetric = Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert_eq!(name(w.add_body(RigidBodyBuilder::new(1.0, asymmetric)).unwrap_err()), "inertia");
    let indefinite = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0));
    assert_eq!(name(w.add_body(RigidBodyBuilder::new(1.0, indefinite)).unwrap_err()), "inertia");
    let singular = Matrix3::from_diagonal(&Vector3::new(1.0, 0.0, 1.0));
    assert_eq!(name(w.add_body(RigidBodyBuilder::new(1.0, singular)).unwrap_err()), "inertia");
    assert_eq!(name(w.add_body(RigidBodyBuilder::new(1.0, i * f64::NAN)).unwrap_err()), "inertia");
    let ball = Shape::sphere(1.0).unwrap();
    assert_eq!(name(w.add_body(RigidBodyBuilder::from_shape(ball.clone(), -5.0)).unwrap_err()), "density");
    assert_eq!(name(w.add_body(RigidBodyBuilder::from_shape_with_mass(ball.clone(), f64::NAN)).unwrap_err()), "mass");
    let ground = Shape::half_space(Vector3::z()).unwrap();
    assert_eq!(name(w.add_body(RigidBodyBuilder::from_shape(ground, 1.0)).unwrap_err()), "shape");
    let at = |p| RigidBodyBuilder::from_shape(ball.clone(), 1.0).position(p);
    assert_eq!(name(w.add_body(at(Vector3::new(f64::INFINITY, 0.0, 0.0))).unwrap_err()), "position");
    assert_eq!(
        name(w.add_body(RigidBodyBuilder::from_shape(ball.clone(), 1.0).restitution(1.5)).unwrap_err()),
        "restitution"
    );
    assert_eq!(w.body_count(), 0);
}

#[test]
fn bad_springs_loads_and_handles() {
    let mut w = World::new();
    let p = w.add_particle(ParticleBuilder::new(1.0)).unwrap();
    let ground = w.add_body(RigidBodyBuilder::fixed(None)).unwrap();
    let to_origin = |p| SpringBuilder::new(Attachment::Particle(p), Attachment::Point(Vector3::new(0.0, 0.0, 1.0)));
    assert_eq!(name(w.add_spring(to_origin(p).stiffness(0.0)).unwrap_err()), "stiffness");
    assert_eq!(name(w.add_spring(to_origin(p).damping(-1.0)).unwrap_err()), "damping");
    assert_eq!(name(w.add_spring(to_origin(p).rest_length(-1.0)).unwrap_err()), "rest_length");
    assert_eq!(
        name(w.add_spring(SpringBuilder::new(Attachment::Particle(p), Attachment::Particle(p))).unwrap_err()),
        "b"
    );
    let stale = BodyHandle::from_parts(7, 3);
    assert_eq!(
        name(
            w.add_spring(SpringBuilder::new(Attachment::Particle(p), Attachment::Body(stale, Vector3::zeros())))
                .unwrap_err()
        ),
        "b"
    );
    assert_eq!(name(w.add_force(Target::Body(ground), Vector3::x(), None).unwrap_err()), "target");
    assert_eq!(name(w.add_force(Target::Particle(p), Vector3::x(), Some(Vector3::y())).unwrap_err()), "at");
    assert_eq!(name(w.add_force(Target::Particle(p), Vector3::new(f64::NAN, 0.0, 0.0), None).unwrap_err()), "force");
    assert_eq!(name(w.step(0.0).unwrap_err()), "dt");
    assert_eq!(name(w.step(-0.1).unwrap_err()), "dt");
    assert_eq!(name(w.step(f64::NAN).unwrap_err()), "dt");
    assert_eq!(name(w.run(1.0, 0.0).unwrap_err()), "frame_interval");
    assert_eq!(name(w.run(-1.0, 0.1).unwrap_err()), "duration");
    assert_eq!(name(w.set_integrator(Settings::fixed(Method::Rk4, -1e-3)).unwrap_err()), "dt");
    // A removed particle's handle is stale, and its springs went with it.
    let q = w.add_particle(ParticleBuilder::new(1.0).position(Vector3::x())).unwrap();
    w.add_spring(SpringBuilder::new(Attachment::Particle(p), Attachment::Particle(q)).stiffness(1.0)).unwrap();
    w.remove_particle(q).unwrap();
    assert_eq!(w.springs().count(), 0);
    assert_eq!(name(w.particle(q).unwrap_err()), "particle");
    assert_eq!(name(w.remove_particle(q).unwrap_err()), "particle");
}

/// A callback that fails once t passes 0.5 makes that step fail; the world keeps the time and state it had.
#[test]
fn failed_step_leaves_the_world_unchanged() {
    let mut w = World::new();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-8, 1e-8)).unwrap();
    let p = w.add_particle(ParticleBuilder::new(1.0).velocity(Vector3::new(1.0, 0.0, 0.0))).unwrap();
    w.add_force_callback(
        Target::Particle(p),
        |t, _| if t > 0.5 { Err("sensor lost".into()) } else { Ok(Wrench::default()) },
    )
    .unwrap();
    w.step(0.4).unwrap();
    let (t, before) = (w.time(), w.particle(p).unwrap().clone());
    let err = w.step(0.4).unwrap_err();
    assert!(err.to_string().contains("sensor lost"), "{err}");
    assert_eq!(w.time(), t);
    assert_eq!(w.particle(p).unwrap(), &before);
    let err = w.run(1.0, 0.1).unwrap_err();
    assert!(matches!(err, WorldError::Simulation(_)));
    assert_eq!(w.particle(p).unwrap(), &before);
}

#[test]
fn a_static_body_takes_no_velocity_and_the_world_is_left_as_it_was() {
    // an option that does not apply is an error: a static body does not move
    let mut w = World::new();
    let v = Vector3::new(1.0, 0.0, 0.0);
    let fixed = || RigidBodyBuilder::fixed(Some(Shape::sphere(0.5).unwrap()));
    assert_eq!(name(w.add_body(fixed().velocity(v)).unwrap_err()), "velocity");
    assert_eq!(name(w.add_body(fixed().angular_velocity(v)).unwrap_err()), "angular_velocity");
    assert_eq!(w.body_count(), 0);
    let h = w.add_body(fixed().position(Vector3::new(0.0, 0.0, 1.0))).unwrap();
    let q = nalgebra::UnitQuaternion::identity();
    let (here, there, zero) = (Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.0, 0.0, 2.0), Vector3::zeros());
    assert_eq!(name(w.set_body_state(h, there, q, v, zero).unwrap_err()), "velocity");
    assert_eq!(name(w.set_body_state(h, there, q, zero, v).unwrap_err()), "angular_velocity");
    assert_eq!(w.body(h).unwrap().position(), here, "a refused call moves nothing");
    // with zero velocities it is moved to the pose
    w.set_body_state(h, there, q, zero, zero).unwrap();
    assert_eq!(w.body(h).unwrap().position(), there);
}

#[test]
fn integrator_keywords_are_checked_by_name() {
    use tumble::{IntegratorOptions, WorldOptions};
    let build = |integrator: IntegratorOptions| WorldOptions { integrator, ..Default::default() }.build();
    let named = |o: IntegratorOptions| name(build(o).err().expect("refused"));
    let o = IntegratorOptions::default;
    // tolerances: finite and not negative, wherever they apply
    for bad in [f64::NAN, -1.0, f64::INFINITY] {
        assert_eq!(named(IntegratorOptions { rtol: Some(bad), ..o() }), "rtol", "rtol {bad}");
        assert_eq!(named(IntegratorOptions { atol: Some(bad), ..o() }), "atol", "atol {bad}");
    }
    // step doubling and euler-variable control their step by `tolerance`: rtol and atol do not apply to them
    let doubling = || IntegratorOptions { step_doubling: true, integrator: Some("rk4".into()), ..o() };
    assert_eq!(named(IntegratorOptions { rtol: Some(1e-6), ..doubling() }), "rtol");
    assert_eq!(named(IntegratorOptions { atol: Some(1e-6), ..doubling() }), "atol");
    assert_eq!(named(IntegratorOptions { rtol: Some(f64::NAN), ..doubling() }), "rtol");
    let variable = || IntegratorOptions { integrator: Some("euler-variable".into()), ..o() };
    assert_eq!(named(IntegratorOptions { atol: Some(1e-9), ..variable() }), "atol");
    assert_eq!(named(IntegratorOptions { dt: Some(1e-3), ..variable() }), "dt");
    // the step is named `dt` whatever the settings call it (an adaptive method's first step)
    for bad in [f64::INFINITY, f64::NAN, 0.0, -1e-3] {
        assert_eq!(named(IntegratorOptions { dt: Some(bad), ..o() }), "dt", "dt {bad}");
        assert_eq!(named(IntegratorOptions { dt: Some(bad), integrator: Some("rk4".into()), ..o() }), "dt");
    }
    assert_eq!(named(IntegratorOptions { tolerance: Some(f64::NAN), ..doubling() }), "tolerance");
    assert!(build(IntegratorOptions { rtol: Some(1e-8), atol: Some(0.0), ..o() }).is_ok());
    assert!(build(IntegratorOptions { tolerance: Some(1e-7), ..doubling() }).is_ok());
}

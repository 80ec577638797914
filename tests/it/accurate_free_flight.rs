//! Accurate mode's touching phase with actors that touch nothing: they follow the integrator (its order and
//! tolerances), not the first-order contact steps, and their motion no longer sets the contact step. Actors joined
//! by a spring to a touching one step with it.

use crate::common;

use nalgebra::Vector3;
use tumble::{
    AccurateSettings, Attachment, Material, Method, Mode, ParticleBuilder, RigidBodyBuilder, Settings, Shape,
    SpringBuilder, World, WorldReport,
};

const G: f64 = 9.81;

/// An accurate-mode world at contact tolerance `tol` with Dopri5 at rtol 1e-10, a floor of friction `mu`, and a
/// 0.5 m cube of density 1000 on it moving at `v` along x.
fn sliding_cube(tol: f64, mu: f64, v: f64) -> (World, tumble::BodyHandle) {
    let mut w = World::new();
    w.set_mode(Mode::Accurate(AccurateSettings { contact_tolerance: Some(tol), ..Default::default() })).unwrap();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-10, 1e-12)).unwrap();
    w.add_ground(0.0, Material::new(0.0, mu)).unwrap();
    let cube = Shape::cuboid(Vector3::repeat(0.25)).unwrap();
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(cube, 1000.0)
                .position(Vector3::new(0.0, 0.0, 0.25))
                .velocity(Vector3::new(v, 0.0, 0.0))
                .restitution(0.0)
                .friction(mu),
        )
        .unwrap();
    (w, b)
}

fn run(w: &mut World, t: f64) -> WorldReport {
    w.step(t).unwrap();
    w.report()
}

#[test]
fn a_fast_damped_particle_beside_a_sliding_box_follows_its_closed_form_and_leaves_the_contact_steps_alone() {
    let (tol, mu, v, t) = (1e-8, 0.5, 2.0, 0.3);
    let (mut alone, cube) = sliding_cube(tol, mu, v);
    let alone_report = run(&mut alone, t);
    let (mut w, cube_b) = sliding_cube(tol, mu, v);
    // 3 kg at 1e4 m/s with damping 2 kg/s, passing through everything (no radius): v(t) = v_inf + (v0 - v_inf)
    // e^(-c t / m), v_inf = m g / c, x(t) = x0 + v_inf t + (v0 - v_inf) (m / c) (1 - e^(-c t / m)).
    let (m, c) = (3.0, 2.0);
    let (x0, v0) = (Vector3::new(0.0, 5.0, 10.0), Vector3::new(0.0, 1e4, 0.0));
    let p = w.add_particle(ParticleBuilder::new(m).position(x0).velocity(v0).damping(c)).unwrap();
    let report = run(&mut w, t);
    let v_inf = Vector3::new(0.0, 0.0, -G) * m / c;
    let decay = (-c * t / m).exp();
    let x = x0 + v_inf * t + (v0 - v_inf) * (m / c) * (1.0 - decay);
    let vel = v_inf + (v0 - v_inf) * decay;
    let particle = w.particle(p).unwrap();
    let (dx, dv) = ((particle.position() - x).norm(), (particle.velocity() - vel).norm());
    println!(
        "measured: particle error {dx:.2e} m, {dv:.2e} m/s; contact steps {} with it, {} without",
        report.contact_steps, alone_report.contact_steps
    );
    // Dopri5 at rtol 1e-10 over ~2,000 m of flight: each of its steps is accurate to about 1e-10 of the state,
    // and its steps here are those the contact steps set (at most 1/60 s, where Dopri5's error is far smaller);
    // 1e-6 m is 5e-10 of the distance flown.
    assert!(dx < 1e-6 && dv < 1e-6, "particle off its closed form by {dx:e} m, {dv:e} m/s");
    // The contact steps are the box's: as many as without the particle (within a few: the energy check of the
    // extrapolation sees rounding of a larger total). Before, the particle's first-order error made them ~4e-5 s.
    let (with, without) = (report.contact_steps as f64, alone_report.contact_steps as f64);
    assert!(with <= 1.1 * without + 5.0, "{with} contact steps with the particle, {without} without");
    // and the box slides the same: d = v t - mu g t^2 / 2 until it stops (t = 0.3 s < v / (mu g) = 0.41 s)
    let d = v * t - 0.5 * mu * G * t * t;
    for (world, b) in [(&alone, cube), (&w, cube_b)] {
        let error = (world.body(b).unwrap().position().x - d).abs();
        assert!(error < 1e-6, "box off its closed form by {error:e} m");
    }
}

#[test]
fn a_particle_on_a_spring_to_a_touching_box_steps_with_the_box() {
    // A 1 kg particle hangs above a 0.5 m cube (125 kg) by a spring of 100 N/m on its top centre, and both move
    // at 1 m/s over a frictionless floor. The spring is vertical, so the box keeps its speed and stays on the floor
    // (the spring's force, under 5 N, against 1226 N of weight): x = v t, and the particle oscillates about its
    // equilibrium, z = z_eq + A cos(w t), w = sqrt(k / m), z_eq = 0.5 + l0 - m g / k. Were the particle stepped
    // apart from the box (held still over each step), the spring would pull it back by ~k v h^3 / (2 m), 2e-4 m a
    // step of 1/60 s.
    let (k, m, l0, a, v) = (100.0, 1.0, 0.5, 0.01, 1.0);
    let (mut w, cube) = sliding_cube(1e-7, 0.0, v);
    let z_eq = 0.5 + l0 - m * G / k;
    let p = w
        .add_particle(ParticleBuilder::new(m).position(Vector3::new(0.0, 0.0, z_eq + a)).velocity(Vector3::x() * v))
        .unwrap();
    w.add_spring(
        SpringBuilder::new(Attachment::Particle(p), Attachment::Body(cube, Vector3::new(0.0, 0.0, 0.25)))
            .stiffness(k)
            .rest_length(l0),
    )
    .unwrap();
    let t = 0.5;
    let report = run(&mut w, t);
    let exact = Vector3::new(v * t, 0.0, z_eq + a * ((k / m).sqrt() * t).cos());
    let error = (w.particle(p).unwrap().position() - exact).norm();
    let box_error = (w.body(cube).unwrap().position() - Vector3::new(v * t, 0.0, 0.25)).norm();
    println!("measured: particle error {error:.2e} m, box {box_error:.2e} m, {} contact steps", report.contact_steps);
    assert!(report.contact_steps > 0, "the box touched the floor in contact steps");
    // contact steps at 1e-7 m a step, ~2,000 of them: the global error is within a few hundred tolerances
    assert!(error < 1e-5, "particle off its closed form by {error:e} m");
    assert!(box_error < 1e-5, "box off its closed form by {box_error:e} m");
}

#[test]
fn bodies_that_touch_while_falling_together_follow_free_fall_without_a_convex_solve() {
    // The long fuzz run's last slow call: two boxes touching, carried along together by gravity, cost nine convex
    // solves a contact step (2 s of work a simulated second) for contacts that never push. A contact nothing
    // presses needs no impulse; the free velocities are then the program's optimum, and the step answers with them.
    // Seeded random pairs: a box on a box face to face, or two spheres touching, in a random orientation, random
    // sizes, densities and materials, a common random velocity and a random gravity. Each body follows
    // x0 + v0 t + g t^2 / 2, and no solve is made.
    let mut rng = common::Lcg(20261130);
    for case in 0..12 {
        let mut w = World::new();
        let g = Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize()
            * rng.range(5.0, 20.0);
        w.set_gravity(g).unwrap();
        let q = nalgebra::UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), 0.3);
        let v0 = Vector3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        let (a_shape, b_shape, offset) = if case % 2 == 0 {
            let (ha, hb) = (rng.range(0.05, 0.3), rng.range(0.05, 0.3));
            let shape = |h: f64| Shape::cuboid(Vector3::new(h, 0.5 * h + 0.05, h)).unwrap();
            (shape(ha), shape(hb), q * Vector3::new(0.0, 0.0, ha + hb))
        } else {
            let (ra, rb) = (rng.range(0.05, 0.3), rng.range(0.05, 0.3));
            (Shape::sphere(ra).unwrap(), Shape::sphere(rb).unwrap(), q * Vector3::new(0.0, 0.0, ra + rb))
        };
        let x0 = [Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)), Vector3::zeros()];
        let x0 = [x0[0], x0[0] + offset];
        let handles: Vec<_> = [a_shape, b_shape]
            .into_iter()
            .zip(x0)
            .map(|(shape, x)| {
                w.add_body(
                    RigidBodyBuilder::from_shape(shape, rng.range(100.0, 5000.0))
                        .position(x)
                        .orientation(q)
                        .velocity(v0)
                        .friction(rng.range(0.0, 1.0))
                        .restitution(rng.range(0.0, 0.9)),
                )
                .unwrap()
            })
            .collect();
        let t = 0.5;
        let report = run(&mut w, t);
        assert!(report.contact_steps > 0, "case {case}: the pair touched (contact steps)");
        assert_eq!(report.qp_solves, 0, "case {case}: a contact nothing presses needs no solve");
        for (h, x) in handles.iter().zip(x0) {
            let exact = x + v0 * t + g * (0.5 * t * t);
            let error = (w.body(*h).unwrap().position() - exact).norm();
            // Semi-implicit Euler extrapolated over halves is exact for a constant acceleration; what remains is
            // the rounding of some thousand steps on positions of a few metres (1e-16 each, relative).
            assert!(error < 1e-10, "case {case}: off free fall by {error:e} m");
        }
    }
}

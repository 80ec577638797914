//! Fast mode (time stepping) against closed forms and the issue's scenes: a box at rest stays put, a sliding box
//! stops after v^2 / (2 mu g), stacks and a pyramid stand, mass ratios of 1000 rest without jitter, a bullet does
//! not pass through a thin wall, energy never grows, a sleeping box wakes when another lands on it, and springs are
//! semi-implicit Euler at the soft step's substeps.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use tumble::{
    Attachment, BodyHandle, FastSettings, FastSolver, Material, Method, Mode, ParticleBuilder, RigidBodyBuilder,
    Settings, Shape, SoftSolver, SpringBuilder, World,
};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 240.0;

fn fast_world(sleep: bool) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings { sleep, ..FastSettings::new(DT) })).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    w
}

fn cube(w: &mut World, half: f64, density: f64, at: Vector3<f64>) -> BodyHandle {
    let shape = Shape::cuboid(Vector3::repeat(half)).unwrap();
    w.add_body(RigidBodyBuilder::from_shape(shape, density).position(at).restitution(0.0).friction(0.5)).unwrap()
}

#[test]
fn a_box_resting_on_the_floor_stays_within_5e_6_m_for_10_s() {
    for sleep in [false, true] {
        let mut w = fast_world(sleep);
        let b = cube(&mut w, 0.5, 1000.0, Vector3::new(0.0, 0.0, 0.5));
        let run = w.run(10.0, 0.1).unwrap();
        let drift = (0..run.frames())
            .map(|f| (run.body_position(f, 1) - Vector3::new(0.0, 0.0, 0.5)).norm())
            .fold(0.0, f64::max);
        println!("measured: resting box, sleep {sleep}: drift {drift:.3e} m");
        // The issue's goal, 5e-6 m: the floor's soft contact carries the box's weight after sinking about
        // g / (2 pi f)^2 at f = 960 Hz (half of the 1,920 substeps a second), 2.7e-7 m measured.
        assert!(drift < 5e-6, "sleep {sleep}: drift {drift}");
        assert!(w.body(b).unwrap().orientation().angle() < 1e-6);
    }
}

#[test]
fn a_sliding_box_stops_after_v_squared_over_2_mu_g() {
    // mu = 0.5 for box and floor (combined: their geometric mean, 0.5). Semi-implicit Euler at a constant
    // deceleration a covers v^2 / (2 a) - v h / 2, h the substep (1/240 s in 8 substeps): 0.085% short at v = 3 m/s.
    let v = 3.0;
    let mut w = fast_world(false);
    let b = cube(&mut w, 0.25, 500.0, Vector3::new(0.0, 0.0, 0.25));
    let q = w.body(b).unwrap().orientation();
    w.set_body_state(b, Vector3::new(0.0, 0.0, 0.25), q, Vector3::new(v, 0.0, 0.0), Vector3::zeros()).unwrap();
    w.run(2.0, 0.5).unwrap();
    let body = w.body(b).unwrap();
    let expected = v * v / (2.0 * 0.5 * G);
    let travelled = body.position().x;
    println!("measured: sliding box stopped after {travelled:.5} m, v^2/(2 mu g) = {expected:.5} m");
    assert!(body.velocity().norm() < 1e-9, "still moving at {}", body.velocity().norm());
    let substep = DT / SoftSolver::default().substeps as f64;
    let discrete = expected - 0.5 * v * substep;
    // The last substep stops the box partway (friction holds it at rest): at most a h^2 = 1.3e-6 m of difference.
    assert!((travelled - discrete).abs() < 5e-6, "stopped after {travelled} m, expected {discrete} m");
    assert!(body.position().z - 0.25 < 1e-4, "it hopped: z = {}", body.position().z);
}

#[test]
fn twelve_substeps_hold_the_issues_stack_to_0_1_mm_and_its_slide_to_0_1_percent() {
    // The peer comparison's stack and slide (issue 13) with 12 substeps of the soft step instead of the default 8:
    // the contacts' stiffness cap rises with the substep rate (480 -> 720 Hz between boxes), so the stack's sink,
    // summed down its nine loaded contacts, falls by (8/12)^2; and the semi-implicit substep's v h / 2 shortfall of
    // the stop distance falls to 2 m/s x (1/2880 s) / 2 = 3.5e-4 m, 0.085% of v^2 / (2 mu g).
    let soft = SoftSolver { substeps: 12, ..SoftSolver::default() };
    let world = |mu: f64| {
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings { sleep: false, solver: FastSolver::Soft(soft), ..FastSettings::new(DT) }))
            .unwrap();
        w.add_ground(0.0, Material::new(0.0, mu)).unwrap();
        w
    };
    let body = |w: &mut World, half: f64, at: Vector3<f64>, v: Vector3<f64>, mu: f64| {
        let shape = Shape::cuboid(Vector3::repeat(half)).unwrap();
        w.add_body(RigidBodyBuilder::from_shape(shape, 500.0).position(at).velocity(v).restitution(0.0).friction(mu))
            .unwrap()
    };
    // stack: ten cubes of half extent 0.25 m, density 500, friction 0.6, 10 s at 1/240 s, every step measured
    let mut w = world(0.6);
    let stack: Vec<BodyHandle> = (0..10)
        .map(|k| body(&mut w, 0.25, Vector3::new(0.0, 0.0, 0.25 + 0.5 * k as f64), Vector3::zeros(), 0.6))
        .collect();
    let start: Vec<Vector3<f64>> = stack.iter().map(|&b| w.body(b).unwrap().position()).collect();
    let mut moved = 0.0f64;
    for _ in 0..2400 {
        w.step(DT).unwrap();
        for (&b, s) in stack.iter().zip(&start) {
            moved = moved.max((w.body(b).unwrap().position() - s).norm());
        }
    }
    println!("measured: 12 substeps, stack of 10 moved at most {moved:.3e} m in 10 s");
    // the issue's goal, 0.1 mm (0.049 mm measured; 0.136 mm with 8 substeps)
    assert!(moved <= 1e-4, "the stack moved {moved} m");
    // slide: a cube of half extent 0.2 m at 2 m/s on mu 0.5, 2 s
    let mut w = world(0.5);
    let b = body(&mut w, 0.2, Vector3::new(0.0, 0.0, 0.2), Vector3::new(2.0, 0.0, 0.0), 0.5);
    w.step(2.0).unwrap();
    let exact = 2.0 * 2.0 / (2.0 * 0.5 * G);
    let error = (w.body(b).unwrap().position().x - exact) / exact;
    println!("measured: 12 substeps, slide stop distance error {:+.4}%", error * 100.0);
    // the issue's goal, 0.1% (-0.085% measured, the substep's v h / 2)
    assert!(error.abs() <= 1e-3, "stop distance error {error}");
}

/// Largest displacement of any of `bodies` from where they started, over the run.
fn displacement(w: &mut World, bodies: &[BodyHandle], seconds: f64) -> f64 {
    let start: Vec<Vector3<f64>> = bodies.iter().map(|&b| w.body(b).unwrap().position()).collect();
    w.run(seconds, 0.5).unwrap();
    bodies.iter().zip(&start).map(|(&b, s)| (w.body(b).unwrap().position() - s).norm()).fold(0.0, f64::max)
}

/// A pyramid of 10 layers of 0.5 m cubes in a plane, each resting on two below (10 + 9 + ... + 1 = 55 boxes).
fn pyramid(w: &mut World) -> Vec<BodyHandle> {
    let mut pyramid = Vec::new();
    for layer in 0..10 {
        for k in 0..10 - layer {
            let x = (k as f64 + 0.5 * layer as f64) * 0.5;
            pyramid.push(cube(w, 0.25, 500.0, Vector3::new(x, 0.0, 0.25 + 0.5 * layer as f64)));
        }
    }
    pyramid
}

#[test]
fn a_stack_of_10_boxes_and_a_10_layer_pyramid_still_stand_after_10_s() {
    // Stack: ten 1 m cubes, each placed touching the one below. The top sinks as the soft contacts take the
    // weight of the boxes above them (about g / (2 pi f)^2 a box's weight, f = 480 Hz between boxes, summed down
    // the stack), 1.0e-4 m measured; a box that slid or tipped would move centimetres.
    let mut w = fast_world(true);
    let stack: Vec<BodyHandle> =
        (0..10).map(|k| cube(&mut w, 0.5, 500.0, Vector3::new(0.0, 0.0, 0.5 + k as f64))).collect();
    let moved = displacement(&mut w, &stack, 10.0);
    println!("measured: stack of 10 moved {moved:.3e} m in 10 s");
    assert!(moved < 2e-4, "the stack moved {moved} m");
    // Pyramid: 10 layers of 0.5 m cubes in a plane, each resting on two below (10 + 9 + ... + 1 = 55 boxes).
    let mut w = fast_world(true);
    let pyramid = pyramid(&mut w);
    assert_eq!(pyramid.len(), 55);
    let moved = displacement(&mut w, &pyramid, 10.0);
    println!("measured: pyramid of 55 moved {moved:.3e} m in 10 s");
    // half-size boxes, at most five layers of weight on a contact: 2.8e-5 m measured
    assert!(moved < 1e-4, "the pyramid moved {moved} m");
}

#[test]
fn a_resting_pyramid_keeps_its_manifolds_and_stays_put() {
    // The 55-box pyramid without sleep: once it rests, its pairs move far less than 1e-4 of a box's size a step,
    // so the narrow phase is skipped (each pair's manifold carried by its bodies) and the pairs are tested only
    // when they have moved. The pyramid must not creep meanwhile: every box within 1e-4 m over the last 5 s.
    let mut w = fast_world(false);
    let pyramid = pyramid(&mut w);
    w.step(2.0).unwrap();
    let before = w.report();
    let moved = displacement(&mut w, &pyramid, 5.0);
    let after = w.report();
    let steps = (after.integrator.steps - before.integrator.steps) as f64;
    // 55 boxes touch 10 floor contacts' and 90 pairs of neighbours: 100 pairs a step (a few more pass the broad phase)
    let checks = (after.collision_checks - before.collision_checks) as f64 / steps;
    println!("measured: resting pyramid, {checks:.2} narrow-phase tests a step, moved {moved:.3e} m in 5 s");
    assert!(checks < 5.0, "{checks} pair tests a step: the resting pairs' manifolds were not kept");
    assert!(moved < 1e-4, "the resting pyramid moved {moved} m");
}

#[test]
fn boxes_with_a_mass_ratio_of_1000_rest_on_each_other_without_jitter() {
    // A light box on a heavy one and a heavy box on a light one (densities 1 and 1000 kg/m^3): after settling,
    // neither moves by more than 1e-4 m nor keeps any speed above 1e-3 m/s (sleep off, so jitter would show).
    for (below, above) in [(1000.0, 1.0), (1.0, 1000.0)] {
        let mut w = fast_world(false);
        let a = cube(&mut w, 0.5, below, Vector3::new(0.0, 0.0, 0.5));
        let b = cube(&mut w, 0.5, above, Vector3::new(0.0, 0.0, 1.5));
        w.run(1.0, 0.5).unwrap();
        let moved = displacement(&mut w, &[a, b], 5.0);
        let speed = [a, b].iter().map(|&h| w.body(h).unwrap().velocity().norm()).fold(0.0, f64::max);
        println!("measured: densities {below}/{above}: moved {moved:.3e} m, speed {speed:.3e} m/s");
        assert!(moved < 1e-4 && speed < 1e-3, "densities {below}/{above}: moved {moved}, speed {speed}");
    }
}

#[test]
fn a_sphere_at_1000_m_per_s_does_not_pass_through_a_1_cm_wall() {
    let mut w = World::new();
    w.set_gravity(Vector3::zeros()).unwrap();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 60.0))).unwrap();
    let wall = Shape::cuboid(Vector3::new(0.005, 1.0, 1.0)).unwrap();
    w.add_body(RigidBodyBuilder::fixed(Some(wall)).position(Vector3::new(5.0, 0.0, 0.0))).unwrap();
    let ball = Shape::sphere(0.05).unwrap();
    let b = w
        .add_body(RigidBodyBuilder::from_shape(ball, 7800.0).velocity(Vector3::new(1000.0, 0.0, 0.0)).restitution(0.0))
        .unwrap();
    w.run(0.5, 1.0 / 60.0).unwrap();
    let x = w.body(b).unwrap().position().x;
    // It must end on the near side: centre at most at 5 - 0.005 - 0.05 (plus the 1e-3 m contact margin).
    println!("measured: bullet ends at x = {x:.6} m (wall face at 4.995, ball radius 0.05)");
    assert!(x <= 5.0 - 0.055 + 1e-3, "the ball is at x = {x}");
}

#[test]
fn energy_never_grows_in_a_pile_without_driving_forces() {
    // Boxes dropped onto each other with restitution up to 1: total energy (kinetic + gravity) never rises by more
    // than 1e-6 of its start between frames.
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(DT))).unwrap();
    w.add_ground(0.0, Material::new(0.5, 0.5)).unwrap();
    for k in 0..8 {
        let shape = Shape::cuboid(Vector3::new(0.3, 0.2, 0.25)).unwrap();
        let tilt = UnitQuaternion::from_euler_angles(0.3 * k as f64, 0.2, 0.1 * k as f64);
        w.add_body(
            RigidBodyBuilder::from_shape(shape, 700.0)
                .position(Vector3::new(0.2 * (k % 3) as f64, 0.1 * (k % 2) as f64, 0.5 + 0.7 * k as f64))
                .orientation(tilt)
                .restitution(if k % 2 == 0 { 1.0 } else { 0.3 }),
        )
        .unwrap();
    }
    let run = w.run(4.0, 1.0 / 60.0).unwrap();
    let e0 = run.energy(0);
    let rise = (1..run.frames()).map(|f| run.energy(f) - run.energy(f - 1)).fold(f64::MIN, f64::max);
    println!("measured: largest energy rise between frames {:.3e} of |E0|", rise / e0.abs());
    for f in 1..run.frames() {
        assert!(
            run.energy(f) <= run.energy(f - 1) + 1e-6 * e0.abs(),
            "frame {f}: {} -> {}",
            run.energy(f - 1),
            run.energy(f)
        );
    }
}

/// An elastic ball (e = 1, radius 0.1 m) dropped from 1 m onto the floor at h = 1/240 s with `solver`, no sleep,
/// for 4 s: (energy lost, energy lost in flight by the closed form below, bounces, mass).
fn elastic_ball(solver: FastSolver, substeps: usize) -> (f64, f64, usize, f64) {
    let h = 1.0 / 240.0;
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings { sleep: false, solver, ..FastSettings::new(h) })).unwrap();
    w.add_ground(0.0, Material::new(1.0, 0.0)).unwrap();
    let ball = Shape::sphere(0.1).unwrap();
    w.add_body(RigidBodyBuilder::from_shape(ball, 1000.0).position(Vector3::new(0.0, 0.0, 1.1)).restitution(1.0))
        .unwrap();
    let run = w.run(4.0, h).unwrap();
    let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.1f64.powi(3);
    let bounces =
        (1..run.frames()).filter(|&f| run.body_velocity(f, 1).z > 0.0 && run.body_velocity(f - 1, 1).z < 0.0).count();
    // semi-implicit Euler loses 1/2 m g^2 s^2 a step s of constant gravity:
    // E_{n+1} - E_n = 1/2 m (v - g s)^2 - 1/2 m v^2 + m g s (v - g s) = -1/2 m g^2 s^2; the soft step takes
    // `substeps` of h / substeps.
    let s = h / substeps as f64;
    let flight = 0.5 * m * G * G * s * s * ((run.frames() - 1) * substeps) as f64;
    (run.energy(0) - run.energy(run.frames() - 1), flight, bounces, m)
}

#[test]
fn an_elastic_ball_loses_only_semi_implicit_eulers_half_g_squared_h_squared_a_flight_step() {
    // Exact solver: a bounce step loses the same as a flight step (the ball leaves at e |v| less what gravity takes
    // over the rest of the step, |v| - g h), so the total over 4 s is the flight closed form, to 1e-6.
    let (loss, expected, bounces, _) = elastic_ball(FastSolver::exact(), 1);
    println!("measured: exact solver, elastic ball, {bounces} bounces: lost {loss:.9} J, closed form {expected:.9} J");
    assert!(bounces >= 4, "{bounces} bounces");
    assert!((loss - expected).abs() < 1e-6 * expected, "lost {loss} J, expected {expected} J");
    // Soft step: flight loses the closed form of its substeps; a bounce leaves at e times the speed the step started
    // with, so it loses at most what gravity added within that step, m |v| g h at the impact speed |v| <=
    // sqrt(2 g 1 m), and never gains.
    let substeps = SoftSolver::default().substeps;
    let (loss, flight, bounces, m) = elastic_ball(FastSolver::default(), substeps);
    let per_bounce = m * (2.0 * G).sqrt() * G / 240.0;
    println!("measured: soft step, {bounces} bounces: lost {loss:.6} J, flight {flight:.6} J, bound a bounce {per_bounce:.3} J");
    assert!(bounces >= 4, "{bounces} bounces");
    assert!(loss >= flight - 1e-9 && loss <= flight + bounces as f64 * per_bounce, "lost {loss} J");
}

#[test]
fn two_boxes_falling_together_after_a_bounce_solve_cleanly() {
    // The lower box bounces off the floor (e = 0.5) into the falling upper one; afterwards they fall together,
    // touching at zero relative velocity and zero gap. Regression: the answer's residual was measured against that
    // zero relative velocity and rejected ("misses complementarity by 5.7e8"); it is now measured against the
    // speeds of the contact points.
    for dt in [1.0 / 240.0, 0.01, 1.0 / 30.0] {
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings::new(dt))).unwrap();
        w.add_ground(0.0, Material::new(0.5, 0.5)).unwrap();
        let boxes: Vec<BodyHandle> =
            [1.0, 2.0].iter().map(|&z| cube(&mut w, 0.25, 500.0, Vector3::new(0.0, 0.0, z))).collect();
        let run = w.run(3.0, 0.05).unwrap();
        // Energy: never up by more than 1e-6 of its start, except what pushing out an interpenetration can add,
        // m g times the depth (Baumgarte's correction lifts the upper box by up to that; at 1/30 s a landing sinks
        // 8 mm in).
        let e0 = run.energy(0);
        let allowance = 2.0 * 500.0 * 0.125 * G * run.report.max_penetration;
        let rise = (1..run.frames()).map(|f| run.energy(f) - run.energy(f - 1)).fold(f64::MIN, f64::max);
        println!("measured: dt {dt}: largest energy rise {rise:.3e} J, allowance {allowance:.3e} J");
        assert!(rise <= 1e-6 * e0.abs() + allowance, "dt {dt}: energy rose by {rise} J");
        let z: Vec<f64> = boxes.iter().map(|&b| w.body(b).unwrap().position().z).collect();
        // stacked at the end: 0.25 and 0.75, to the penetration a step of 1/30 s leaves (erp 0.2): 1 cm
        assert!((z[0] - 0.25).abs() < 0.01 && (z[1] - 0.75).abs() < 0.01, "dt {dt}: heights {z:?}");
    }
}

#[test]
fn a_sleeping_box_wakes_when_another_lands_on_it_and_both_sleep_after() {
    // Box A rests on the floor and falls asleep (still for 0.5 s); box B, dropped from 10 m, lands on it at
    // t = sqrt(2 * 8.5 / g) = 1.32 s. A must wake at the impact (the report's sleepers drop to 0), carry B, and both
    // sleep once still again. While asleep, A does not move at all.
    let mut w = fast_world(true);
    let a = cube(&mut w, 0.5, 500.0, Vector3::new(0.0, 0.0, 0.5));
    let b = cube(&mut w, 0.5, 500.0, Vector3::new(0.0, 0.0, 10.0));
    w.step(1.0).unwrap();
    assert_eq!(w.report().sleepers, 1, "A asleep before B lands");
    let za = w.body(a).unwrap().position().z;
    let landing = (2.0 * 8.5 / G).sqrt();
    let mut woke = false;
    while w.time() < landing + 0.1 {
        w.step(DT).unwrap();
        if w.time() < landing - 0.02 {
            assert_eq!(w.body(a).unwrap().position().z, za, "a sleeping body does not move");
        }
        woke |= w.report().sleepers == 0;
    }
    assert!(woke, "A never woke when B landed on it");
    w.step(3.0).unwrap();
    let (za, zb) = (w.body(a).unwrap().position().z, w.body(b).unwrap().position().z);
    println!("measured: after the landing, A at z = {za:.6} m, B at z = {zb:.6} m, {} asleep", w.report().sleepers);
    assert_eq!(w.report().sleepers, 2, "both asleep at the end");
    // Resting on each other: to the 1e-3 m contact margin plus the slop the landing left (Baumgarte's 0.2 a step).
    assert!((za - 0.5).abs() < 2e-3 && (zb - 1.5).abs() < 2e-3, "A {za}, B {zb}");
}

#[test]
fn step_doubling_estimates_a_free_fall_step_error_as_its_closed_form_and_changes_nothing() {
    // Semi-implicit Euler in n substeps of s = h / n under gravity: a step of h moves by v h + g s^2 n (n + 1) / 2
    // (the velocity after substep k is v + k g s); two halves of n substeps of s / 2 move by v h + g (s/2)^2 2n (2n
    // + 1) / 2. They differ by g h^2 / (4 n) in position (velocities agree), which the estimate must report, to
    // the rounding of two 50 m positions (an ulp is 7e-15 m; 1e-13 m allows a few per step). The run itself must be
    // the same bits as without the estimate.
    let h = 1.0 / 240.0;
    let cube_at = |w: &mut World| {
        w.add_body(
            RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.1)).unwrap(), 500.0)
                .position(Vector3::new(0.0, 0.0, 50.0))
                .velocity(Vector3::new(1.0, 0.0, 2.0)),
        )
        .unwrap()
    };
    for (solver, n) in [(FastSolver::default(), SoftSolver::default().substeps), (FastSolver::exact(), 1)] {
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings { step_doubling: true, solver, ..FastSettings::new(h) })).unwrap();
        let b = cube_at(&mut w);
        w.step(0.5).unwrap();
        let expected = G * h * h / (4.0 * n as f64);
        let got = w.report().step_error.expect("step doubling reports its estimate");
        println!("measured: {} solver, step error {got:.6e} m, g h^2 / (4 n) = {expected:.6e} m", solver.name());
        assert!((got - expected).abs() < 1e-13, "{got} vs {expected}");
        let mut plain = World::new();
        plain.set_mode(Mode::Fast(FastSettings { solver, ..FastSettings::new(h) })).unwrap();
        let p = cube_at(&mut plain);
        plain.step(0.5).unwrap();
        assert_eq!(plain.report().step_error, None, "no estimate unless asked");
        let (x, y) = (w.body(b).unwrap().position(), plain.body(p).unwrap().position());
        assert_eq!(x.map(f64::to_bits), y.map(f64::to_bits), "the estimate changed the run");
    }
}

#[test]
fn an_undamped_spring_keeps_its_energy_in_fast_mode() {
    // A particle of the cloth drape's (0.3 / 144 kg) on an undamped spring of its stiffness (60 N/m) to a fixed
    // point, without gravity, at the drape's 1/480 s. Forces taken once a step and spread over the 8 substeps moved
    // it by 9/16 of h^2 F / m: the step's determinant was 1 + 7/16 h^2 k / m, and the spring blew up at 1.6 s.
    // Evaluated at every substep it is semi-implicit Euler at h / 8, whose energy oscillates by about h_s omega / 2
    // of itself (omega = sqrt(k / m) = 170 rad/s, h_s = 1/3840 s: 0.022) without drifting.
    let (m, k, dt) = (0.3 / 144.0, 60.0, 1.0 / 480.0);
    for solver in [FastSolver::default(), FastSolver::exact()] {
        let mut w = World::new();
        w.set_gravity(Vector3::zeros()).unwrap();
        w.set_mode(Mode::Fast(FastSettings { sleep: false, solver, ..FastSettings::new(dt) })).unwrap();
        let p = w.add_particle(ParticleBuilder::new(m).position(Vector3::new(0.12, 0.0, 1.0))).unwrap();
        let anchor = Attachment::Point(Vector3::new(0.0, 0.0, 1.0));
        w.add_spring(SpringBuilder::new(Attachment::Particle(p), anchor).stiffness(k).rest_length(0.1)).unwrap();
        let run = w.run(5.0, dt).unwrap();
        let start = run.energy(0);
        let worst = (0..run.frames()).map(|f| (run.energy(f) / start - 1.0).abs()).fold(0.0, f64::max);
        // the exact solver takes one semi-implicit Euler step of h: about h omega / 2 = 0.18
        let h = if solver == FastSolver::default() { dt / SoftSolver::default().substeps as f64 } else { dt };
        let bound = h * (k / m).sqrt();
        println!(
            "measured: {} solver, largest energy change over 5 s {worst:.3e} of its start (bound {bound:.3e})",
            solver.name()
        );
        assert!(worst < bound, "{}: {worst}", solver.name());
    }
}

#[test]
fn a_body_swinging_on_a_spring_follows_the_accurate_integration_to_first_order() {
    // A spinning body hung by a damped spring from a point 0.23 m off its centre of mass, 1 s: the soft step turns
    // the spring's arm with the body and applies its torque at every substep. Against dop853 at 1e-11 the end
    // position's error halves with the step (first order), as semi-implicit Euler's does; forces spread over
    // the substeps were 30 times further off (5.7e-2 m and 0.49 rad at 1/240 s).
    let build = |mode: Option<Mode>| {
        let mut w = World::new();
        match mode {
            Some(mode) => w.set_mode(mode).unwrap(),
            None => w.set_integrator(Settings::tolerances(Method::Dop853, 1e-11, 1e-11)).unwrap(),
        }
        let b = w
            .add_body(
                RigidBodyBuilder::new(2.0, Matrix3::from_diagonal(&Vector3::new(0.05, 0.08, 0.1)))
                    .position(Vector3::new(0.2, 0.0, 1.0))
                    .orientation(UnitQuaternion::from_euler_angles(0.3, 0.2, 0.1))
                    .angular_velocity(Vector3::new(1.0, -2.0, 0.5)),
            )
            .unwrap();
        let arm = Attachment::Body(b, Vector3::new(0.1, 0.05, 0.2));
        let point = Attachment::Point(Vector3::new(0.0, 0.0, 2.0));
        w.add_spring(SpringBuilder::new(arm, point).stiffness(400.0).damping(0.5).rest_length(0.6)).unwrap();
        w.run(1.0, 1.0).unwrap();
        let body = w.body(b).unwrap();
        (body.position(), body.orientation())
    };
    let (x, q) = build(None);
    let mut errors = Vec::new();
    for dt in [1.0 / 240.0, 1.0 / 480.0] {
        let (y, r) = build(Some(Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(dt) })));
        let (dx, angle) = ((y - x).norm(), r.angle_to(&q));
        println!("measured: body on a spring, fast mode at {dt:.3e} s: {dx:.3e} m, {angle:.3e} rad from dop853");
        errors.push((dx, angle));
    }
    // 1.8e-3 m and 2.4e-2 rad measured at 1/240 s
    assert!(errors[0].0 < 3e-3 && errors[0].1 < 4e-2, "{errors:?}");
    let ratio = errors[0].0 / errors[1].0;
    assert!((1.7..2.3).contains(&ratio), "position error ratio {ratio} for a halved step: {errors:?}");
}

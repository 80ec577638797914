//! Kinematic bodies: a keyframed paddle sweeps boxes off a table in both modes, following its path to 1e-9 m,
//! pushing the boxes at its own speed and never pushed back; its settings, files and copies.
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use crate::common;
use common::{random_shape, Lcg};
use nalgebra::{UnitQuaternion, Vector3};
use tumble::{FastSettings, Keyframes, Material, Mode, RigidBodyBuilder, Shape, World};

/// The paddle's path: still at x = -0.7 until 0.2 s, then across the table to x = 0.9 by 1.2 s (1.6 m/s).
fn paddle_path() -> Keyframes {
    let at = |x: f64| Vector3::new(x, 0.0, 0.1);
    Keyframes::new(vec![0.0, 0.2, 1.2], vec![at(-0.7), at(-0.7), at(0.9)], None).unwrap()
}

const SPEED: f64 = 1.6;

/// A body's place among a run's bodies.
fn index(run: &tumble::Run, b: tumble::BodyHandle) -> usize {
    run.bodies.iter().position(|&h| h == b).expect("recorded")
}

/// Every body's pose at a run's last frame.
fn last_poses(run: &tumble::Run) -> Vec<(Vector3<f64>, UnitQuaternion<f64>)> {
    let f = run.frames() - 1;
    (0..run.bodies.len()).map(|j| (run.body_position(f, j), run.body_orientation(f, j))).collect()
}

/// How far a kinematic body of the world is from its path's pose at the world's time (m, rad): the engine's own
/// state, read back after a step (a run's frames of a kinematic body are its path's by construction).
fn off_path(w: &World, k: tumble::BodyHandle, path: &Keyframes) -> (f64, f64) {
    let (b, want) = (w.body(k).unwrap(), path.pose_at(w.time()));
    ((b.position() - want.translation.vector).norm(), b.orientation().angle_to(&want.rotation))
}

/// Every body's pose in a world.
fn poses(w: &World) -> Vec<(Vector3<f64>, UnitQuaternion<f64>)> {
    w.bodies().map(|(_, b)| (b.position(), b.orientation())).collect()
}

/// A 1 m table (top at z = 0), three 0.1 m boxes on it in a row across the paddle's way, and the paddle.
fn table(fast: bool) -> (World, tumble::BodyHandle, Vec<tumble::BodyHandle>) {
    let mut w = World::new();
    if fast {
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
    }
    let top = Shape::cuboid(Vector3::new(0.5, 0.5, 0.05)).unwrap();
    w.add_body(RigidBodyBuilder::fixed(Some(top)).position(Vector3::new(0.0, 0.0, -0.05)).restitution(0.0)).unwrap();
    let cube = Shape::cuboid(Vector3::new(0.05, 0.05, 0.05)).unwrap();
    let boxes = (0..3)
        .map(|k| {
            let at = Vector3::new(-0.3, -0.3 + 0.3 * k as f64, 0.05);
            w.add_body(RigidBodyBuilder::from_shape(cube.clone(), 500.0).position(at).restitution(0.0).friction(0.4))
                .unwrap()
        })
        .collect();
    let blade = Shape::cuboid(Vector3::new(0.02, 0.6, 0.1)).unwrap();
    let paddle = w.add_body(RigidBodyBuilder::kinematic(Some(blade), paddle_path()).restitution(0.0)).unwrap();
    (w, paddle, boxes)
}

#[test]
fn a_keyframed_paddle_sweeps_boxes_off_a_table_in_both_modes() {
    let path = paddle_path();
    for fast in [false, true] {
        // the paddle is where its keyframes put it after every step (1e-9 m: the steps' rounding)
        let (mut probe, paddle, _) = table(fast);
        for _ in 0..90 {
            probe.step(1.0 / 60.0).unwrap();
            let (miss, turn) = off_path(&probe, paddle, &path);
            assert!(miss < 1e-9 && turn < 1e-9, "fast {fast}: {miss:e} m off its path at t = {}", probe.time());
        }
        let (mut w, paddle, boxes) = table(fast);
        let run = w.run(1.5, 1.0 / 60.0).unwrap();
        let j = index(&run, paddle);
        assert_eq!(run.body_position(run.frames() - 1, j), path.pose_at(1.5).translation.vector);
        // while the paddle pushes (the boxes touch it from 0.45 s), each box moves at the paddle's speed: no
        // restitution, so contact holds; accurate mode to its contact tolerance, fast mode's soft contact to 1%
        let f = run.times.iter().position(|&t| t >= 0.9).unwrap();
        for &b in &boxes {
            let v = run.body_velocity(f, index(&run, b)).x;
            let tolerance = if fast { 1e-2 } else { 1e-5 } * SPEED;
            assert!((v - SPEED).abs() < tolerance, "fast {fast}: a pushed box moves at {v} m/s, the paddle {SPEED}");
        }
        // every box ends off the table, below its top
        for &b in &boxes {
            let z = w.body(b).unwrap().position().z;
            assert!(z < -0.05, "fast {fast}: a box is still at z = {z}");
        }
        // the boxes never sink into the paddle past the mode's bound: accurate mode's contact tolerance, fast
        // mode's speculative margin (a step at the paddle's speed, 1.6 / 240 = 6.7 mm, bounds any overlap)
        let bound = if fast { SPEED / 240.0 } else { run.report.contact_tolerance.expect("contact stages ran") };
        assert!(run.report.max_penetration <= bound, "fast {fast}: {} m deep", run.report.max_penetration);
    }
}

#[test]
fn a_turning_kinematic_body_follows_its_slerp() {
    // a turntable half a turn in 1 s (pi rad/s about z) carrying nothing: fast mode lands on the path every step;
    // accurate mode's integration holds the turn to its error tolerance, and lands on it at each keyframe
    let half = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 3.0));
    let path = Keyframes::new(
        vec![0.0, 1.0],
        vec![Vector3::zeros(), Vector3::new(0.5, 0.0, 0.0)],
        Some(vec![UnitQuaternion::identity(), half]),
    )
    .unwrap();
    for fast in [false, true] {
        let mut w = World::new();
        if fast {
            w.set_mode(Mode::Fast(FastSettings::new(0.01))).unwrap();
        }
        let plate = Shape::cuboid(Vector3::new(0.5, 0.5, 0.05)).unwrap();
        let b = w.add_body(RigidBodyBuilder::kinematic(Some(plate), path.clone())).unwrap();
        // after every step: fast mode lands on the path; accurate mode puts it back on after each accepted
        // step of its integration (contact steps turn it exactly)
        for _ in 0..15 {
            w.step(0.1).unwrap();
            let (miss, turn) = off_path(&w, b, &path);
            assert!(miss < 1e-9 && turn < 1e-9, "fast {fast}: {miss:e} m, {turn:e} rad off at t = {}", w.time());
        }
        // past its last keyframe it rests exactly there
        let end = w.body(b).unwrap();
        assert!(end.orientation().angle_to(&half) < 1e-12 && end.velocity() == Vector3::zeros());
        assert_eq!(end.angular_velocity(), Vector3::zeros());
    }
}

#[test]
fn a_kinematic_body_reports_its_path_velocity_and_has_no_mass() {
    let (mut w, paddle, _) = table(false);
    w.step(0.5).unwrap();
    let p = w.body(paddle).unwrap();
    assert!(p.is_kinematic() && !p.is_static());
    assert_eq!(p.mass(), f64::INFINITY);
    assert_eq!(p.velocity(), Vector3::new(SPEED, 0.0, 0.0));
    assert!((p.position().x - (-0.7 + SPEED * 0.3)).abs() < 1e-9);
}

#[test]
fn what_a_kinematic_body_cannot_take_is_an_error_naming_it() {
    let path = paddle_path();
    let cube = || Some(Shape::cuboid(Vector3::new(0.1, 0.1, 0.1)).unwrap());
    let named = |b: RigidBodyBuilder| World::new().add_body(b).unwrap_err().argument();
    let k = || RigidBodyBuilder::kinematic(cube(), path.clone());
    assert_eq!(named(k().position(Vector3::new(1.0, 0.0, 0.0))), Some("position"));
    assert_eq!(named(k().orientation(UnitQuaternion::from_scaled_axis(Vector3::x()))), Some("orientation"));
    assert_eq!(named(k().velocity(Vector3::x())), Some("velocity"));
    assert_eq!(named(k().linear_damping(1.0)), Some("linear_damping"));
    assert_eq!(named(k().shape(Shape::half_space(Vector3::z()).unwrap())), Some("shape"));
    let (mut w, paddle, _) = table(true);
    let load = w.add_force(tumble::Target::Body(paddle), Vector3::x(), None).unwrap_err();
    assert_eq!(load.argument(), Some("target"));
    let set =
        w.set_body_state(paddle, Vector3::zeros(), UnitQuaternion::identity(), Vector3::zeros(), Vector3::zeros());
    assert_eq!(set.unwrap_err().argument(), Some("body"));
}

#[test]
fn files_copies_and_pauses_keep_a_kinematic_run_to_the_bit() {
    for fast in [false, true] {
        let (mut w, _, _) = table(fast);
        w.step(0.5).unwrap();
        let json = tumble::World::from_json(&w.to_json().unwrap()).unwrap();
        let binary = tumble::World::from_bytes(&w.to_bytes().unwrap()).unwrap();
        let mut copies = [w.clone(), json, binary];
        let whole = w.run(0.6, 0.05).unwrap();
        for c in &mut copies[..] {
            let again = c.run(0.6, 0.05).unwrap();
            assert_eq!(last_poses(&again), last_poses(&whole), "fast {fast}: a copy ran differently");
        }
        // recording frames changes nothing: a step of the same span ends on the same bits
        let (mut a, _, _) = table(fast);
        a.step(0.5).unwrap();
        a.step(0.6).unwrap();
        assert_eq!(poses(&a), poses(&w), "fast {fast}: pausing changed the run");
    }
}

#[test]
fn a_ball_sliding_off_a_table_edge_falls_from_the_edge() {
    // A frictionless 0.05 m ball slides at 1.6 m/s towards the edge of a table (x = 0.5) and leaves it there
    // (v^2 = 2.56 > g r = 0.49: it does not roll round the edge), then falls freely: at 0.2 s past the edge it is
    // g (0.2 s)^2 / 2 = 0.196 m lower. At a steady speed the contact steps' error estimates see nothing; the step
    // that crosses the edge slides at most a tenth of the ball's radius (5 mm, 3.1 ms late), which costs
    // g 0.2 s 3.1 ms = 6.1 mm of height at most: the tolerance is 7 mm.
    let mut w = World::new();
    let top = Shape::cuboid(Vector3::new(0.5, 0.5, 0.05)).unwrap();
    w.add_body(RigidBodyBuilder::fixed(Some(top)).position(Vector3::new(0.0, 0.0, -0.05)).friction(0.0)).unwrap();
    let ball = RigidBodyBuilder::from_shape(Shape::sphere(0.05).unwrap(), 500.0)
        .position(Vector3::new(-0.3, 0.0, 0.05))
        .velocity(Vector3::new(SPEED, 0.0, 0.0))
        .friction(0.0)
        .restitution(0.0);
    let b = w.add_body(ball).unwrap();
    let t_edge = 0.8 / SPEED;
    w.step(t_edge + 0.2).unwrap();
    let x = w.body(b).unwrap().position();
    let fall = 0.5 * 9.81 * 0.2 * 0.2;
    println!("measured: the ball is {:.2e} m from free fall from the edge", x.z - (0.05 - fall));
    assert!((x.z - (0.05 - fall)).abs() < 7e-3, "the ball is at z = {}, free fall from the edge {}", x.z, 0.05 - fall);
    assert!((x.x - (-0.3 + SPEED * (t_edge + 0.2))).abs() < 1e-6, "x = {}", x.x);
}

/// A seeded random push: one to three random shapes (random orientations, densities, frictions, restitutions) on
/// the ground, and a random kinematic wall (a box 0.04 to 0.2 m thick, 0.4 to 1.2 m wide, from just above the
/// ground to 0.9 m up, so that it pushes from the side and cannot squeeze a body into the ground, which no solver
/// could undo) sweeping into them on a straight path at 0.6 to 3 m/s, turning about the vertical at up to 3 rad/s,
/// from 0.1 s to 0.9 s; with the peak speed of any of its points. The bodies stand 1.2 m apart (none reaches
/// 0.52 m from its centre): nothing overlaps at the start.
fn random_push(seed: u64) -> (World, tumble::BodyHandle, Keyframes, f64) {
    let mut rng = Lcg(seed.wrapping_mul(104_729).wrapping_add(3));
    let mut w = World::new();
    w.add_ground(0.0, Material::new(rng.range(0.0, 0.6), rng.range(0.0, 1.0))).unwrap();
    let count = 1 + (rng.next() * 3.0) as usize;
    for k in 0..count {
        let shape = random_shape(&mut rng);
        let q = UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        let at = Vector3::new(1.2 * k as f64 - 1.0, rng.range(-0.2, 0.2), 0.0);
        let b = w
            .add_body(
                RigidBodyBuilder::from_shape(shape, rng.range(100.0, 3000.0))
                    .position(at)
                    .orientation(q)
                    .restitution(rng.range(0.0, 0.6))
                    .friction(rng.range(0.0, 1.0)),
            )
            .unwrap();
        // lifted to 1 mm above the ground (a hull's collider sits off its centre of mass)
        let body = w.body(b).unwrap();
        let low = body
            .colliders()
            .iter()
            .map(|c| c.shape.aabb(&(body.pose() * c.offset)).unwrap().min.z)
            .fold(f64::MAX, f64::min);
        let lifted = body.position() + Vector3::new(0.0, 0.0, 1e-3 - low);
        w.set_body_state(b, lifted, q, Vector3::zeros(), Vector3::zeros()).unwrap();
    }
    let half = Vector3::new(rng.range(0.02, 0.1), rng.range(0.2, 0.6), 0.45);
    let wall = Shape::cuboid(half).unwrap();
    let speed = rng.range(0.6, 3.0);
    let spin = rng.range(0.0, 3.0);
    let z = half.z + 2e-3;
    let (start, end) = (Vector3::new(-1.9, 0.0, z), Vector3::new(-1.9 + 0.8 * speed, 0.0, z));
    let turn = UnitQuaternion::from_scaled_axis(Vector3::z() * spin * 0.8);
    let path = Keyframes::new(
        vec![0.0, 0.1, 0.9],
        vec![start, start, end],
        Some(vec![UnitQuaternion::identity(), UnitQuaternion::identity(), turn]),
    )
    .unwrap();
    let k = w.add_body(RigidBodyBuilder::kinematic(Some(wall), path.clone()).friction(rng.range(0.0, 1.0))).unwrap();
    (w, k, path, speed + spin * half.xy().norm())
}

#[test]
fn random_kinematic_pushes_follow_the_path_stay_finite_and_bounded_in_both_modes() {
    for seed in 0..8 {
        for fast in [false, true] {
            let (mut w, k, path, peak) = random_push(seed);
            if fast {
                w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
            }
            let (mut fastest, mut deep) = (0.0f64, 0.0f64);
            for _ in 0..36 {
                w.step(1.0 / 30.0).unwrap_or_else(|e| panic!("seed {seed} fast {fast}: {e}"));
                // on its path after every step, to the steps' rounding
                let (miss, turn) = off_path(&w, k, &path);
                assert!(miss < 1e-9 && turn < 1e-9, "seed {seed} fast {fast}: {miss:e} m, {turn:e} rad off");
                for (h, b) in w.bodies().filter(|(h, b)| *h != k && !b.is_static()) {
                    let v = b.velocity();
                    assert!(v.iter().all(|c| c.is_finite()), "seed {seed} fast {fast}: {h:?} not finite");
                    fastest = fastest.max(v.norm());
                }
                deep = deep.max(w.report().max_penetration);
            }
            // a push gives a body at most (1 + e) times the pusher's fastest point's speed (e <= 0.6), and gravity
            // 9.81 m/s^2 over the 1.2 s more; 1 m/s more for the spin a corner struck off centre can pick up
            let bound = 1.6 * peak + 9.81 * 1.2 + 1.0;
            assert!(fastest < bound, "seed {seed} fast {fast}: a body moves at {fastest} m/s, bound {bound}");
            // penetration: fast mode's random drops' bound (1 cm); accurate mode's ten times its tolerance (random
            // drops sink up to about that, docs/modes.md)
            let allowed = if fast { 1e-2 } else { 10.0 * w.report().contact_tolerance.unwrap_or(0.0) };
            println!("measured: seed {seed} fast {fast}: penetration {deep:.2e} m (bound {allowed:.2e}), fastest {fastest:.2} m/s");
            assert!(deep <= allowed, "seed {seed} fast {fast}: {deep} m deep, bound {allowed}");
        }
    }
}

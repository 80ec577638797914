//! The joints that hold some motions and free others, against closed forms: a rope slack until taut, a piston that
//! slides and turns about its axis, a drive that spins or slides its body up to its speed.
// (with joints.rs's scenes, which need clarabel)
#![cfg(feature = "clarabel")]

use crate::joints::{accurate, fast, G};
use nalgebra::{Matrix3, Vector3};
use tumble::{JointBuilder, RigidBodyBuilder, World};

#[test]
fn a_rope_is_slack_until_taut_then_holds_in_both_modes() {
    // a 1 kg ball on a 1 m rope from the origin, started 0.5 m to the side of it at rest: it falls freely until the
    // rope is taut (at t = sqrt(2 * sqrt(0.75) / g), when it has fallen sqrt(1 - 0.25) m), then swings on it
    for accurate_mode in [false, true] {
        let mut w = if accurate_mode { accurate(1e-9) } else { fast(8) };
        let bob = w
            .add_body(RigidBodyBuilder::new(1.0, Matrix3::identity() * 1e-3).position(Vector3::new(0.5, 0.0, 0.0)))
            .unwrap();
        w.add_joint(JointBuilder::rope(None, Some(bob), Some(1.0))).unwrap();
        // free fall before the rope is taut: the fast mode's substeps are semi-implicit Euler (error h g t / 2)
        w.step(0.2).unwrap();
        let z = w.body(bob).unwrap().position().z;
        let tolerance = if accurate_mode { 1e-9 } else { 0.5 * (1.0 / 480.0) * G * 0.2 + 1e-12 };
        assert!((z + 0.5 * G * 0.04).abs() < tolerance, "accurate {accurate_mode}: z {z}");
        let mut longest = 0.0f64;
        for _ in 0..120 {
            w.step(1.0 / 60.0).unwrap();
            longest = longest.max(w.body(bob).unwrap().position().norm());
        }
        // taut, it holds: measured 1 + 1e-14 m (accurate), 1 + 1.5e-5 m (fast); bound 1 + 1e-3 m
        eprintln!("rope accurate {accurate_mode}: longest {longest}");
        assert!(longest < 1.0 + 1e-3 && longest > 0.999, "accurate {accurate_mode}: {longest}");
    }
}

#[test]
fn a_piston_slides_and_turns_about_its_axis_and_holds_the_rest() {
    // A ball (1 kg, 0.1 m) on a vertical piston from the world at the origin, thrown up at 0.5 m/s while spinning
    // at 3 rad/s about the axis, with a torque of 2 N m about x and a force of 5 N along x pushing it over: it rises
    // and falls freely along the axis (z = 0.5 t - g t^2 / 2), keeps its spin (nothing turns it about z), and
    // neither tilts nor leaves the axis. Accurate mode to its tolerance, fast mode to its soft joints' millimetre. Its
    // travel's and its turn's limits hold.
    for fast_mode in [false, true] {
        let mut w = if fast_mode { fast(8) } else { accurate(1e-9) };
        let ball = RigidBodyBuilder::from_shape_with_mass(tumble::Shape::sphere(0.1).unwrap(), 1.0)
            .velocity(Vector3::new(0.0, 0.0, 0.5))
            .angular_velocity(Vector3::new(0.0, 0.0, 3.0));
        let b = w.add_body(ball).unwrap();
        w.add_joint(JointBuilder::piston(None, Some(b), Vector3::z())).unwrap();
        w.add_torque(b, Vector3::new(2.0, 0.0, 0.0)).unwrap();
        w.add_force(tumble::Target::Body(b), Vector3::new(5.0, 0.0, 0.0), None).unwrap();
        w.step(1.0).unwrap();
        let body = w.body(b).unwrap();
        let (x, v, spin) = (body.position(), body.velocity(), body.angular_velocity());
        let tolerance = if fast_mode { 1e-3 } else { 1e-6 };
        // (fast mode's semi-implicit substeps fall g h t / 2 further, h = 1/480 s: 10.2 mm)
        let z = 0.5 - 0.5 * G - if fast_mode { 0.5 * G / 480.0 } else { 0.0 };
        assert!((x.z - z).abs() < tolerance * 10.0, "fast {fast_mode}: z = {}, free {z}", x.z);
        assert!((v.z - (0.5 - G)).abs() < tolerance * 10.0, "fast {fast_mode}: vz = {}", v.z);
        assert!(x.xy().norm() < tolerance, "fast {fast_mode}: off the axis by {}", x.xy().norm());
        assert!((spin.z - 3.0).abs() < tolerance, "fast {fast_mode}: spin {}", spin.z);
        assert!(spin.xy().norm() < tolerance, "fast {fast_mode}: tilting at {}", spin.xy().norm());
        // the travel's limits hold it: from 0.1 m below to 0.2 m above where it started
        let mut w = if fast_mode { fast(8) } else { accurate(1e-9) };
        let b = w.add_body(RigidBodyBuilder::from_shape_with_mass(tumble::Shape::sphere(0.1).unwrap(), 1.0)).unwrap();
        w.add_joint(JointBuilder::piston(None, Some(b), Vector3::z()).limits(-0.1, 0.2)).unwrap();
        w.step(1.0).unwrap();
        let z = w.body(b).unwrap().position().z;
        assert!((z + 0.1).abs() < tolerance * 10.0, "fast {fast_mode}: rests at {z}, the limit -0.1");
        // its turn's limits stop a spin: a ball spun at 3 rad/s about the axis, with a turn limit of 0.5 rad, comes
        // to rest there (an inelastic stop) while it slides on freely
        let mut w = if fast_mode { fast(8) } else { accurate(1e-9) };
        let ball = RigidBodyBuilder::from_shape_with_mass(tumble::Shape::sphere(0.1).unwrap(), 1.0)
            .angular_velocity(Vector3::new(0.0, 0.0, 3.0));
        let b = w.add_body(ball).unwrap();
        w.add_joint(JointBuilder::piston(None, Some(b), Vector3::z()).turn_limits(-0.2, 0.5)).unwrap();
        // (through a file, which keeps them)
        let mut w = World::from_json(&w.to_json().unwrap()).unwrap();
        w.step(1.0).unwrap();
        let (_, body) = w.bodies().last().unwrap();
        let turn = body.orientation().scaled_axis();
        assert!((turn.z - 0.5).abs() < tolerance * 10.0, "fast {fast_mode}: turned {} rad, the limit 0.5", turn.z);
        assert!(body.angular_velocity().norm() < tolerance * 10.0, "fast {fast_mode}: {}", body.angular_velocity());
        let free = -0.5 * G - if fast_mode { 0.5 * G / 480.0 } else { 0.0 };
        assert!((body.position().z - free).abs() < tolerance * 10.0, "fast {fast_mode}: z = {}", body.position().z);
    }
}

#[test]
fn a_drive_spins_or_slides_its_body_up_to_its_speed_and_holds_nothing_else() {
    // A 0.2 m cube of 1 kg (I = m a^2 / 6 = 1/150 kg m^2) driven from the world about z at 2 rad/s with at most
    // 0.01 N m: it spins up at 1.5 rad/s^2 until 2 rad/s (at 4/3 s), and falls freely meanwhile (the drive holds
    // nothing): -g t^2 / 2. A slide drive along x at 0.5 m/s with at most 1 N: v = t until 0.5 s, then 0.5 m/s.
    // Both modes to 1e-6 (the motor holds its speed exactly within its torque; fast mode falls g h t / 2 further).
    for fast_mode in [false, true] {
        let tolerance = 1e-6;
        let cube = || RigidBodyBuilder::from_shape_with_mass(tumble::Shape::cuboid(Vector3::repeat(0.1)).unwrap(), 1.0);
        let mut w = if fast_mode { fast(8) } else { accurate(1e-9) };
        let b = w.add_body(cube()).unwrap();
        w.add_joint(JointBuilder::spin_drive(None, Some(b), Vector3::z()).motor(2.0, 0.01)).unwrap();
        w.step(1.0).unwrap();
        let spin = w.body(b).unwrap().angular_velocity();
        assert!((spin.z - 1.5).abs() < tolerance, "fast {fast_mode}: spin {} after 1 s, 1.5 rad/s", spin.z);
        let fall = 0.5 * G + if fast_mode { 0.5 * G / 480.0 } else { 0.0 };
        let z = w.body(b).unwrap().position().z;
        assert!((z + fall).abs() < tolerance, "fast {fast_mode}: z = {z}, free fall {}", -fall);
        w.step(1.0).unwrap();
        let spin = w.body(b).unwrap().angular_velocity();
        assert!((spin.z - 2.0).abs() < tolerance, "fast {fast_mode}: spin {} after 2 s, the drive's 2 rad/s", spin.z);
        let mut w = if fast_mode { fast(8) } else { accurate(1e-9) };
        w.set_gravity(Vector3::zeros()).unwrap();
        let b = w.add_body(cube()).unwrap();
        w.add_joint(JointBuilder::slide_drive(None, Some(b), Vector3::x()).motor(0.5, 1.0)).unwrap();
        w.step(0.25).unwrap();
        let v = w.body(b).unwrap().velocity();
        assert!((v.x - 0.25).abs() < tolerance && v.yz().norm() < 1e-9, "fast {fast_mode}: v = {v}");
        w.step(0.75).unwrap();
        let v = w.body(b).unwrap().velocity();
        assert!((v.x - 0.5).abs() < tolerance, "fast {fast_mode}: v = {v}, the drive's 0.5 m/s");
    }
    // a drive is its motor alone
    let mut w = World::new();
    let b = w.add_body(RigidBodyBuilder::from_shape_with_mass(tumble::Shape::sphere(0.1).unwrap(), 1.0)).unwrap();
    let refused = w.add_joint(JointBuilder::spin_drive(None, Some(b), Vector3::z())).unwrap_err();
    assert_eq!(refused.argument(), Some("motor"));
    let refused = w.add_joint(JointBuilder::spin_drive(None, Some(b), Vector3::z()).motor(1.0, 1.0).limits(0.0, 1.0));
    assert_eq!(refused.unwrap_err().argument(), Some("limits"));
}

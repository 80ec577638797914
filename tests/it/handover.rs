//! Hand-over between keyframes and physics, in both modes: a keyframed box let go flies on with the velocity and
//! spin its path had (closed form: the centre of mass on a parabola, the spin kept); a falling ball taken over stays
//! where it was; bad hand-overs are refused by name and change nothing.

use nalgebra::{UnitQuaternion, Vector3};
use tumble::{FastSettings, Keyframes, Mode, RigidBodyBuilder, Shape, World};

const G: f64 = 9.81;

fn modes() -> [(Mode, &'static str); 2] {
    [(Mode::default(), "accurate"), (Mode::Fast(FastSettings::new(1.0 / 240.0)), "fast")]
}

#[test]
fn a_keyframed_box_let_go_flies_on_as_its_path_moved() {
    for (mode, name) in modes() {
        let mut w = World::new();
        w.set_mode(mode).unwrap();
        // 1 m/s along x and 2 rad/s about z over the first second, at 1 m
        let path = Keyframes::new(
            vec![0.0, 1.0],
            vec![Vector3::new(0.0, 0.0, 1.0), Vector3::new(1.0, 0.0, 1.0)],
            Some(vec![UnitQuaternion::identity(), UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 2.0)]),
        )
        .unwrap();
        let b = w
            .add_body(RigidBodyBuilder::kinematic(Some(Shape::cuboid(Vector3::new(0.1, 0.2, 0.3)).unwrap()), path))
            .unwrap();
        w.step(0.5).unwrap();
        w.release(b, Some(500.0)).unwrap();
        let body = w.body(b).unwrap();
        assert!(!body.is_kinematic() && (body.mass() - 500.0 * 0.2 * 0.4 * 0.6).abs() < 1e-12, "{name}");
        w.step(0.5).unwrap();
        let body = w.body(b).unwrap();
        // after release the centre flies on: x = 0.5 + 1 * 0.5, z = 1 - g 0.5^2 / 2; the spin kept (a box about a
        // principal axis). Accurate mode to its integrator's tolerance (1e-6 of a state of order 1); fast mode's
        // semi-implicit Euler gains g h t / 2 in height (5e-3 m at h = 1/240 s over 0.5 s)
        let tol = if name == "accurate" { 1e-6 } else { G * 0.5 / 240.0 };
        let want = Vector3::new(1.0, 0.0, 1.0 - 0.5 * G * 0.25);
        assert!((body.position() - want).norm() < tol, "{name}: {} against {want}", body.position());
        assert!((body.angular_velocity() - Vector3::new(0.0, 0.0, 2.0)).norm() < 1e-9, "{name}");
    }
}

#[test]
fn a_falling_ball_taken_over_stays_and_let_go_falls_from_rest() {
    for (mode, name) in modes() {
        let mut w = World::new();
        w.set_mode(mode).unwrap();
        let b = w
            .add_body(
                RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0).position(Vector3::new(0.0, 0.0, 2.0)),
            )
            .unwrap();
        w.step(0.25).unwrap();
        w.hold(b, None).unwrap();
        let held = w.body(b).unwrap().position();
        w.step(0.25).unwrap();
        assert_eq!(w.body(b).unwrap().position(), held, "{name}: held where it was");
        w.release(b, None).unwrap();
        w.step(0.5).unwrap();
        let z = w.body(b).unwrap().position().z;
        let tol = if name == "accurate" { 1e-6 } else { G * 0.5 / 240.0 };
        assert!((z - (held.z - 0.5 * G * 0.25)).abs() < tol, "{name}: falls from rest, {z}");
    }
}

#[test]
fn bad_hand_overs_are_refused_by_name_and_change_nothing() {
    let mut w = World::new();
    let ball = w.add_body(RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0)).unwrap();
    let ground = w.add_ground(0.0, Default::default()).unwrap();
    let path = Keyframes::new(vec![0.0], vec![Vector3::zeros()], None).unwrap();
    let shapeless = w.add_body(RigidBodyBuilder::kinematic(None, path.clone())).unwrap();
    let keyed = w.add_body(RigidBodyBuilder::kinematic(Some(Shape::sphere(0.1).unwrap()), path)).unwrap();
    let json = w.to_json().unwrap();
    let named = |e: tumble::WorldError| e.argument().unwrap_or_default();
    assert_eq!(named(w.release(ball, None).unwrap_err()), "body");
    assert_eq!(named(w.release(shapeless, None).unwrap_err()), "body");
    assert_eq!(named(w.release(keyed, Some(-1.0)).unwrap_err()), "density");
    assert_eq!(named(w.hold(ground, None).unwrap_err()), "body");
    assert_eq!(named(w.hold(keyed, None).unwrap_err()), "body");
    assert_eq!(w.to_json().unwrap(), json, "nothing changed");
}

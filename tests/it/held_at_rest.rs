//! Rest inside a moving island (accurate mode): a box at rest on a plank that a ball rolls along is held while the
//! ball rolls (its island still moves, so it cannot sleep as a whole), costs no solve, and wakes when the ball
//! reaches it, moving as it does when nothing is held; a held world saves, loads and copies with the same bits.

use crate::common;

use common::state_bits;
use nalgebra::Vector3;
use tumble::{AccurateSettings, Material, Mode, RigidBodyBuilder, Shape, World};

/// A plank (2 m x 0.4 m x 2 cm) on the ground, a 10 cm box resting on its far end and a ball rolling along it from
/// the near end at 0.8 m/s; `sleep` on or off. Returns the world, the box and the ball.
fn plank(sleep: bool) -> (World, tumble::BodyHandle, tumble::BodyHandle) {
    let mut w = World::new();
    w.set_threads(1).unwrap();
    let settings = AccurateSettings { sleep, contact_tolerance: Some(1e-4), ..AccurateSettings::default() };
    w.set_mode(Mode::Accurate(settings)).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.6)).unwrap();
    let slab = Shape::cuboid(Vector3::new(1.0, 0.2, 0.01)).unwrap();
    w.add_body(RigidBodyBuilder::from_shape(slab, 500.0).position(Vector3::new(0.0, 0.0, 0.01))).unwrap();
    let cube = Shape::cuboid(Vector3::repeat(0.05)).unwrap();
    let b = w.add_body(RigidBodyBuilder::from_shape(cube, 300.0).position(Vector3::new(0.8, 0.0, 0.07))).unwrap();
    let r = 0.04;
    let (v, at) = (0.8, Vector3::new(-0.9, 0.0, 0.02 + r));
    let ball = RigidBodyBuilder::from_shape(Shape::sphere(r).unwrap(), 2000.0)
        .position(at)
        .velocity(Vector3::new(v, 0.0, 0.0))
        .angular_velocity(Vector3::new(0.0, v / r, 0.0));
    let ball = w.add_body(ball).unwrap();
    (w, b, ball)
}

#[test]
fn a_box_at_rest_beside_a_rolling_ball_is_held_and_wakes_when_the_ball_reaches_it() {
    let (mut w, b, ball) = plank(true);
    // 1.2 s: the box and the plank have been calm for the sleep time while the ball still rolls (1 m to go)
    w.run(1.2, 1.0 / 60.0).unwrap();
    let r = w.report();
    assert!(r.sleepers >= 2, "the box and the plank are held: {} resting", r.sleepers);
    assert!(w.body(ball).unwrap().velocity().x > 0.5, "the ball still rolls");
    let start = w.body(b).unwrap().position();
    // the ball reaches the box about 2.1 s in and pushes it along
    w.run(1.8, 1.0 / 60.0).unwrap();
    let moved = w.body(b).unwrap().position() - start;
    // the same world with nothing held: the box ends where it does there, to 5 mm (the two runs differ by the holds'
    // zeroed velocities, under the resting speed, and by the contact tolerance of 0.1 mm a step through the impact)
    let (mut free, fb, _) = plank(false);
    let free_start = free.body(fb).unwrap().position();
    free.run(3.0, 1.0 / 60.0).unwrap();
    let free_moved = free.body(fb).unwrap().position() - free_start;
    println!("measured: the box moved {:.4} m held, {:.4} m never held", moved.x, free_moved.x);
    assert!(free_moved.x > 0.02, "the ball pushes the box: {free_moved}");
    assert!((moved - free_moved).norm() < 5e-3, "held {moved} against never held {free_moved}");
}

#[test]
fn a_world_with_held_bodies_saves_loads_and_copies_with_the_same_bits() {
    let (mut w, _, _) = plank(true);
    w.run(1.2, 1.0 / 60.0).unwrap();
    assert!(w.report().sleepers >= 2);
    let mut json = World::from_json(&w.to_json().unwrap()).unwrap();
    let mut bytes = World::from_bytes(&w.to_bytes().unwrap()).unwrap();
    let mut copy = w.clone();
    let mut two = w.clone();
    two.set_threads(2).unwrap();
    w.step(1.5).unwrap();
    for other in [&mut json, &mut bytes, &mut copy, &mut two] {
        other.step(1.5).unwrap();
        assert_eq!(state_bits(other), state_bits(&w));
    }
}

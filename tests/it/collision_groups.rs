//! Collision groups: two bodies touch only if their groups share a bit, in both modes; files and copies keep them.

use nalgebra::Vector3;
use tumble::{FastSettings, Material, Mode, RigidBodyBuilder, Shape, World};

/// A 0.1 m ball dropped from 1 m onto the ground, each in the groups given; where the ball is after 1 s.
fn drop(fast: bool, ground: u32, ball: u32) -> (f64, World) {
    let mut w = World::new();
    if fast {
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
    }
    let floor = Shape::cuboid(Vector3::new(5.0, 5.0, 0.5)).unwrap();
    w.add_body(RigidBodyBuilder::fixed(Some(floor)).position(Vector3::new(0.0, 0.0, -0.5)).collision_groups(ground))
        .unwrap();
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0)
                .position(Vector3::new(0.0, 0.0, 1.0))
                .restitution(0.0)
                .collision_groups(ball),
        )
        .unwrap();
    w.step(1.0).unwrap();
    (w.body(b).unwrap().position().z, w)
}

#[test]
fn bodies_touch_only_when_their_groups_share_a_bit() {
    for fast in [false, true] {
        // sharing bit 2 of the ball's two: it rests on the floor, its centre 0.1 m up (fast mode's soft contact
        // sinks it by microns: 1e-4 m)
        let (z, _) = drop(fast, 0b0110, 0b0011);
        assert!((z - 0.1).abs() < 1e-4, "fast {fast}: rests at {z}");
        // no bit in common: it falls through, g t^2 / 2 = 4.9 m in free fall (accurate mode to its tolerance;
        // fast mode's semi-implicit substeps fall g h t / 2 further, h = 1/1920 s: 2.55 mm)
        let (z, _) = drop(fast, 0b0100, 0b0011);
        let free = 1.0 - 0.5 * 9.81 - if fast { 0.5 * 9.81 / 1920.0 } else { 0.0 };
        assert!((z - free).abs() < 1e-6, "fast {fast}: falls through to {z}, free fall {free}");
        // the default, every group, touches any group
        let (z, _) = drop(fast, tumble::ALL_GROUPS, 0b1000_0000);
        assert!((z - 0.1).abs() < 1e-4, "fast {fast}: default groups touch, at {z}");
    }
}

#[test]
fn files_and_copies_keep_the_groups() {
    let (_, w) = drop(true, 0b0100, 0b0011);
    let groups = |w: &World| w.bodies().map(|(_, b)| b.collision_groups()).collect::<Vec<_>>();
    assert_eq!(groups(&w), vec![0b0100, 0b0011]);
    for copy in [
        w.clone(),
        World::from_json(&w.to_json().unwrap()).unwrap(),
        World::from_bytes(&w.to_bytes().unwrap()).unwrap(),
        World::from_json(&w.to_json_scene().unwrap()).unwrap(),
    ] {
        assert_eq!(groups(&copy), groups(&w));
    }
    // a body of the default groups writes none (a hand-written scene need not name them)
    let mut plain = World::new();
    plain.add_ground(0.0, Material::default()).unwrap();
    assert!(plain.to_json_scene().unwrap().contains("\"collision_groups\": null"));
}

//! Accurate mode carries stacks and piles to rest: a column of ten cubes and twenty cubes dropped in a loose pile,
//! both with friction 0.6. (Before the touching phase, both ended in "200 contact events at one time".)
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use nalgebra::{UnitQuaternion, Vector3};
use tumble::{BodyHandle, Material, RigidBodyBuilder, Shape, World};

fn cube() -> Shape {
    Shape::cuboid(Vector3::repeat(0.25)).unwrap()
}

/// Runs `seconds` and returns the fastest body's speed and the deepest penetration seen.
fn settle(w: &mut World, bodies: &[BodyHandle], seconds: f64) -> (f64, f64) {
    w.run(seconds, 0.1).unwrap();
    let fastest = bodies.iter().map(|&b| w.body(b).unwrap().velocity().norm()).fold(0.0, f64::max);
    (fastest, w.report().max_penetration)
}

#[test]
fn a_column_of_ten_cubes_stands_at_rest() {
    let mut w = World::new();
    w.add_ground(0.0, Material::new(0.1, 0.6)).unwrap();
    // 1 mm gaps: each cube lands on the one below
    let column: Vec<BodyHandle> = (0..10)
        .map(|k| {
            let z = 0.25 + 0.501 * k as f64;
            w.add_body(RigidBodyBuilder::from_shape(cube(), 500.0).position(Vector3::new(0.0, 0.0, z)).friction(0.6))
                .unwrap()
        })
        .collect();
    let (fastest, penetration) = settle(&mut w, &column, 2.0);
    let top = w.body(column[9]).unwrap().position();
    println!("measured: column of 10: fastest {fastest:.1e} m/s, top at {top:?}, penetration {penetration:.1e} m");
    assert!(fastest < 1e-6, "at rest: {fastest} m/s");
    // straight and on the floor: the top cube at 4.75 m, each of ten contacts within the lift threshold (the
    // contact tolerance in force)
    let tol = w.report().contact_tolerance.expect("accurate mode reports its contact tolerance");
    assert!(penetration <= tol, "penetration {penetration} m at tolerance {tol} m");
    assert!(top.x.abs() < 1e-6 && top.y.abs() < 1e-6 && (top.z - 4.75).abs() < 10.0 * tol, "top at {top}");
}

#[test]
fn twenty_cubes_dropped_in_a_pile_come_to_rest() {
    let mut w = World::new();
    w.add_ground(0.0, Material::new(0.2, 0.6)).unwrap();
    let pile: Vec<BodyHandle> = (0..20)
        .map(|k: usize| {
            let (i, j, l) = (k % 3, (k / 3) % 3, k / 9);
            let tilt = 0.05 * ((k * 7919 % 13) as f64 / 13.0 - 0.5);
            w.add_body(
                RigidBodyBuilder::from_shape(cube(), 500.0)
                    .position(Vector3::new(0.6 * i as f64, 0.6 * j as f64, 0.3 + 0.6 * l as f64))
                    .orientation(UnitQuaternion::from_euler_angles(tilt, -tilt, 2.0 * tilt))
                    .restitution(0.2)
                    .friction(0.6),
            )
            .unwrap()
        })
        .collect();
    let (fastest, penetration) = settle(&mut w, &pile, 2.0);
    println!("measured: pile of 20: fastest {fastest:.1e} m/s, penetration {penetration:.1e} m");
    assert!(fastest < 1e-6, "at rest: {fastest} m/s");
    // no contact sinks past the design's bound: a kept step may end two tolerances deeper than its start's deepest
    // (`LATE_SINK`, engine/accurate/late_sink.rs) and the next step lifts anything past one tolerance, so three (the
    // pile on one clock reached 1.0 of it, on its columns' own clocks 1.1)
    let tol = w.report().contact_tolerance.expect("accurate mode reports its contact tolerance");
    assert!(penetration <= 3.0 * tol, "penetration {penetration} m at tolerance {tol} m");
}

//! Islands on their own clocks (accurate mode): groups of bodies that cannot meet before the next frame each take
//! their own contact steps. They give one clock's answers to the contact tolerance on seeded random scatters of 1 to
//! 40 random shapes (random orientations, spins, densities, friction and restitution), dropped apart and in clusters
//! that meet, with the same bits on one and two threads and across a save and load.
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use crate::common;

use common::{random_shape, state_bits, Lcg};
use nalgebra::{UnitQuaternion, Vector3};
use tumble::{AccurateSettings, Material, Mode, RigidBodyBuilder, World};

/// `count` random shapes scattered over the ground in clusters of up to three (a cluster's bodies one above
/// another, so they meet), the clusters 1.5 m apart, dropped from 0.5 to 1.5 m; own clocks or one.
fn scatter(seed: u64, count: usize, clocks: bool) -> World {
    scatter_at(seed, count, clocks, 1e-4)
}

fn scatter_at(seed: u64, count: usize, clocks: bool, tol: f64) -> World {
    let mut rng = Lcg(seed.wrapping_mul(104_729).wrapping_add(3));
    let mut w = World::new();
    w.set_threads(1).unwrap();
    let settings =
        AccurateSettings { island_clocks: clocks, contact_tolerance: Some(tol), ..AccurateSettings::default() };
    w.set_mode(Mode::Accurate(settings)).unwrap();
    w.add_ground(0.0, Material::new(rng.range(0.0, 0.5), rng.range(0.2, 1.0))).unwrap();
    let side = (count as f64).sqrt().ceil() as usize;
    let mut k = 0;
    while k < count {
        let cluster = (1 + (rng.next() * 3.0) as usize).min(count - k);
        let (i, j) = ((k % side) as f64, (k / side) as f64);
        let drop = rng.range(0.5, 1.5);
        for level in 0..cluster {
            let q = UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            let at =
                Vector3::new(1.5 * i + rng.range(-0.1, 0.1), 1.5 * j + rng.range(-0.1, 0.1), drop + 0.7 * level as f64);
            w.add_body(
                RigidBodyBuilder::from_shape(random_shape(&mut rng), rng.range(100.0, 3000.0))
                    .position(at)
                    .orientation(q)
                    .angular_velocity(Vector3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)))
                    .restitution(rng.range(0.0, 0.5))
                    .friction(rng.range(0.2, 1.0)),
            )
            .unwrap();
        }
        k += cluster;
    }
    w
}

fn positions(w: &World) -> Vec<Vector3<f64>> {
    w.bodies().map(|(_, b)| b.position()).collect()
}

#[test]
fn sliding_boxes_on_their_own_clocks_stop_where_coulomb_says() {
    // Eight boxes 2 m apart slide at 0.5 to 2 m/s on a floor, friction 0.5: each stops after v^2 / (2 mu g), at its
    // own time, each box a group of its own. Tolerance: the slide's error at a contact tolerance of 1e-5 m is below
    // 1e-4 m (the accurate slide of docs/benchmarks.md), so 1e-4 m; own clocks and one clock alike.
    for clocks in [false, true] {
        let mut w = World::new();
        let settings =
            AccurateSettings { island_clocks: clocks, contact_tolerance: Some(1e-5), ..AccurateSettings::default() };
        w.set_mode(Mode::Accurate(settings)).unwrap();
        w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
        let cube = tumble::Shape::cuboid(Vector3::new(0.1, 0.1, 0.05)).unwrap();
        let mut boxes = Vec::new();
        for k in 0..8 {
            let v = 0.5 + 1.5 * ((k * 3) % 8) as f64 / 7.0;
            let at = Vector3::new(0.0, 2.0 * k as f64, 0.05);
            let b = RigidBodyBuilder::from_shape(cube.clone(), 500.0).position(at).velocity(Vector3::new(v, 0.0, 0.0));
            boxes.push((w.add_body(b.friction(0.5)).unwrap(), v));
        }
        w.run(2.0, 1.0 / 60.0).unwrap();
        for (b, v) in boxes {
            let stop = v * v / (2.0 * 0.5 * 9.81);
            let x = w.body(b).unwrap().position().x;
            assert!((x - stop).abs() < 1e-4, "clocks {clocks}: stopped at {x}, Coulomb {stop}");
        }
    }
}

#[test]
fn own_clocks_give_one_clocks_answers_within_its_own_sensitivity() {
    // Scatters of tumbling random shapes are chaotic: one clock at 90% of the tolerance ends up to 0.8 m from one clock
    // at it (a cylinder landing on its rim rolls off one way or the other). Own clocks must stay within that: the
    // worst own-clock distance at most twice the worst distance a 10% change of tolerance makes.
    let (mut worst, mut chaos) = (0.0f64, 0.0f64);
    for (seed, count) in [(1u64, 1usize), (2, 2), (3, 5), (4, 8), (5, 12), (6, 20), (7, 40)] {
        let (mut own, mut one) = (scatter(seed, count, true), scatter(seed, count, false));
        own.run(1.5, 1.0 / 60.0).unwrap();
        one.run(1.5, 1.0 / 60.0).unwrap();
        let mut other = scatter_at(seed, count, false, 0.9e-4);
        other.run(1.5, 1.0 / 60.0).unwrap();
        let far = |w: &World| positions(w).iter().zip(positions(&one)).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
        let (d_own, d_tol) = (far(&own), far(&other));
        println!("measured: seed {seed}, {count} bodies: own clocks {d_own:.2e} m from one clock, 0.9 tolerance {d_tol:.2e} m");
        worst = worst.max(d_own);
        chaos = chaos.max(d_tol);
    }
    assert!(worst <= 2.0 * chaos, "own clocks {worst:e} m from one clock; a 10% tolerance change {chaos:e} m");
}

#[test]
fn own_clocks_are_the_same_bits_on_any_thread_count_and_across_files() {
    let mut w = scatter(11, 12, true);
    w.run(0.6, 1.0 / 60.0).unwrap();
    let mut json = World::from_json(&w.to_json().unwrap()).unwrap();
    let mut bytes = World::from_bytes(&w.to_bytes().unwrap()).unwrap();
    let mut two = w.clone();
    two.set_threads(2).unwrap();
    w.run(0.9, 1.0 / 60.0).unwrap();
    for other in [&mut json, &mut bytes, &mut two] {
        other.run(0.9, 1.0 / 60.0).unwrap();
        assert_eq!(state_bits(other), state_bits(&w));
    }
}

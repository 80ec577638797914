//! Property test of accurate mode on the scenes a newcomer drops first: seeded random drops of one to five shapes
//! (every kind a body can have: sphere, cuboid, capsule, cylinder, convex hull), random orientations, spins,
//! densities (100 to 3000 kg/m^3, mass ratios up to ~1e3), friction (0 to 1) and restitution (0 to 0.6), 3 s each.
//! Every one must run to the end, stay finite, never gain energy between frames, never penetrate deeper than 1 mm,
//! and repeat bit for bit. CI runs `TUMBLE_DROPS` (default 4) seeds; `TUMBLE_DROPS=100` is a long local run.

mod common;
use common::{state_bits, Lcg};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use tumble::{Material, RigidBodyBuilder, Shape, World};

fn random_shape(rng: &mut Lcg) -> Shape {
    let kind = (rng.next() * 5.0) as usize;
    match kind {
        0 => Shape::sphere(rng.range(0.05, 0.3)).unwrap(),
        1 => Shape::cuboid(Vector3::new(rng.range(0.05, 0.3), rng.range(0.05, 0.3), rng.range(0.05, 0.3))).unwrap(),
        2 => Shape::capsule(rng.range(0.05, 0.3), rng.range(0.05, 0.3)).unwrap(),
        3 => Shape::cylinder(rng.range(0.05, 0.3), rng.range(0.05, 0.3)).unwrap(),
        _ => {
            let points: Vec<Point3<f64>> = (0..8)
                .map(|_| Point3::new(rng.range(-0.25, 0.25), rng.range(-0.25, 0.25), rng.range(-0.25, 0.25)))
                .collect();
            Shape::convex_hull(&points).unwrap()
        }
    }
}

fn random_drop(seed: u64) -> World {
    let mut rng = Lcg(seed.wrapping_mul(7919).wrapping_add(17));
    let mut w = World::new();
    w.add_ground(0.0, Material { restitution: rng.range(0.0, 0.6), friction: rng.range(0.0, 1.0) }).unwrap();
    let count = 1 + (rng.next() * 5.0) as usize;
    for k in 0..count {
        let shape = random_shape(&mut rng);
        let q = UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        w.add_body(
            RigidBodyBuilder::from_shape(shape, rng.range(100.0, 3000.0))
                .position(Vector3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 0.6 + 0.7 * k as f64))
                .orientation(q)
                .angular_velocity(Vector3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)))
                .restitution(rng.range(0.0, 0.6))
                .friction(rng.range(0.0, 1.0)),
        )
        .unwrap();
    }
    w
}

#[test]
fn random_drops_run_to_the_end_finite_without_energy_gain_or_deep_penetration_and_repeat() {
    let seeds: u64 = std::env::var("TUMBLE_DROPS").map_or(4, |s| s.parse().expect("TUMBLE_DROPS is a count"));
    for seed in 0..seeds {
        let mut w = random_drop(seed);
        let run = w.run(3.0, 1.0 / 30.0).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        let bits = state_bits(&w);
        assert!(bits.iter().all(|b| f64::from_bits(*b).is_finite()), "seed {seed}: not finite");
        // Energy may rise between frames only by what lifting sunk contacts adds (m g times the contact tolerance,
        // 1e-6 of the scene's size) and the contact solves' accuracy allowed in extrapolation: well under 1e-6 E0.
        let e0 = run.energy(0);
        let rise = (1..run.frames()).map(|f| run.energy(f) - run.energy(f - 1)).fold(f64::MIN, f64::max);
        let report = w.report();
        println!(
            "measured: seed {seed}, {} shapes: energy rise {:.1e} of E0, penetration {:.1e} m, {} contact steps",
            w.body_count() - 1,
            rise / e0,
            report.max_penetration,
            report.contact_steps
        );
        assert!(rise <= 1e-6 * e0, "seed {seed}: energy rose by {rise} J of {e0}");
        assert!(report.max_penetration < 1e-3, "seed {seed}: penetration {} m", report.max_penetration);
        let mut again = random_drop(seed);
        again.run(3.0, 1.0 / 30.0).unwrap();
        assert_eq!(state_bits(&again), bits, "seed {seed}: a rerun differs");
    }
}

//! Accurate mode's energy law and its touching phase at any tolerance, on the scenes where they failed: a box
//! dropped tumbling onto a frictionless floor (its frames' energy rose 2.3e-2 J of 380 J above an earlier frame, the
//! same at every tolerance), three dominoes at a loose tolerance (they stood), and a box resting asleep (its frames'
//! times repeated).
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use tumble::integrate::{Method, Settings};
use tumble::{AccurateSettings, Material, Mode, RigidBodyBuilder, Shape, World};

/// The tumbling box: half extents 0.3 x 0.2 x 0.1 m, density 800, from 1 m, turned 45 degrees about x and spinning
/// (1, 2, 0.5) rad/s, on a frictionless floor of restitution 0.5; dopri5 at 1e-9 / 1e-11.
fn tumbling_box(tolerance: Option<f64>) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Accurate(AccurateSettings { contact_tolerance: tolerance, ..AccurateSettings::default() }))
        .unwrap();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-9, 1e-11)).unwrap();
    w.add_ground(0.0, Material::new(0.5, 0.0)).unwrap();
    let q = UnitQuaternion::from_quaternion(Quaternion::new(0.9238795, 0.3826834, 0.0, 0.0));
    w.add_body(
        RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.3, 0.2, 0.1)).unwrap(), 800.0)
            .position(Vector3::new(0.0, 0.0, 1.0))
            .orientation(q)
            .angular_velocity(Vector3::new(1.0, 2.0, 0.5))
            .restitution(0.5)
            .friction(0.0),
    )
    .unwrap();
    w
}

/// The largest rise of a run's frame energies over the lowest frame energy before each (J).
fn largest_rise(run: &tumble::Run) -> f64 {
    let mut lowest = f64::INFINITY;
    let mut rise: f64 = 0.0;
    for f in 0..run.frames() {
        rise = rise.max(run.energy(f) - lowest);
        lowest = lowest.min(run.energy(f));
    }
    rise
}

#[test]
fn a_tumbling_box_gains_no_energy_between_frames_and_a_tighter_tolerance_gains_no_more() {
    let mut rises = Vec::new();
    for tolerance in [None, Some(1e-7)] {
        let mut w = tumbling_box(tolerance);
        let run = w.run(4.0, 0.01).unwrap();
        let e0 = run.energy(0);
        let tol = w.report().contact_tolerance.unwrap();
        let weight = 0.6 * 0.4 * 0.2 * 800.0 * 9.81;
        let rise = largest_rise(&run);
        println!("measured: tolerance {tol:.1e} m: largest rise {rise:.2e} J of E0 = {e0:.1} J");
        // the law (docs/modes.md): the weight times the tolerance, and the integrator's rotation to its relative
        // tolerance (1e-9 here) of the energy
        assert!(rise <= weight * tol + 1e-9 * e0, "{rise} J at a tolerance of {tol} m");
        rises.push(rise);
    }
    // what is left is the integrator's (dopri5 carries the free tumble to its tolerance), not the contacts': the
    // tighter contact tolerance gains no more, beyond rounding of the energies (1e-12 of E0)
    assert!(rises[1] <= rises[0] + 1e-12 * 380.0, "{rises:?}");
}

/// Three dominoes (half extents 4 x 12 x 24 mm, density 700, 33 mm apart, friction 0.5), the first tipping at
/// 12 rad/s toward the others: each one's tilt (rad) after 1.5 s at `tolerance`.
fn domino_tilts(tolerance: f64) -> Vec<f64> {
    let mut w = World::new();
    w.set_mode(Mode::Accurate(AccurateSettings { contact_tolerance: Some(tolerance), ..AccurateSettings::default() }))
        .unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let shape = Shape::cuboid(Vector3::new(0.004, 0.012, 0.024)).unwrap();
    let dominoes: Vec<_> = (0..3)
        .map(|k| {
            let spin = if k == 0 { 12.0 } else { 0.0 };
            w.add_body(
                RigidBodyBuilder::from_shape(shape.clone(), 700.0)
                    .position(Vector3::new(0.033 * k as f64, 0.0, 0.024))
                    .angular_velocity(Vector3::new(0.0, spin, 0.0))
                    .friction(0.5),
            )
            .unwrap()
        })
        .collect();
    w.step(1.5).unwrap();
    dominoes.iter().map(|&d| w.body(d).unwrap().orientation().angle()).collect()
}

#[test]
fn three_dominoes_fall_at_every_tolerance_as_they_do_at_a_tight_one() {
    let reference = domino_tilts(1e-6);
    // fallen: the first two lean on their neighbours (about 77 degrees), the last lies flat (90)
    assert!(reference.iter().all(|t| t.to_degrees() > 70.0), "{reference:?}");
    for tolerance in [1e-2, 3e-3, 1e-3, 1e-4, 1e-5] {
        let tilts = domino_tilts(tolerance);
        let worst = tilts.iter().zip(&reference).map(|(t, r)| (t - r).abs()).fold(0.0f64, f64::max);
        println!("measured: tolerance {tolerance:.0e} m: tilts {tilts:.4?} rad, worst {worst:.2e} rad from 1e-6 m's");
        // the tolerance's share of the reference's tilt: tol over the domino's height (48 mm), with a floor of
        // 4e-3 of it for the leaning dominoes' contacts, whose paths differ by up to 4.4e-3 rad whatever the
        // tolerance (measured from 1e-2 to 1e-5 m)
        let share = (tolerance / 0.048).max(4e-3);
        assert!(worst <= share * std::f64::consts::FRAC_PI_2, "tolerance {tolerance}: {tilts:?} against {reference:?}");
    }
}

#[test]
fn frame_times_strictly_increase_while_everything_sleeps() {
    let mut w = World::new();
    w.add_ground(0.0, Material::default()).unwrap();
    w.add_body(
        RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.1, 0.1, 0.1)).unwrap(), 500.0)
            .position(Vector3::new(0.0, 0.0, 0.1)),
    )
    .unwrap();
    let run = w.run(2.0, 1.0 / 60.0).unwrap();
    assert_eq!(run.frames(), 121);
    assert!(w.report().sleepers > 0, "the box sleeps");
    for f in 1..run.frames() {
        assert!(run.times[f] > run.times[f - 1], "frame {f}: {} after {}", run.times[f], run.times[f - 1]);
        // each frame at its own time
        assert!((run.times[f] - f as f64 / 60.0).abs() < 1e-12, "frame {f} at {}", run.times[f]);
    }
}

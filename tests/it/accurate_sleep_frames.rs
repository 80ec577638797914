//! Accurate mode's frames and sleep: recording frames never changes the physics (the same final bits with frames
//! every 1/30, 1/60 and 1/240 s and with none, on contact scenes, islands on their own clocks and in free flight), and a pile falls asleep,
//! costs no contact step while asleep, wakes when a body is dropped on it, with the same bits on one and two
//! threads and across a save and load.
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use crate::common;

use common::state_bits;
use nalgebra::Vector3;
use tumble::scenes::{Benchmark, BouncingBall};
use tumble::{AccurateSettings, Mode, RigidBodyBuilder, Shape, World};

/// The final bits after `span` with frames every `interval` (none: one `step`).
fn final_bits(mut w: World, span: f64, interval: Option<f64>) -> Vec<u64> {
    match interval {
        Some(dt) => {
            let run = w.run(span, dt).unwrap();
            assert!(run.frames() >= (span / dt) as usize, "the frames were recorded");
        }
        None => w.step(span).unwrap(),
    }
    state_bits(&w)
}

/// `n` spinning boxes dropped 2 m apart from slightly different heights (each a group on its own clock).
fn boxes_apart(n: usize) -> World {
    let mut w = World::new();
    w.add_ground(0.0, tumble::Material::new(0.3, 0.5)).unwrap();
    for k in 0..n {
        let at = Vector3::new(2.0 * (k % 4) as f64, 2.0 * (k / 4) as f64, 0.5 + 0.01 * (k % 7) as f64);
        w.add_body(
            RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.1)).unwrap(), 500.0)
                .position(at)
                .angular_velocity(Vector3::new(0.3 * (k % 5) as f64, 0.2, 0.1)),
        )
        .unwrap();
    }
    w
}

#[test]
fn frames_do_not_change_the_final_state() {
    let scenes: Vec<(&str, Box<dyn Fn() -> World>, f64)> = vec![
        ("slide", Box::new(|| Benchmark::Slide.build().unwrap().0), 1.0),
        ("roll", Box::new(|| Benchmark::Roll.build().unwrap().0), 0.5),
        ("dominoes", Box::new(|| Benchmark::DominoRow.build().unwrap().0), 0.6),
        ("bouncing ball", Box::new(|| BouncingBall::default().build().unwrap().0), 1.5),
        ("ten boxes apart, on their own clocks", Box::new(|| boxes_apart(10)), 1.2),
    ];
    for (name, build, span) in scenes {
        let plain = final_bits(build(), span, None);
        for dt in [1.0 / 30.0, 1.0 / 60.0, 1.0 / 240.0] {
            assert_eq!(final_bits(build(), span, Some(dt)), plain, "{name}: frames every {dt} s changed the physics");
        }
        println!("measured: {name}: the same bits with frames every 1/30, 1/60, 1/240 s and none");
    }
}

/// The 20-cube pile at contact tolerance 0.1 mm (enough to settle it; the tests are of sleep, not accuracy).
fn pile(threads: usize) -> (World, Vec<tumble::BodyHandle>) {
    let (mut w, cubes) = Benchmark::CubePile.build().unwrap();
    w.set_threads(threads).unwrap();
    w.set_mode(Mode::Accurate(AccurateSettings { contact_tolerance: Some(1e-4), ..AccurateSettings::default() }))
        .unwrap();
    (w, cubes)
}

/// The 20-cube pile settled for 3 s (and asleep by then).
fn settled_pile(threads: usize) -> World {
    let (mut w, _) = pile(threads);
    w.step(3.0).unwrap();
    w
}

#[test]
fn a_settled_pile_sleeps_for_free() {
    let mut w = settled_pile(1);
    let r = w.report();
    assert_eq!(r.sleepers, 20, "the whole pile sleeps after 3 s ({} asleep)", r.sleepers);
    // asleep, a long rest costs no contact step and moves nothing
    let before = state_bits(&w);
    let steps = w.report().contact_steps;
    w.step(1000.0).unwrap();
    let r = w.report();
    println!("measured: 1000 s of a sleeping pile took {} contact steps", r.contact_steps - steps);
    assert_eq!(r.contact_steps, steps, "no contact step while everything sleeps");
    assert_eq!(state_bits(&w)[3..], before[3..], "nothing moved while asleep");
}

#[test]
fn a_sleeping_pile_wakes_when_a_falling_cube_reaches_it() {
    // the pile and, far above it, a cube (restitution 0) that lands on it at about 3.5 s, after the pile fell
    // asleep
    let (mut w, cubes) = pile(1);
    let cube = Shape::cuboid(Vector3::repeat(0.1)).unwrap();
    let high =
        RigidBodyBuilder::from_shape(cube, 500.0).position(Vector3::new(0.3, 0.3, 60.0)).friction(0.5).restitution(0.0);
    let falling = w.add_body(high).unwrap();
    w.step(3.0).unwrap();
    assert_eq!(w.report().sleepers, 20, "the pile sleeps while the cube falls");
    let resting: Vec<u64> = cubes.iter().map(|&b| w.body(b).unwrap().position().z.to_bits()).collect();
    w.step(1.5).unwrap();
    let z = w.body(falling).unwrap().position().z;
    assert!(z < 1.5, "the cube landed on the pile: z = {z}");
    let moved = cubes.iter().zip(&resting).filter(|(b, z)| w.body(**b).unwrap().position().z.to_bits() != **z).count();
    println!("measured: the landing moved {moved} of the 20 cubes; {} asleep after", w.report().sleepers);
    assert!(moved > 0, "the pile woke: a cube it landed on moved");
}

#[test]
fn sleep_keeps_its_bits_across_threads_and_save_and_load() {
    let one = settled_pile(1);
    let two = settled_pile(2);
    assert_eq!(state_bits(&one), state_bits(&two), "one and two threads");
    // the saved and loaded world sleeps on like the original, and wakes alike
    let mut original = one;
    let mut copy = World::from_bytes(&original.to_bytes().unwrap()).unwrap();
    for w in [&mut original, &mut copy] {
        w.step(10.0).unwrap();
        let cube = Shape::cuboid(Vector3::repeat(0.1)).unwrap();
        w.add_body(RigidBodyBuilder::from_shape(cube, 500.0).position(Vector3::new(0.0, 0.0, 1.5))).unwrap();
        w.step(0.5).unwrap();
    }
    assert_eq!(state_bits(&original), state_bits(&copy), "across a save and load");
    assert_eq!(original.report().sleepers, copy.report().sleepers);
}

//! Long runs that say and keep: an interrupted run keeps the frames it did and leaves the world at the last of
//! them, so the next run carries on; a slow accurate run says so once, naming fast mode with its time.
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use crate::common;
use common::random_drop;
use nalgebra::Vector3;
use tumble::{Control, Material, Mode, RigidBodyBuilder, Shape, World, WorldError};

/// A box thrown up and along in accurate mode, tumbling fast about all three axes (many integrator steps), nothing
/// to touch.
fn thrown() -> (World, tumble::BodyHandle) {
    let mut w = World::new();
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.1, 0.2, 0.3)).unwrap(), 1000.0)
                .position(Vector3::new(0.0, 0.0, 1.0))
                .velocity(Vector3::new(1.0, 0.0, 6.0))
                .angular_velocity(Vector3::new(30.0, 20.0, 10.0)),
        )
        .unwrap();
    (w, b)
}

#[test]
fn an_interrupted_run_keeps_its_frames_and_the_next_run_carries_on() {
    let (mut whole, _) = thrown();
    let reference = whole.run(1.0, 0.01).unwrap();
    let (mut w, b) = thrown();
    let e = w.run_with(1.0, 0.01, |done: f64| done < 0.4);
    assert!(matches!(e, Err(WorldError::Interrupted)), "{e:?}");
    let kept = w.take_failed_run().expect("the frames done are kept");
    assert!(kept.interrupted);
    let n = kept.frames();
    assert!(n > 40 && n < 101, "stopped past 40% of the frames, before the end: {n}");
    // the frames kept are the uninterrupted run's, bit for bit (recording and stopping change nothing before)
    for f in 0..n {
        assert_eq!(kept.times[f], reference.times[f]);
        assert_eq!(kept.body_position(f, 0), reference.body_position(f, 0));
    }
    // the world is at the last of them
    let last = n - 1;
    assert_eq!(w.time(), kept.times[last]);
    assert_eq!(w.body(b).unwrap().position(), kept.body_position(last, 0));
    // the next run carries on: its frames at the uninterrupted run's times, ending on the closed form (x = x0 + v0 t,
    // z = z0 + w0 t - g t^2 / 2) to the integrator's tolerance (rtol 1e-6 of a state of order 1: 1e-5 m allowed)
    let rest = w.run(1.0 - kept.times[last], 0.01).unwrap();
    assert!((rest.times[rest.frames() - 1] - 1.0).abs() < 1e-12);
    for (f, &t) in rest.times.iter().enumerate() {
        let k = reference.times.iter().position(|&r| (r - t).abs() < 1e-12).expect("a frame at the same time");
        assert!((rest.body_position(f, 0) - reference.body_position(k, 0)).norm() < 1e-5, "frame at {t}");
    }
    let end = w.body(b).unwrap().position();
    let closed = Vector3::new(1.0, 0.0, 1.0 + 6.0 - 0.5 * 9.81);
    assert!((end - closed).norm() < 1e-5, "{end} against {closed}");
}

/// A control that stops the call after `after` of it and says the stop keeps no work (a failure).
struct Failing {
    after: f64,
}

impl Control for Failing {
    fn go_on(&mut self, done: f64) -> bool {
        done < self.after
    }

    fn keeps_work(&self) -> bool {
        false
    }
}

#[test]
fn a_stop_that_keeps_no_work_leaves_the_world_as_it_was_with_the_frames_on_the_error() {
    let (mut w, b) = thrown();
    let before = (w.time(), w.body(b).unwrap().position());
    let e = w.run_with(1.0, 0.01, Failing { after: 0.4 });
    assert!(matches!(e, Err(WorldError::Interrupted)), "{e:?}");
    assert_eq!((w.time(), w.body(b).unwrap().position()), before, "the world as the call found it");
    let run = w.take_failed_run().expect("the frames done ride on the error");
    assert!(!run.interrupted && run.frames() > 40);
    // to the bit, in either mode, whether the failed call built the engine or was given a state to start from (an
    // engine's state is its own form of the world's, equal to it only to rounding: fast mode's velocities)
    for fast in [false, true] {
        let mut w = World::new();
        if fast {
            w.set_mode(Mode::Fast(tumble::FastSettings::new(1.0 / 240.0))).unwrap();
        }
        let ball = RigidBodyBuilder::from_shape(Shape::sphere(0.5).unwrap(), 100.0)
            .angular_velocity(Vector3::new(0.3, 0.0, 1.0))
            .velocity(Vector3::new(0.1, 0.2, 0.0));
        let h = w.add_body(ball).unwrap();
        for round in 0..3 {
            if round == 2 {
                w.set_body_state(h, Vector3::zeros(), Default::default(), Vector3::x(), Vector3::new(0.0, 0.7, 0.1))
                    .unwrap();
            }
            let before = (w.kinetic_energy(), w.angular_momentum(), w.time());
            assert!(w.run_with(0.5, 0.1, Failing { after: 0.0 }).is_err());
            assert_eq!((w.kinetic_energy(), w.angular_momentum(), w.time()), before, "fast {fast}, round {round}");
            w.step(1.0 / 240.0).unwrap();
        }
    }
}

#[test]
fn interrupted_contact_runs_leave_the_world_at_the_last_frame_in_both_modes() {
    // random drops of boxes, balls, capsules and hulls (seeded), in both modes, interrupted half way
    for seed in 0..4u64 {
        for fast in [false, true] {
            let mut w = random_drop(seed);
            if fast {
                w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
            }
            let mut whole = w.clone();
            let reference = whole.run(1.0, 1.0 / 60.0).unwrap();
            let e = w.run_with(1.0, 1.0 / 60.0, |done: f64| done < 0.5);
            assert!(matches!(e, Err(WorldError::Interrupted)), "seed {seed}: {e:?}");
            let kept = w.take_failed_run().unwrap();
            let last = kept.frames() - 1;
            assert_eq!(kept.times[..=last], reference.times[..=last], "seed {seed}");
            for f in 0..=last {
                for j in 0..kept.bodies.len() {
                    assert_eq!(kept.body_position(f, j), reference.body_position(f, j), "seed {seed}, frame {f}");
                }
            }
            assert_eq!(w.time(), kept.times[last]);
            for (j, (_, body)) in w.bodies().enumerate() {
                assert_eq!(body.position(), kept.body_position(last, j), "seed {seed}, body {j}");
            }
            // the next run goes on from there to the end, every body finite and above the ground (a start afresh
            // from the frame: contacts found again, within the contact tolerance of 1e-4 of the scene or fast mode's
            // margin)
            w.run(1.0 - kept.times[last], 1.0 / 60.0).unwrap();
            assert!((w.time() - 1.0).abs() < 1e-9);
            for (_, body) in w.bodies() {
                assert!(body.position().iter().all(|x| x.is_finite()) && body.position().z > -0.05, "seed {seed}");
            }
        }
    }
}

#[test]
fn a_step_that_is_interrupted_leaves_the_world_as_it_was() {
    let (mut w, b) = thrown();
    let before = (w.time(), w.body(b).unwrap().position());
    let e = w.step_with(1.0, |done: f64| done < 0.3);
    assert!(matches!(e, Err(WorldError::Interrupted)), "{e:?}");
    assert_eq!((w.time(), w.body(b).unwrap().position()), before);
    assert!(w.take_failed_run().is_none(), "a step records no frame to keep");
}

/// A control that makes the call slow as its waiting person sees it: told a fraction, it takes `pace` times the
/// simulated time that fraction added (so the call takes at least `pace` times the span, whatever the machine), and
/// keeps the hints it is given.
struct Slow {
    pace: f64,
    span: f64,
    done: f64,
    hints: Vec<String>,
}

impl Slow {
    fn new(pace: f64, span: f64) -> Slow {
        Slow { pace, span, done: 0.0, hints: Vec::new() }
    }
}

impl Control for &mut Slow {
    fn go_on(&mut self, fraction: f64) -> bool {
        std::thread::sleep(std::time::Duration::from_secs_f64(self.pace * self.span * (fraction - self.done)));
        self.done = fraction;
        true
    }

    fn hint(&mut self, line: &str) {
        self.hints.push(line.to_string());
    }
}

/// A box dropped onto the ground in accurate mode.
fn dropped_box(mode: Mode) -> World {
    let mut w = World::new();
    w.set_mode(mode).unwrap();
    w.add_ground(0.0, Material::default()).unwrap();
    w.add_body(
        RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.1)).unwrap(), 500.0)
            .position(Vector3::new(0.0, 0.0, 0.3)),
    )
    .unwrap();
    w
}

#[test]
fn a_slow_accurate_run_says_so_once_naming_fast_mode() {
    // 0.2 s simulated taking at least 15 times that (3 s): the line is due once two seconds have passed
    let mut w = dropped_box(Mode::default());
    let mut slow = Slow::new(15.0, 0.2);
    w.run_with(0.2, 1.0 / 200.0, &mut slow).unwrap();
    assert_eq!(slow.hints.len(), 1, "{:?}", slow.hints);
    let line = &slow.hints[0];
    assert!(line.contains("accurate mode projects") && line.contains("fast mode (mode \"fast\""), "{line}");
    assert!(line.contains("would take about"), "fast mode runs a box: its time is given: {line}");
    // once a world
    let mut again = Slow::new(15.0, 0.2);
    w.run_with(0.2, 1.0 / 200.0, &mut again).unwrap();
    assert!(again.hints.is_empty());
    // a quick run says nothing
    let mut quick = random_drop(1);
    let mut heard = Slow::new(0.0, 0.5);
    quick.run_with(0.5, 1.0 / 60.0, &mut heard).unwrap();
    assert!(heard.hints.is_empty());
    // fast mode never says it, however slow
    let mut fast = dropped_box(Mode::fast(1.0 / 240.0));
    let mut slow_fast = Slow::new(15.0, 0.2);
    fast.run_with(0.2, 1.0 / 200.0, &mut slow_fast).unwrap();
    assert!(slow_fast.hints.is_empty());
}

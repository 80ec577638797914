//! Batches (issue 15): copies of a world run from many states on a thread pool give the runs of the same copies run
//! one after another, bit for bit, on any number of threads; bad states are refused by index before anything runs.

use crate::common;

use common::{random_drop, Lcg};
use nalgebra::Vector3;
use tumble::{rollout, FastSettings, Mode, RolloutSettings, Run, World, WorldError, WorldState};

/// Every number a run recorded, as bits.
fn bits(run: Run) -> Vec<u64> {
    let a = run.into_arrays().0;
    let lists = [
        &a.times,
        &a.particle_positions,
        &a.body_positions,
        &a.body_orientations,
        &a.body_velocities,
        &a.body_angular_velocities,
        &a.energy,
        &a.step_times,
        &a.penetration,
        &a.contact_events,
    ];
    lists.iter().flat_map(|l| l.iter().map(|v| v.to_bits())).collect()
}

/// Eight states of a world: its own, stepped on, and with random velocities given to its bodies.
fn states(w: &mut World, seed: u64) -> Vec<WorldState> {
    let mut rng = Lcg(seed);
    let mut out = vec![w.state()];
    w.step(0.1).unwrap();
    out.push(w.state());
    for _ in 0..6 {
        let mut s = w.state();
        for m in s.body_momenta.iter_mut().skip(1) {
            *m += Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.0, 2.0));
        }
        out.push(s);
    }
    out
}

#[test]
fn a_batch_equals_its_copies_run_one_after_another_on_any_thread_count() {
    for (seed, fast) in [(1, true), (2, true), (3, false)] {
        let mut w = random_drop(seed);
        if fast {
            w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
        }
        let states = states(&mut w, seed);
        let settings = RolloutSettings { duration: 0.25, frame_interval: 1.0 / 60.0, threads: 1 };
        let one_by_one: Vec<Vec<u64>> = states
            .iter()
            .map(|s| {
                let mut copy = w.clone();
                copy.set_state(s).unwrap();
                bits(copy.run(settings.duration, settings.frame_interval).unwrap())
            })
            .collect();
        // and the world itself set to each state in turn gives the same runs
        let mut same = w.clone();
        for (s, want) in states.iter().zip(&one_by_one) {
            same.set_state(s).unwrap();
            let k = states.iter().position(|x| std::ptr::eq(x, s)).unwrap();
            assert_eq!(
                &bits(same.run(settings.duration, settings.frame_interval).unwrap()),
                want,
                "seed {seed} state {k}"
            );
        }
        let before = common::state_bits(&w);
        for threads in [1, 2, 3, 0] {
            let runs = rollout(&w, &states, RolloutSettings { threads, ..settings }, |_| true).unwrap();
            let got: Vec<Vec<u64>> = runs.into_iter().map(bits).collect();
            assert_eq!(got, one_by_one, "seed {seed}, {threads} threads");
        }
        assert_eq!(common::state_bits(&w), before, "the world itself is untouched");
    }
}

#[test]
fn a_bad_state_is_refused_by_its_index_and_a_stopped_batch_says_so() {
    let mut w = random_drop(4);
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
    let mut states = states(&mut w, 4);
    states[5].body_positions[1].x = f64::NAN;
    let settings = RolloutSettings { duration: 0.25, frame_interval: 1.0 / 60.0, threads: 2 };
    match rollout(&w, &states, settings, |_| true) {
        Err(WorldError::InvalidArgument { name: "body_positions", reason }) => assert!(reason.contains("states[5]")),
        other => panic!("expected the bad state named, got {:?}", other.map(|r| r.len())),
    }
    states.truncate(5);
    assert!(matches!(rollout(&w, &states, settings, |_| false), Err(WorldError::Interrupted) | Ok(_)));
    let long = RolloutSettings { duration: 60.0, ..settings };
    assert!(matches!(rollout(&w, &states, long, |_| false), Err(WorldError::Interrupted)));
    assert!(rollout(&w, &states, RolloutSettings { duration: -1.0, ..settings }, |_| true).is_err());
    assert!(rollout(&w, &states, RolloutSettings { frame_interval: 0.0, ..settings }, |_| true).is_err());
    assert!(rollout(&w, &[], settings, |_| true).unwrap().is_empty());
}

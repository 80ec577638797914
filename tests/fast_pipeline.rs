//! Fast mode's pipeline on large scenes: a wall of cubes too large for one thread (its colours shared out among the
//! workers) gives the same bits on one, two and three threads; what the engine keeps from step to step (its state
//! in velocity form, each contact pair's points, impulses, friction and colour) survives copies, files and failed
//! calls bit for bit; and tall walls of cubes stand at every substep count from two up.

mod common;

use common::state_bits;
use tumble::scenes::LargePyramid;
use tumble::{FastSettings, FastSolver, Mode, SoftSolver, World, WorldError};

/// Box3D's large pyramid with `base` cubes at the bottom, its solver `substeps` x `iterations`, on `threads`.
fn pyramid(base: usize, substeps: usize, iterations: usize, threads: usize) -> (World, Vec<tumble::BodyHandle>) {
    let (mut w, cubes) = LargePyramid { base }.build().unwrap();
    let Mode::Fast(settings) = w.mode() else { unreachable!("a fast-mode scene") };
    let soft = SoftSolver { substeps, iterations, ..SoftSolver::default() };
    w.set_mode(Mode::Fast(FastSettings { solver: FastSolver::Soft(soft), ..settings })).unwrap();
    w.set_threads(threads).unwrap();
    (w, cubes)
}

/// Every number of the world's state and of its last step's contacts, as bits.
fn bits(w: &World) -> Vec<u64> {
    let mut out = state_bits(w);
    for c in w.contacts() {
        out.extend(c.point.iter().chain(c.normal.iter()).chain([c.gap, c.impulse].iter()).map(|v| v.to_bits()));
    }
    out
}

#[test]
fn a_wall_shared_out_among_threads_gives_the_same_bits_on_one_two_and_three() {
    // 30 cubes at the base: 465 cubes in one island of about 1,300 manifolds and 5,000 contact points, past the
    // thousand from which an island's colours are shared out among the workers
    let run = |threads: usize| {
        let (mut w, _) = pyramid(30, 4, 1, threads);
        for _ in 0..30 {
            w.step(1.0 / 60.0).unwrap();
        }
        assert!(w.contacts().len() > 4000, "{} contacts", w.contacts().len());
        bits(&w)
    };
    let one = run(1);
    for threads in [2, 3] {
        assert!(run(threads) == one, "{threads} threads");
    }
}

#[test]
fn the_engines_memory_survives_copies_files_and_failed_calls_bit_for_bit() {
    // A wall of 120 cubes after half a second: every pair keeps points, impulses, friction and a colour
    let (mut w, _) = pyramid(15, 4, 1, 1);
    w.step(0.5).unwrap();
    let copy = w.clone();
    let binary = World::from_bytes(&w.to_bytes().unwrap()).unwrap();
    let json = World::from_json(&w.to_json().unwrap()).unwrap();
    // a call stopped partway leaves the world as it was
    let mut failed = w.clone();
    let stopped = failed.step_with(0.5, |done| done < 0.3);
    assert!(matches!(stopped, Err(WorldError::Interrupted)), "{stopped:?}");
    assert_eq!(bits(&failed), bits(&w), "a failed call changed the world");
    w.step(0.5).unwrap();
    for (name, mut other) in [("copy", copy), ("binary", binary), ("json", json), ("failed call", failed)] {
        other.step(0.5).unwrap();
        assert!(bits(&other) == bits(&w), "{name}: went another way");
    }
}

//! Fast mode's pipeline on large scenes: a wall of cubes too large for one thread (its colours shared out among the
//! workers) gives the same bits on one, two and three threads; what the engine keeps from step to step (its state
//! in velocity form, each contact pair's points, impulses, friction and colour) survives copies, files and failed
//! calls bit for bit; and tall walls of cubes stand at every substep count from two up.

use crate::common;

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

#[test]
fn a_wall_40_cubes_high_stands_at_2_4_and_8_substeps() {
    // Box3D's large pyramid cut to 40 cubes at the base (820 unit cubes, density 100), 5 s at 1/60 s, the default
    // two sweeps a pass. Soft contacts sink until their springs carry the load: a layer k cubes below the top
    // carries about k/2 cubes' weight on each contact, and a contact of stiffness omega^2 (its hertz capped at a
    // quarter of the substep rate) gives g / omega^2 a cube's weight, so the top sinks about
    // g / omega^2 (1 + 2 + ... + 39) / 2 = 390 g / omega^2: 108 mm at 2 substeps, 27 mm at 4, 6.8 mm at 8. Allowed:
    // 1.1 times that (the loads are not spread quite evenly: measured within 4%). A wall that stands moves no cube
    // sideways by more than a tenth of its size; one that falls moves them metres.
    for substeps in [2, 4, 8] {
        let (mut w, cubes) = pyramid(40, substeps, 2, 1);
        let start: Vec<_> = cubes.iter().map(|&c| w.body(c).unwrap().position()).collect();
        w.step(5.0).unwrap();
        let top = cubes.len() - 1;
        let sink = start[top].z - w.body(cubes[top]).unwrap().position().z;
        let sideways = cubes
            .iter()
            .zip(&start)
            .map(|(&c, s)| (w.body(c).unwrap().position() - s).xy().norm())
            .fold(0.0f64, f64::max);
        let omega = std::f64::consts::TAU * 0.25 * substeps as f64 * 60.0;
        let expected = 390.0 * 9.81 / (omega * omega);
        println!("measured: {substeps} substeps, the top sank {sink:.4} m (about {expected:.4}), cubes moved sideways at most {sideways:.4} m");
        assert!(sink > 0.0 && sink < 1.1 * expected, "{substeps} substeps: the top sank {sink} m");
        assert!(sideways < 0.1, "{substeps} substeps: a cube moved {sideways} m sideways");
    }
}

//! A world's whole state (issue 15): read and put back it continues bit for bit, in every mode; edited it starts
//! afresh as a new world would; `reset` returns to the start; rows after removals; bad states change nothing.
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use crate::common;

use common::{random_drop, state_bits};
use nalgebra::{UnitQuaternion, Vector3};
use tumble::{
    Attachment, BodyHandle, FastSettings, FastSolver, Mode, ParticleBuilder, RigidBodyBuilder, Shape, SpringBuilder,
    World, WorldError,
};

/// The scenes: seeded random drops (one to five random shapes with random orientations, spins, densities,
/// frictions and restitutions) in accurate mode, in fast mode with the soft and the exact solver; and a chain of
/// particles on springs under Dormand-Prince (smooth integration: its memory is the step size controller's).
fn scene(kind: usize, seed: u64) -> World {
    match kind {
        0 => random_drop(seed),
        1 | 2 => {
            let mut w = random_drop(seed);
            let solver = if kind == 1 { FastSolver::default() } else { FastSolver::exact() };
            w.set_mode(Mode::Fast(FastSettings { solver, ..FastSettings::new(1.0 / 240.0) })).unwrap();
            w
        }
        _ => {
            let mut w = World::new();
            let mut last = None;
            for k in 0..(2 + seed as usize % 4) {
                let p = w
                    .add_particle(ParticleBuilder::new(1.0 + k as f64).position(Vector3::new(0.3 * k as f64, 0.0, 0.0)))
                    .unwrap();
                let spring = match last {
                    None => SpringBuilder::new(Attachment::Point(Vector3::new(0.0, 0.0, 0.5)), Attachment::Particle(p)),
                    Some(q) => SpringBuilder::new(Attachment::Particle(q), Attachment::Particle(p)),
                };
                w.add_spring(spring.stiffness(50.0 + 10.0 * seed as f64).damping(0.1)).unwrap();
                last = Some(p);
            }
            w
        }
    }
}

/// Span of each leg: whole steps of fast mode's 1/240 s.
const LEG: f64 = 60.0 / 240.0;

#[test]
fn a_state_read_and_put_back_continues_bit_for_bit_in_every_mode() {
    for kind in 0..4 {
        for seed in 0..5 {
            let mut w = scene(kind, seed);
            w.step(LEG).unwrap();
            let s = w.state();
            assert!(s.has_memory(), "kind {kind} seed {seed}: a stepped world's state carries its engine's memory");
            w.step(LEG).unwrap();
            let first = state_bits(&w);
            w.set_state(&s).unwrap();
            assert_eq!(w.time(), s.time);
            w.step(LEG).unwrap();
            assert_eq!(state_bits(&w), first, "kind {kind} seed {seed}: the second leg again");
            // into an engine built anew (reset drops the world's own), and into a copy of the world
            w.reset();
            w.set_state(&s).unwrap();
            w.step(LEG).unwrap();
            assert_eq!(state_bits(&w), first, "kind {kind} seed {seed}: after a reset");
            let mut copy = w.clone();
            copy.set_state(&s).unwrap();
            copy.step(LEG).unwrap();
            assert_eq!(state_bits(&copy), first, "kind {kind} seed {seed}: in a copy");
        }
    }
}

#[test]
fn an_edited_state_starts_afresh_as_a_new_world_built_with_it() {
    for kind in 0..4 {
        for seed in 0..4 {
            let mut stepped = scene(kind, seed);
            stepped.step(LEG).unwrap();
            let mut s = stepped.state();
            // row 1 is a body of the drops (row 0 the ground), row 0 a particle of the chain
            if kind < 3 {
                s.body_positions[1].z += 0.05;
                s.body_momenta[1].x += 0.1;
            } else {
                s.particle_positions[0].z += 0.05;
            }
            stepped.set_state(&s).unwrap();
            let mut fresh = scene(kind, seed);
            fresh.set_state(&s).unwrap();
            assert_eq!(state_bits(&stepped), state_bits(&fresh));
            stepped.step(LEG).unwrap();
            fresh.step(LEG).unwrap();
            assert_eq!(state_bits(&stepped), state_bits(&fresh), "kind {kind} seed {seed}");
        }
    }
}

#[test]
fn reset_returns_to_the_start_and_runs_as_a_new_world() {
    for kind in 0..4 {
        let mut w = scene(kind, 3);
        // a state set before the first step is part of the start
        if kind < 3 {
            let (h, b) = w.bodies().nth(1).map(|(h, b)| (h, b.position())).unwrap();
            w.set_body_state(h, b, UnitQuaternion::identity(), Vector3::new(0.5, 0.0, 0.0), Vector3::zeros()).unwrap();
        }
        let start = state_bits(&w);
        w.step(LEG).unwrap();
        let first = state_bits(&w);
        w.step(LEG).unwrap();
        assert!(w.report().forces.evaluations > 0);
        w.reset();
        assert_eq!(w.time(), 0.0);
        assert_eq!(w.report().forces.evaluations, 0, "the report starts again");
        assert_eq!(state_bits(&w), start);
        w.step(LEG).unwrap();
        assert_eq!(state_bits(&w), first, "kind {kind}");
    }
}

#[test]
fn rows_follow_removals_and_dead_or_foreign_handles_are_refused() {
    let mut w = World::new();
    let ball =
        |z: f64| RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0).position(Vector3::new(0.0, 0.0, z));
    let h: Vec<BodyHandle> = (0..3).map(|k| w.add_body(ball(k as f64)).unwrap()).collect();
    assert_eq!((w.body_row(h[0]).unwrap(), w.body_row(h[2]).unwrap()), (0, 2));
    w.remove_body(h[1]).unwrap();
    assert_eq!(w.body_row(h[2]).unwrap(), 1, "the row after a removal");
    assert!(matches!(w.body_row(h[1]), Err(WorldError::UnknownHandle { name: "handle", .. })));
    let again = w.add_body(ball(9.0)).unwrap(); // takes the freed slot
    assert_eq!((w.body_row(again).unwrap(), w.body_row(h[2]).unwrap()), (1, 2));
    let s = w.state();
    assert_eq!(s.body_positions[w.body_row(again).unwrap()].z, 9.0);
    assert_eq!(s.body_positions[w.body_row(h[2]).unwrap()].z, 2.0);
    let mut other = World::new();
    let theirs = other.add_body(ball(0.0)).unwrap();
    assert!(matches!(w.body_row(theirs), Err(WorldError::UnknownHandle { .. })), "a handle of another world");
    let p = other.add_particle(ParticleBuilder::new(1.0)).unwrap();
    assert_eq!(other.particle_row(p).unwrap(), 0);
    assert!(w.particle_row(p).is_err());
}

#[test]
fn a_bad_state_is_refused_by_name_and_changes_nothing() {
    let mut w = scene(1, 2);
    w.step(LEG).unwrap();
    let good = w.state();
    let before = state_bits(&w);
    let mut bad: Vec<(&str, tumble::WorldState)> = Vec::new();
    let mut s = good.clone();
    s.body_positions.pop();
    bad.push(("body_positions", s));
    let mut s = good.clone();
    s.body_momenta[1].y = f64::NAN;
    bad.push(("body_momenta", s));
    let mut s = good.clone();
    s.body_orientations[1] = UnitQuaternion::new_unchecked(s.body_orientations[1].into_inner() * 1.5);
    bad.push(("body_orientations", s));
    let mut s = good.clone();
    s.body_positions[0].z += 1.0; // the ground is static
    bad.push(("body_positions", s));
    let mut s = good.clone();
    s.time = f64::INFINITY;
    bad.push(("time", s));
    let mut s = good.clone();
    s.body_angular_momenta[1].x = 1e300;
    bad.push(("body_angular_momenta", s));
    for (name, s) in bad {
        match w.set_state(&s) {
            Err(WorldError::InvalidArgument { name: got, reason }) => assert_eq!(got, name, "{reason}"),
            other => panic!("{name}: expected an error naming it, got {other:?}"),
        }
        assert_eq!(state_bits(&w), before, "{name}: nothing changed");
    }
    // and the hidden state neither: the world continues as one that was never given them
    let mut clean = scene(1, 2);
    clean.step(LEG).unwrap();
    w.step(LEG).unwrap();
    clean.step(LEG).unwrap();
    assert_eq!(state_bits(&w), state_bits(&clean));
}

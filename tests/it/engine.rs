//! The engine layer: runs repeat bit for bit (reruns, one thread or many), options that do not apply are errors,
//! recording frames does not change fast mode's physics, the plan names exactly the stages that run, and step logs
//! hold the steps actually taken.
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use crate::common;
use common::{state_bits, Lcg};
use nalgebra::{UnitQuaternion, Vector3};
use tumble::scenes::{BouncingBall, Dominoes, Pile};
use tumble::{
    FastSettings, IntegratorOptions, Material, Mode, ParticleBuilder, RigidBodyBuilder, Shape, World, WorldOptions,
};

/// Five random bodies (boxes and spheres, random sizes, orientations, densities and materials) dropped together
/// onto the floor from overlapping columns, so they land on each other.
fn random_drop(seed: u64) -> World {
    let mut rng = Lcg(seed);
    let mut w = World::new();
    w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
    w.add_ground(0.0, Material::new(0.3, 0.5)).unwrap();
    for k in 0..5 {
        let shape = if rng.next() < 0.5 {
            Shape::cuboid(Vector3::new(rng.range(0.1, 0.4), rng.range(0.1, 0.4), rng.range(0.1, 0.4))).unwrap()
        } else {
            Shape::sphere(rng.range(0.1, 0.3)).unwrap()
        };
        let q = UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        w.add_body(
            RigidBodyBuilder::from_shape(shape, rng.range(100.0, 3000.0))
                .position(Vector3::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2), 0.5 + 0.9 * k as f64))
                .orientation(q)
                .angular_velocity(Vector3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)))
                .restitution(rng.range(0.0, 0.6))
                .friction(rng.range(0.1, 0.9)),
        )
        .unwrap();
    }
    w
}

/// Runs a fresh world from `build` for `seconds`: twice on one thread, once on two and once on three (more than
/// this machine's cores need not have); all end in the same bits. Returns the final state.
fn same_bits_three_ways(name: &str, build: impl Fn() -> World, seconds: f64) -> Vec<u64> {
    let mut runs = Vec::new();
    for threads in [1, 1, 2, 3] {
        let mut w = build();
        w.set_threads(threads).unwrap();
        w.run(seconds, 1.0 / 60.0).unwrap();
        runs.push(state_bits(&w));
    }
    assert_eq!(runs[0], runs[1], "{name}: two runs in one process differ");
    assert_eq!(runs[0], runs[2], "{name}: two threads differ from one");
    assert_eq!(runs[0], runs[3], "{name}: three threads differ from one");
    runs.remove(0)
}

#[test]
fn dominoes_pile_and_random_drops_repeat_bit_for_bit_across_reruns_and_thread_counts() {
    // The 20 dominoes for their whole fall (497 / 493 / 482 collisions in three runs before the warm start's sums
    // were ordered).
    same_bits_three_ways("dominoes", || Dominoes::default().build().unwrap().0, 6.0);
    // A 512-box pile while it lands and settles, kept awake (from 1,000 contacts a step, the soft step's batches are
    // solved on several threads).
    let awake_pile = || {
        let mut w = Pile { side: 16, layers: 2 }.build().unwrap().0;
        let Mode::Fast(settings) = w.mode() else { unreachable!("the pile is a fast-mode scene") };
        w.set_mode(Mode::Fast(FastSettings { sleep: false, ..settings })).unwrap();
        w
    };
    same_bits_three_ways("pile", awake_pile, 1.5);
    for seed in 1..=3 {
        let end = same_bits_three_ways("random drop", || random_drop(seed), 3.0);
        assert!(end.iter().all(|b| f64::from_bits(*b).is_finite()), "seed {seed}");
    }
}

#[test]
fn one_large_island_with_joints_and_springs_repeats_bit_for_bit_on_any_thread_count() {
    // A pyramid of 28 layers (406 cubes, about 2,400 contacts in one island: solved colour by colour on all the
    // workers) with a chain of three hinged boxes and a spring hanging from its top: the joints and the spring are
    // stages of the same list, on worker 0, between the colours' shared sweeps.
    let build = || {
        let (mut w, cubes) = tumble::scenes::Pyramid { layers: 28 }.build().unwrap();
        let top = *cubes.last().unwrap();
        let apex = w.body(top).unwrap().position();
        let mut last = top;
        for k in 1..=3 {
            let at = apex + Vector3::new(0.6 * k as f64, 0.0, 0.0);
            let link = w
                .add_body(
                    RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.2)).unwrap(), 300.0).position(at),
                )
                .unwrap();
            let hinge = tumble::JointBuilder::hinge(Some(last), Some(link), Vector3::y())
                .anchor_a(Vector3::new(0.3, 0.0, 0.0))
                .anchor_b(Vector3::new(-0.3, 0.0, 0.0));
            w.add_joint(hinge).unwrap();
            last = link;
        }
        let spring = tumble::SpringBuilder::new(
            tumble::Attachment::Body(last, Vector3::zeros()),
            tumble::Attachment::Point(apex + Vector3::new(1.8, 0.0, 1.0)),
        )
        .stiffness(2000.0)
        .damping(5.0);
        w.add_spring(spring).unwrap();
        w
    };
    let end = same_bits_three_ways("pyramid with a chain", build, 0.5);
    assert!(end.iter().all(|b| f64::from_bits(*b).is_finite()));
}

#[test]
fn accurate_mode_repeats_bit_for_bit() {
    let runs: Vec<Vec<u64>> = (0..2)
        .map(|_| {
            let (mut w, _) = BouncingBall::default().build().unwrap();
            w.run(3.0, 1.0 / 60.0).unwrap();
            state_bits(&w)
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
}

#[test]
fn fast_mode_frames_do_not_change_the_physics() {
    let dt = 1.0 / 240.0;
    let mut ends = Vec::new();
    for interval in [dt / 4.0, dt, 1.0 / 60.0, 0.1] {
        let mut w = random_drop(7);
        let run = w.run(2.0, interval).unwrap();
        // Each frame is the state of a step: times are whole steps, increasing, the last one the end.
        assert!(run.times.windows(2).all(|t| t[1] > t[0]), "interval {interval}");
        assert!((run.times.last().unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(run.step_times.len(), 480, "2 s in steps of 1/240 s, whatever the frames");
        assert!(run.step_sizes.iter().all(|&h| h == dt));
        ends.push(state_bits(&w));
    }
    for e in &ends[1..] {
        assert_eq!(&ends[0], e, "the frame interval changed the state");
    }
    // One call of 2 s and 120 calls of 1/60 s take the same steps.
    let mut w = random_drop(7);
    for _ in 0..120 {
        w.step(1.0 / 60.0).unwrap();
    }
    assert_eq!(state_bits(&w), ends[0]);
}

#[test]
fn fast_mode_steps_only_whole_steps_and_a_refusal_changes_nothing() {
    let mut w = random_drop(3);
    w.step(0.25).unwrap();
    let before = (state_bits(&w), w.time());
    let e = w.step(0.001).unwrap_err();
    assert_eq!(e.argument(), Some("dt"), "{e}");
    let e = w.run(0.001, 0.001).unwrap_err();
    assert_eq!(e.argument(), Some("duration"), "{e}");
    assert_eq!((state_bits(&w), w.time()), before);
    // a call of more than the 1e7-step budget is refused, not run
    let e = w.step(1e7).unwrap_err();
    assert_eq!(e.argument(), Some("dt"), "{e}");
}

#[test]
fn options_that_do_not_apply_to_the_mode_are_errors_naming_them() {
    let fast = |integrator: IntegratorOptions| {
        WorldOptions { mode: Some("fast".into()), integrator, ..WorldOptions::default() }.build()
    };
    let e = fast(IntegratorOptions { integrator: Some("radau5".into()), ..Default::default() }).err().unwrap();
    assert_eq!(e.argument(), Some("integrator"), "{e}");
    let e = fast(IntegratorOptions { rtol: Some(1e-8), ..Default::default() }).err().unwrap();
    assert_eq!(e.argument(), Some("rtol"), "{e}");
    let e = fast(IntegratorOptions { newton: true, ..Default::default() }).err().unwrap();
    assert_eq!(e.argument(), Some("newton"), "{e}");
    let w = fast(IntegratorOptions { dt: Some(0.01), ..Default::default() }).unwrap();
    assert_eq!(w.mode(), Mode::Fast(FastSettings::new(0.01)), "dt is fast mode's step");
    let e = WorldOptions { substeps: Some(4), ..WorldOptions::default() }.build().err().unwrap();
    assert_eq!(e.argument(), Some("substeps"), "{e}");
    let e = WorldOptions { solver: Some("soft".into()), ..WorldOptions::default() }.build().err().unwrap();
    assert_eq!(e.argument(), Some("solver"), "{e}");
    // sleep and the solver apply to accurate mode too
    let w = WorldOptions { sleep: Some(false), solver: Some("clarabel".into()), ..WorldOptions::default() }.build();
    let expected = tumble::AccurateSettings {
        sleep: false,
        solver: tumble::AccurateSolver::Clarabel,
        ..tumble::AccurateSettings::default()
    };
    assert_eq!(w.unwrap().mode(), Mode::Accurate(expected));
    let e = tumble::mode_from("accurate", &tumble::ModeOptions { dt: Some(0.01), ..Default::default() }).unwrap_err();
    assert_eq!(e.argument(), Some("dt"), "{e}");
    // An integrator chosen in fast mode.
    let mut w = World::new();
    w.set_mode(Mode::fast(0.01)).unwrap();
    let e = w.set_integrator(tumble::Settings::fixed(tumble::Method::Rk4, 0.01)).unwrap_err();
    assert_eq!(e.argument(), Some("integrator"), "{e}");
    let e = IntegratorOptions { integrator: Some("rk4".into()), tolerance: Some(1e-3), ..Default::default() }
        .settings()
        .unwrap_err();
    assert_eq!(e.argument(), Some("tolerance"), "{e}");
}

/// Steps a world and compares the stages its report saw running with its plan.
fn plan_is_kept(name: &str, mut w: World, seconds: f64) {
    let plan = w.plan();
    w.run(seconds, 1.0 / 60.0).unwrap();
    assert_eq!(w.plan(), plan, "{name}: running changed the plan");
    assert_eq!(w.report().stages.ran(), plan.stages, "{name}: the stages that ran are not the plan's");
}

#[test]
fn the_plan_names_exactly_the_stages_that_run() {
    // Particles on springs with damping, a constant load and a callback, by an implicit method.
    let (mut cloth, ps) = tumble::scenes::Cloth { n: 4, ..Default::default() }.build().unwrap();
    cloth.add_force(tumble::Target::Particle(ps[0]), Vector3::new(0.1, 0.0, 0.0), None).unwrap();
    cloth.add_force_callback(tumble::Target::Particle(ps[1]), |_, _| Ok(tumble::Wrench::default())).unwrap();
    plan_is_kept("cloth", cloth, 0.1);
    // A spinning body with a torque, explicit method: no Jacobian.
    let (top, _) = tumble::scenes::spinning_top().unwrap();
    plan_is_kept("top", top, 0.05);
    // A box dropped onto the floor in accurate mode: collision, bisection, impulse, then resting contact.
    let mut drop = World::new();
    drop.add_ground(0.0, Material::new(0.0, 0.0)).unwrap();
    drop.add_body(
        RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.1)).unwrap(), 1000.0)
            .position(Vector3::new(0.0, 0.0, 0.3)),
    )
    .unwrap();
    plan_is_kept("accurate drop", drop, 2.0); // asleep by the end
                                              // The pile in fast mode, sleeping at the end.
    let (pile, _) = Pile { side: 3, layers: 1 }.build().unwrap();
    plan_is_kept("pile", pile, 2.0);
    // Particles without gravity or shapes.
    let mut free = World::new();
    free.set_gravity(Vector3::zeros()).unwrap();
    free.add_particle(ParticleBuilder::new(1.0).velocity(Vector3::x())).unwrap();
    plan_is_kept("free particle", free, 0.5);
}

#[test]
fn accurate_steps_are_logged_as_taken() {
    let (mut w, _) = BouncingBall::default().build().unwrap();
    // awake to the end (a sleeping ball's clock advances without steps)
    w.set_mode(Mode::Accurate(tumble::AccurateSettings { sleep: false, ..Default::default() })).unwrap();
    let run = w.run(5.0, 1.0 / 60.0).unwrap();
    let (times, sizes) = (&run.step_times, &run.step_sizes);
    assert!(!run.contact_events.is_empty());
    // Each step starts where the last one ended: its end minus its size is the previous end (to rounding).
    let mut previous = 0.0;
    for (t, h) in times.iter().zip(sizes) {
        assert!(*h > 0.0 && *t > previous, "step ({t}, {h}) after {previous}");
        assert!((t - h - previous).abs() <= 1e-12 * t.max(1.0), "step ({t}, {h}) does not start at {previous}");
        previous = *t;
    }
    assert!((previous - 5.0).abs() < 1e-12);
    // Every contact event ends a step.
    for e in &run.contact_events {
        assert!(times.iter().any(|t| t == e), "event at {e} ends no step");
    }
}

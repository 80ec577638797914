//! Contact benchmarks: fast mode's time per step for 100, 1,000, 5,000 and 10,000 boxes falling into a pile with
//! the soft step (the default solver), and 100 with the exact cone program for the ratio; accurate
//! mode on the bouncing ball, on a column of ten cubes and on twenty cubes dropped in a pile (the wall time of the
//! first simulated 0.5 s, printed per simulated second); the share of that time spent finding contacts, preparing
//! the rows, solving and the rest is printed from the world's report, with the substeps, clarabel solves, contact steps and events; and a
//! contact step's time split on the 20-cube pile and ten dominoes (`accurate_step_split`).
//!
//! Run: `cargo bench --bench contact`. The pile: cubes of edge 0.5 m on a k x k grid (0.6 m apart) in L layers
//! (0.6 m apart), each slightly tilted, dropped onto the floor; the measured steps lie between 0.4 s and 1.0 s
//! of falling, while the layers land and stacks form. In test mode (`cargo test --all-targets` runs each bench
//! once) only the 100-box pile is built: the others take minutes to set up.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use tumble::World;

fn pile(side: usize, layers: usize, exact: bool) -> World {
    let mut w = tumble::scenes::Pile { side, layers }.build().unwrap().0;
    if exact {
        let tumble::Mode::Fast(settings) = w.mode() else { unreachable!("the pile is a fast-mode scene") };
        w.set_mode(tumble::Mode::Fast(tumble::FastSettings { solver: tumble::FastSolver::exact(), ..settings }))
            .unwrap();
    }
    w
}

/// Prints where `seconds` of stepping went, from the world's report of those steps.
fn share(name: &str, w: &World, before: &tumble::WorldReport, seconds: f64) {
    let r = w.report();
    let wall = seconds;
    let finding = r.collision_seconds - before.collision_seconds;
    let solving = r.contact_seconds - before.contact_seconds;
    let preparing = (r.program_seconds - before.program_seconds).min(solving);
    println!(
        "{name}: {} steps in {:.3} s; finding contacts {:.0}%, preparing the rows {:.0}%, solving {:.0}%, the rest {:.0}% \
         ({} clarabel solves, {} islands, {} asleep)",
        r.integrator.steps - before.integrator.steps,
        wall,
        100.0 * finding / wall,
        100.0 * preparing / wall,
        100.0 * (solving - preparing) / wall,
        100.0 * (wall - finding - solving).max(0.0) / wall,
        r.qp_solves - before.qp_solves,
        r.islands - before.islands,
        r.sleepers
    );
}

fn test_mode() -> bool {
    std::env::args().any(|a| a == "--test")
}

/// The measured window: from 0.4 s (the lower layers have landed) to 1.0 s (the top layer, dropped from about
/// 0.6 L m, has landed too); each measured step continues the pile, which is rebuilt (untimed) when it leaves the
/// window, so every sample is a step of boxes landing and stacking, not of a pile asleep.
const WINDOW: (f64, f64) = (0.4, 1.0);
const DT: f64 = 1.0 / 240.0;

fn fast_pile(c: &mut Criterion) {
    let sizes: &[(usize, usize)] = if test_mode() { &[(5, 4)] } else { &[(5, 4), (10, 10), (25, 8), (50, 4)] };
    pile_group(c, "fast_pile_step", sizes, false);
    pile_group(c, "fast_pile_step_exact", &[(5, 4)], true);
}

fn pile_group(c: &mut Criterion, name: &str, sizes: &[(usize, usize)], exact: bool) {
    let mut g = c.benchmark_group(name);
    g.sample_size(10);
    for &(k, layers) in sizes {
        let n = k * k * layers;
        let fresh = || {
            let mut w = pile(k, layers, exact);
            w.step(WINDOW.0).unwrap();
            w
        };
        let mut w = fresh();
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter_custom(|iters| {
                let mut spent = std::time::Duration::ZERO;
                for _ in 0..iters {
                    if w.time() >= WINDOW.1 {
                        w = fresh();
                    }
                    let clock = std::time::Instant::now();
                    w.step(DT).unwrap();
                    spent += clock.elapsed();
                }
                spent
            })
        });
        // 24 more steps, timed, for the shares
        if w.time() + 0.1 > WINDOW.1 {
            w = fresh();
        }
        let before = w.report();
        let clock = std::time::Instant::now();
        w.step(0.1).unwrap();
        let solver = match w.mode() {
            tumble::Mode::Fast(f) => match f.solver {
                tumble::FastSolver::Soft(s) => format!("soft step, {} substeps x {} sweeps", s.substeps, s.iterations),
                tumble::FastSolver::Exact { .. } => "exact cone program".to_string(),
            },
            _ => unreachable!("fast mode"),
        };
        share(&format!("{n} boxes ({solver}), t = {:.2} s", w.time()), &w, &before, clock.elapsed().as_secs_f64());
    }
    g.finish();
}

fn accurate_ball(c: &mut Criterion) {
    let mut g = c.benchmark_group("accurate_bouncing_ball");
    g.bench_function("5 s, e = 0.8", |b| {
        b.iter(|| {
            let (mut w, _) = tumble::scenes::BouncingBall::default().build().unwrap();
            w.step(5.0).unwrap();
            w
        })
    });
    g.finish();
    let (mut w, _) = tumble::scenes::BouncingBall::default().build().unwrap();
    let before = w.report();
    let clock = std::time::Instant::now();
    w.step(5.0).unwrap();
    share("bouncing ball", &w, &before, clock.elapsed().as_secs_f64());
}

/// Cubes of edge 0.5 m (density 500, friction 0.6) in a column of ten, 1 mm apart, or twenty dropped on a 3 x 3 grid
/// in three layers, slightly tilted (the scenes of `tests/it/accurate_stacks.rs`).
fn accurate_scene(pile: bool) -> World {
    use nalgebra::{UnitQuaternion, Vector3};
    use tumble::{Material, RigidBodyBuilder, Shape};
    let mut w = World::new();
    w.add_ground(0.0, Material::new(0.2, 0.6)).unwrap();
    let cube = Shape::cuboid(Vector3::repeat(0.25)).unwrap();
    let count = if pile { 20 } else { 10 };
    for k in 0..count {
        let body = RigidBodyBuilder::from_shape(cube.clone(), 500.0).friction(0.6).restitution(0.2);
        let body = if pile {
            let (i, j, l) = (k % 3, (k / 3) % 3, k / 9);
            let tilt = 0.05 * ((k * 7919 % 13) as f64 / 13.0 - 0.5);
            body.position(Vector3::new(0.6 * i as f64, 0.6 * j as f64, 0.3 + 0.6 * l as f64))
                .orientation(UnitQuaternion::from_euler_angles(tilt, -tilt, 2.0 * tilt))
        } else {
            body.position(Vector3::new(0.0, 0.0, 0.25 + 0.501 * k as f64))
        };
        w.add_body(body).unwrap();
    }
    w
}

fn accurate_contact(c: &mut Criterion) {
    let span = if test_mode() { 0.05 } else { 0.5 };
    let mut g = c.benchmark_group("accurate_contact");
    g.sample_size(10);
    for (name, pile) in [("column of 10", false), ("pile of 20", true)] {
        g.bench_function(format!("{name}, first {span} s"), |b| {
            b.iter(|| {
                let mut w = accurate_scene(pile);
                w.step(span).unwrap();
                w
            })
        });
        let mut w = accurate_scene(pile);
        let before = w.report();
        let clock = std::time::Instant::now();
        w.step(span).unwrap();
        let wall = clock.elapsed().as_secs_f64();
        share(&format!("accurate {name}"), &w, &before, wall);
        let r = w.report();
        println!(
            "  {:.2} s of wall time per simulated second; {} contact steps ({} rejected), {} collisions, {} bisection \
             steps",
            wall / span,
            r.contact_steps,
            r.contact_rejected,
            r.collisions,
            r.bisection_steps
        );
    }
    g.finish();
}

/// A contact step's time split on the scenes accurate mode is compared with Drake's CENIC on
/// (`tumble::scenes::Benchmark`: the 20-cube pile and ten dominoes, at their defaults, one thread, frames every
/// 1/60 s): the wall time of a contact step, and its shares: finding contacts, building the contact programs and
/// solving them (whole step, halves and lagged re-solves), and the rest (error control: the estimate, the
/// extrapolation, the energy guard, sleeping and frames).
fn accurate_split(c: &mut Criterion) {
    use tumble::scenes::Benchmark;
    let span = if test_mode() { 0.05 } else { 1.0 };
    let mut g = c.benchmark_group("accurate_step_split");
    g.sample_size(10);
    for (name, scene) in [("20-cube pile", Benchmark::CubePile), ("ten dominoes", Benchmark::DominoRow)] {
        let build = || {
            let (mut w, _) = scene.build().unwrap();
            w.set_threads(1).unwrap();
            w
        };
        g.bench_function(format!("{name}, first {span} s"), |b| {
            b.iter(|| {
                let mut w = build();
                w.run(span, 1.0 / 60.0).unwrap();
                w
            })
        });
        let mut w = build();
        let r = w.run(span, 1.0 / 60.0).unwrap().report;
        let steps = (r.contact_steps + r.contact_rejected).max(1) as f64;
        let rest = r.wall_seconds - r.collision_seconds - r.contact_seconds;
        println!(
            "{name}: {:.3} ms a contact step tried ({} accepted, {} rejected): finding contacts {:.0}%, building the \
             programs {:.0}%, solving them {:.0}% ({} programs), error control and the rest {:.0}%",
            1e3 * r.wall_seconds / steps,
            r.contact_steps,
            r.contact_rejected,
            100.0 * r.collision_seconds / r.wall_seconds,
            100.0 * r.program_seconds / r.wall_seconds,
            100.0 * (r.contact_seconds - r.program_seconds) / r.wall_seconds,
            r.qp_solves,
            100.0 * rest / r.wall_seconds
        );
    }
    g.finish();
}

criterion_group!(benches, fast_pile, accurate_ball, accurate_contact, accurate_split);
criterion_main!(benches);

//! The peer comparison's scenes in tumble's fast mode: a pile of N cubes, a stack of 10, a sliding box, a resting
//! box and a bullet, each measured as the comparison asks (the stack's and the resting box's time a step too: the
//! fixed cost of a step), one markdown row each. The same scene
//! definitions are in `benches/peers/` for Rapier, MuJoCo and PyBullet.
//!
//! cargo run --release --example fast_scenes -- [soft|exact] [pile sizes, e.g. 100 1000] [--substeps N]
//!     [--iterations K] [--hertz F] [--threads T]
//! cargo run --release --example fast_scenes -- pyramids [--substeps N] ...   (Box3D's two walls of cubes instead)
//! (`--only-piles`: the piles and nothing else; `bins`: the bins of `tumble::scenes::Bin` instead)

#[path = "../benches/peers/overlap.rs"]
mod overlap;

use nalgebra::Vector3;
use std::time::Instant;
use tumble::{BodyHandle, FastSettings, FastSolver, Material, Mode, RigidBodyBuilder, Shape, SoftSolver, World};

const G: f64 = 9.81;

fn world(dt: f64, solver: FastSolver, sleep: bool, mu: f64) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings { sleep, solver, ..FastSettings::new(dt) })).unwrap();
    w.add_ground(0.0, Material::new(0.0, mu)).unwrap();
    w
}

fn cube(w: &mut World, half: f64, density: f64, at: Vector3<f64>, mu: f64) -> BodyHandle {
    let shape = Shape::cuboid(Vector3::repeat(half)).unwrap();
    w.add_body(RigidBodyBuilder::from_shape(shape, density).position(at).restitution(0.0).friction(mu)).unwrap()
}

/// The pile: N cubes of half extent 0.5 m on a 10 x 10 grid at 1.2 m pitch, N / 100 layers 1.2 m apart, the lowest
/// bottoms 2 m up; 600 steps of 1/60 s, each a call of its own and timed alone. Returns (ms a step, the deepest
/// overlap over the last 100 steps, recomputed from the poses as for every engine: `benches/peers/overlap.rs`).
fn pile(n: usize, solver: FastSolver, sleep: bool, threads: usize) -> (f64, f64) {
    let mut w = world(1.0 / 60.0, solver, sleep, 0.5);
    w.set_threads(threads).unwrap();
    let cubes: Vec<BodyHandle> = (0..n)
        .map(|k| {
            let (layer, i, j) = (k / 100, (k % 100) / 10, k % 10);
            let at = Vector3::new(1.2 * i as f64, 1.2 * j as f64, 2.5 + 1.2 * layer as f64);
            cube(&mut w, 0.5, 1000.0, at, 0.5)
        })
        .collect();
    let (mut spent, mut penetration) = (0.0, 0.0f64);
    for step in 0..600 {
        let clock = Instant::now();
        w.step(1.0 / 60.0).unwrap();
        spent += clock.elapsed().as_secs_f64();
        if step >= 500 {
            penetration = penetration.max(overlap::deepest(&boxes(&w, &cubes, 0.5)));
        }
    }
    let r = w.report();
    eprintln!(
        "pile {n}, sleep {sleep}: finding contacts {:.3} ms, solving {:.3} ms (building the rows {:.3} ms) a step; {:.0} pushing \
         contacts and {:.1} islands a step; solver residual {:.1e} m/s",
        r.collision_seconds * 1e3 / 600.0,
        r.contact_seconds * 1e3 / 600.0,
        r.program_seconds * 1e3 / 600.0,
        r.impulses as f64 / 600.0,
        r.islands as f64 / 600.0,
        r.contact_residual
    );
    (spent * 1e3 / 600.0, penetration)
}

/// The cubes of half extent `half` as boxes posed where the world has them.
fn boxes(w: &World, cubes: &[BodyHandle], half: f64) -> Vec<overlap::Boxed> {
    cubes.iter().map(|&b| (Vector3::repeat(half), w.body(b).unwrap().pose())).collect()
}

/// Box3D's walls of cubes (`tumble::scenes::LargePyramid`, `ManyPyramids`): `steps` steps of 1/60 s, the first
/// untimed (Box3D's benchmark does the same), each a call of its own. Returns (ms a step, the largest sink of a
/// wall's top cube, the deepest overlap at the end).
fn walls(
    mut w: World,
    walls: Vec<Vec<BodyHandle>>,
    solver: FastSolver,
    threads: usize,
    steps: usize,
) -> (f64, f64, f64) {
    let Mode::Fast(settings) = w.mode() else { unreachable!("the walls are fast-mode scenes") };
    w.set_mode(Mode::Fast(FastSettings { solver, ..settings })).unwrap();
    w.set_threads(threads).unwrap();
    let tops: Vec<BodyHandle> = walls.iter().map(|c| *c.last().expect("a cube a wall")).collect();
    let start: Vec<f64> = tops.iter().map(|&b| w.body(b).unwrap().position().z).collect();
    w.step(1.0 / 60.0).unwrap();
    let clock = Instant::now();
    for _ in 1..steps {
        w.step(1.0 / 60.0).unwrap();
    }
    let ms = clock.elapsed().as_secs_f64() * 1e3 / (steps - 1) as f64;
    let sink = tops.iter().zip(&start).map(|(&b, z)| z - w.body(b).unwrap().position().z).fold(0.0, f64::max);
    let all: Vec<BodyHandle> = walls.into_iter().flatten().collect();
    (ms, sink, overlap::deepest(&boxes(&w, &all, 0.5)))
}

/// The bins (`tumble::scenes::Bin`): 500 equal boxes, boxes of random sizes, and mixed shapes, at `solver` with
/// sleeping, each stepped 5 s, run 1 s (its deepest overlap), then 2 s more: ms a step over the first 6 s, the
/// overlap, and how many sleep at 6 s and at 8 s.
fn bins(solver: FastSolver, threads: usize) {
    use tumble::scenes::{Bin, Fill};
    for (fill, name) in [
        (Fill::EqualBoxes, "equal boxes"),
        (Fill::MixedBoxes, "boxes of random sizes"),
        (Fill::MixedShapes, "boxes, balls, capsules, hulls"),
    ] {
        let (mut w, _) = Bin { count: 500, fill, seed: 1 }.build().unwrap();
        let Mode::Fast(settings) = w.mode() else { unreachable!("a fast-mode scene") };
        w.set_mode(Mode::Fast(FastSettings { solver, ..settings })).unwrap();
        w.set_threads(threads).unwrap();
        let clock = Instant::now();
        w.step(5.0).unwrap();
        let run = w.run(1.0, 1.0 / 60.0).unwrap();
        let ms = clock.elapsed().as_secs_f64() * 1e3 / 360.0;
        let overlap = run.penetration.iter().fold(0.0f64, |m, p| m.max(*p));
        let asleep = w.report().sleepers;
        w.step(2.0).unwrap();
        println!(
            "| bin of 500 {name}: ms a step / deepest contact in the last second / asleep at 6 s, 8 s | {ms:.2} ms / {:.2} mm / {asleep}, {} |",
            overlap * 1e3,
            w.report().sleepers
        );
    }
}

/// The rows of Box3D's two benchmark walls.
fn pyramids(solver: FastSolver, threads: usize) {
    let (w, cubes) = tumble::scenes::LargePyramid::default().build().unwrap();
    let (ms, sink, deepest) = walls(w, vec![cubes], solver, threads, 200);
    println!(
        "| large pyramid (5,050 cubes), 200 steps: ms a step / top's sink / overlap | {ms:.1} ms / {:.1} mm / {:.2} mm |",
        sink * 1e3,
        deepest * 1e3
    );
    let (w, walls_of) = tumble::scenes::ManyPyramids::default().build().unwrap();
    let (ms, sink, deepest) = walls(w, walls_of, solver, threads, 100);
    println!(
        "| many pyramids (10,780 cubes), 100 steps: ms a step / largest top's sink / overlap | {ms:.1} ms / {:.2} mm / {:.2} mm |",
        sink * 1e3,
        deepest * 1e3
    );
}

/// Largest displacement of any body over `seconds`, and the time of a step (us; the steps alone timed).
fn displacement(w: &mut World, bodies: &[BodyHandle], seconds: f64, dt: f64) -> (f64, f64) {
    let start: Vec<_> = bodies.iter().map(|&b| w.body(b).unwrap().position()).collect();
    let (mut worst, mut spent) = (0.0f64, 0.0);
    let steps = (seconds / dt).round() as usize;
    for _ in 0..steps {
        let clock = Instant::now();
        w.step(dt).unwrap();
        spent += clock.elapsed().as_secs_f64();
        for (&b, s) in bodies.iter().zip(&start) {
            worst = worst.max((w.body(b).unwrap().position() - s).norm());
        }
    }
    (worst, spent * 1e6 / steps as f64)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut soft = SoftSolver::default();
    if let Some(k) = args.iter().position(|a| a == "--substeps") {
        soft.substeps = args[k + 1].parse().expect("a whole number of substeps");
    }
    if let Some(k) = args.iter().position(|a| a == "--iterations") {
        soft.iterations = args[k + 1].parse().expect("a whole number of iterations");
    }
    // 0: one thread per core (the default)
    let threads = match args.iter().position(|a| a == "--threads") {
        Some(k) => args[k + 1].parse().expect("a whole number of threads"),
        None => 0,
    };
    if let Some(k) = args.iter().position(|a| a == "--hertz") {
        soft.contact_hertz = args[k + 1].parse().expect("a stiffness in hertz");
    }
    let solver = if args.iter().any(|a| a == "exact") { FastSolver::exact() } else { FastSolver::Soft(soft) };
    let sizes: Vec<usize> = args
        .iter()
        .enumerate()
        .filter(|(k, _)| *k == 0 || !args[k - 1].starts_with("--"))
        .filter_map(|(_, a)| a.parse().ok())
        .filter(|&n| n >= 100)
        .collect();
    println!("| tumble fast ({}) | value |\n|---|---|", solver.name());
    if args.iter().any(|a| a == "pyramids") {
        pyramids(solver, threads);
        return;
    }
    if args.iter().any(|a| a == "bins") {
        bins(solver, threads);
        return;
    }
    for &n in if sizes.is_empty() { &[100usize, 1000][..] } else { &sizes[..] } {
        for (sleep, label) in [(false, "no sleep"), (true, "sleeping")] {
            let (ms, pen) = pile(n, solver, sleep, threads);
            println!(
                "| pile {n}, {label}: ms a step / penetration (last 100 steps) | {ms:.3} ms / {:.3} mm |",
                pen * 1e3
            );
        }
    }
    if args.iter().any(|a| a == "--only-piles") {
        return;
    }
    // the default job's scene: 20 dominoes, 6 s, frames at 60 Hz
    let (mut w, _) = tumble::scenes::Dominoes::default().build().unwrap();
    let Mode::Fast(settings) = w.mode() else { unreachable!("dominoes are a fast-mode scene") };
    w.set_mode(Mode::Fast(FastSettings { solver, ..settings })).unwrap();
    let clock = Instant::now();
    w.run(6.0, 1.0 / 60.0).unwrap();
    println!("| dominoes (the default job), 6 s: wall time | {:.3} s |", clock.elapsed().as_secs_f64());
    // stack: 10 cubes of half extent 0.25 m, density 500, friction 0.6, dt 1/240, 10 s
    let dt = 1.0 / 240.0;
    let mut w = world(dt, solver, false, 0.6);
    let stack: Vec<_> =
        (0..10).map(|k| cube(&mut w, 0.25, 500.0, Vector3::new(0.0, 0.0, 0.25 + 0.5 * k as f64), 0.6)).collect();
    let (moved, us) = displacement(&mut w, &stack, 10.0, dt);
    println!("| stack of 10: largest displacement in 10 s | {:.3} mm |", moved * 1e3);
    println!("| stack of 10: us a step | {us:.2} us |");
    // slide: half extent 0.2 m, density 500, 2 m/s, mu 0.5, dt 1/240, 2 s
    let mut w = world(dt, solver, false, 0.5);
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.2)).unwrap(), 500.0)
                .position(Vector3::new(0.0, 0.0, 0.2))
                .velocity(Vector3::new(2.0, 0.0, 0.0))
                .restitution(0.0)
                .friction(0.5),
        )
        .unwrap();
    w.step(2.0).unwrap();
    let exact = 4.0 / (2.0 * 0.5 * G);
    let d = w.body(b).unwrap().position().x;
    println!("| slide: stop distance error | {:+.3}% |", (d - exact) / exact * 100.0);
    // rest: half extent 0.5 m, 10 s
    let mut w = world(dt, solver, false, 0.5);
    let b = cube(&mut w, 0.5, 1000.0, Vector3::new(0.0, 0.0, 0.5), 0.5);
    let (moved, us) = displacement(&mut w, &[b], 10.0, dt);
    println!("| rest: largest displacement in 10 s | {moved:.2e} m |");
    println!("| rest: us a step | {us:.2} us |");
    // bullet: a 5 cm sphere at 1000 m/s against a 1 cm static wall, dt 1/60
    let mut w = world(1.0 / 60.0, solver, false, 0.5);
    w.add_body(
        RigidBodyBuilder::fixed(Some(Shape::cuboid(Vector3::new(0.005, 2.0, 2.0)).unwrap()))
            .position(Vector3::new(5.0, 0.0, 2.0)),
    )
    .unwrap();
    let ball = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::sphere(0.05).unwrap(), 1000.0)
                .position(Vector3::new(0.0, 0.0, 2.0))
                .velocity(Vector3::new(1000.0, 0.0, 0.0)),
        )
        .unwrap();
    w.step(0.5).unwrap();
    let x = w.body(ball).unwrap().position().x;
    println!(
        "| bullet: ball ends at x (wall at 5 m) | {x:.3} m ({}) |",
        if x < 5.0 { "held by the wall" } else { "TUNNELLED" }
    );
}

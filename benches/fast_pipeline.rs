//! Fast mode's step on the peer comparison's 1,000-cube pile (1 m cubes, density 1000, friction 0.5, 1/60 s, sleep
//! off; `examples/fast_scenes.rs`) and on a wall of cubes (Box3D's large pyramid, 40 cubes at the base), each at
//! the default solver and at 2 substeps x 1 sweep, on one thread: the time of a step (criterion), and where it went,
//! printed from the world's report: finding contacts (broad and narrow phase, the kept pairs), preparing the rows,
//! solving (the substeps), and the rest (forces, moves, sleep, the report).
//!
//! Run: `cargo bench --bench fast_pipeline`. The pile is stepped 6 s before it is measured (it has landed and
//! rests, awake), the wall 1 s. In test mode (`cargo test --all-targets` runs each bench once) the scenes are small:
//! a pile of 100 and a wall of 10 at the base.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nalgebra::Vector3;
use tumble::{FastSettings, FastSolver, Material, Mode, RigidBodyBuilder, Shape, SoftSolver, World};

fn test_mode() -> bool {
    std::env::args().any(|a| a == "--test")
}

/// The solvers measured: the default, and 2 substeps of one sweep (the fixed cost of a step).
fn solvers() -> [(&'static str, FastSolver); 2] {
    let light = SoftSolver { substeps: 2, iterations: 1, ..SoftSolver::default() };
    [("default", FastSolver::default()), ("2x1", FastSolver::Soft(light))]
}

/// The peer pile of `n` cubes.
fn pile(n: usize, solver: FastSolver) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings { sleep: false, solver, ..FastSettings::new(1.0 / 60.0) })).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let cube = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    for k in 0..n {
        let (layer, i, j) = (k / 100, (k % 100) / 10, k % 10);
        let at = Vector3::new(1.2 * i as f64, 1.2 * j as f64, 2.5 + 1.2 * layer as f64);
        w.add_body(RigidBodyBuilder::from_shape(cube.clone(), 1000.0).position(at).friction(0.5).restitution(0.0))
            .unwrap();
    }
    w
}

/// Box3D's large pyramid of `base` cubes at the bottom.
fn wall(base: usize, solver: FastSolver) -> World {
    let (mut w, _) = tumble::scenes::LargePyramid { base }.build().unwrap();
    let Mode::Fast(settings) = w.mode() else { unreachable!("a fast-mode scene") };
    w.set_mode(Mode::Fast(FastSettings { solver, ..settings })).unwrap();
    w
}

/// Prints where the steps since `before` went, from the world's report.
fn share(name: &str, w: &World, before: &tumble::WorldReport) {
    let r = w.report();
    let steps = (r.integrator.steps - before.integrator.steps).max(1) as f64;
    let wall = r.integrator.wall_seconds - before.integrator.wall_seconds;
    let finding = r.collision_seconds - before.collision_seconds;
    let solving = r.contact_seconds - before.contact_seconds;
    let preparing = (r.program_seconds - before.program_seconds).min(solving);
    let ms = |s: f64| 1e3 * s / steps;
    println!(
        "{name}: {:.3} ms a step: finding contacts {:.3} ms, preparing the rows {:.3} ms, solving {:.3} ms, the rest \
         {:.3} ms",
        ms(wall),
        ms(finding),
        ms(preparing),
        ms(solving - preparing),
        ms((wall - finding - solving).max(0.0)),
    );
}

fn step_of(c: &mut Criterion, group: &str, scenes: &[(usize, f64)], make: fn(usize, FastSolver) -> World) {
    let mut g = c.benchmark_group(group);
    g.sample_size(10);
    for &(size, settle) in scenes {
        for (label, solver) in solvers() {
            let mut w = make(size, solver);
            w.set_threads(1).unwrap();
            w.step(settle).unwrap();
            let before = w.report();
            g.bench_with_input(BenchmarkId::new(label, size), &size, |b, _| b.iter(|| w.step(1.0 / 60.0).unwrap()));
            share(&format!("{group}/{label}/{size}"), &w, &before);
        }
    }
    g.finish();
}

fn fast_pipeline(c: &mut Criterion) {
    let (piles, walls) = if test_mode() { ([(100, 1.0)], [(10, 0.25)]) } else { ([(1000, 6.0)], [(40, 1.0)]) };
    step_of(c, "fast_pile_step", &piles, pile);
    step_of(c, "fast_wall_step", &walls, wall);
}

criterion_group!(benches, fast_pipeline);
criterion_main!(benches);

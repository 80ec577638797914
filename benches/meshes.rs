//! Fast mode's time per step on the pile of 50 meshes (cups, rings, stools, pebbles and pegs, `scenes::meshes`), each
//! body carrying its convex decomposition against the same pile of one convex hull each; both at 1/240 s on one
//! thread, timed over the steps from 0.4 s, as the first layers land.
//!
//! Run: `cargo bench --bench meshes`. The decompositions are made once, as the first pile is built.

use criterion::{criterion_group, criterion_main, Criterion};
use tumble::scenes::meshes::mesh_pile;
use tumble::{Mode, World};

fn pile(as_hull: bool) -> World {
    let (mut w, _) = mesh_pile(Mode::fast(1.0 / 240.0), 50, as_hull).unwrap();
    w.set_threads(1).unwrap();
    w.step(0.4).unwrap();
    w
}

fn step(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesh pile step (fast mode, 50 meshes, one thread)");
    g.sample_size(10);
    for (name, as_hull) in [("decomposed", false), ("convex hulls", true)] {
        let start = pile(as_hull);
        let r = start.report();
        println!("{name}: {} convex pieces, {} bodies", r.mesh_pieces, start.body_count() - 1);
        g.bench_function(name, |b| {
            b.iter_batched_ref(|| start.clone(), |w| w.step(1.0 / 240.0).unwrap(), criterion::BatchSize::LargeInput)
        });
    }
    g.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);

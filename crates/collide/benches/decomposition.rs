//! Convex decomposition time (parry's VHACD at the defaults: resolution 64, 32 pieces at most, concavity 0.01) for
//! tori of about 1k, 10k and 100k triangles, computed afresh each time (the per-process cache bypassed).
//!
//! Run: `cargo bench -p tumble-collide --bench decomposition`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tumble_collide::{Decomposed, Decomposition, Mesh};

fn decomposition(c: &mut Criterion) {
    let mut g = c.benchmark_group("decomposition");
    g.sample_size(10);
    // a torus of n segments each way has 2 n^2 triangles
    for n in [22u32, 71, 224] {
        let mesh = Mesh::torus_mesh(0.1, 0.03, n).unwrap();
        let label = format!("torus {} triangles", mesh.triangles().len());
        g.bench_function(label, |b| {
            b.iter(|| black_box(Decomposed::uncached(&mesh, &Decomposition::default()).unwrap().pieces().len()))
        });
    }
    g.finish();
}

criterion_group!(benches, decomposition);
criterion_main!(benches);

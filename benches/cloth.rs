//! Time per implicit Euler step of a square cloth against its particle count (16x16 up to 128x128), with the
//! springs' analytic sparse Jacobian and the velocity-form linear system solved by sparse LU (direct) or by
//! BiCGSTAB (iterative, rtol = 1e-6).
//!
//! The cloths are the same material, more of it: spacing 1/15 m, 1.95 g a particle, springs of 1000 N/m, so the
//! conditioning of the step's system, and with it the iteration count, does not grow with the size. Every
//! measured step starts from the state after one step from rest. Run: `cargo bench --bench cloth`.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use tumble::integrate::LinearSolver;
use tumble::scenes::Cloth;
use tumble::{Method, Settings, World};

const H: f64 = 1.0 / 60.0;

fn cloth(n: usize, solver: LinearSolver) -> World {
    let size = (n - 1) as f64 / 15.0;
    let mass = 0.5 / 256.0 * (n * n) as f64;
    let (mut w, _) = Cloth { n, size, mass, stiffness: 1e3, damping: 0.5, pin_stiffness: 1e4 }.build().unwrap();
    w.set_integrator(Settings::fixed(Method::ImplicitEuler, H).linear_solver(solver)).unwrap();
    w.step(H).unwrap();
    w
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("cloth implicit-euler step");
    g.sample_size(10);
    for (label, solver) in
        [("iterative", LinearSolver::Iterative { rtol: 1e-6, max_iter: 2000 }), ("direct", LinearSolver::Direct)]
    {
        for n in [16, 32, 64, 128] {
            g.bench_function(format!("{label} {n}x{n} ({} particles)", n * n), |b| {
                b.iter_batched(|| cloth(n, solver), |mut w| w.step(H).unwrap(), BatchSize::PerIteration)
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! Criterion benchmarks of representative (method, problem) pairs, and the per-step overhead of Dormand-Prince on
//! Lotka-Volterra next to the cost of its six right-hand-side evaluations.
//!
//! Run: `cargo bench --bench integrators`. Per-step overhead = (time of `lotka-volterra/dopri5` / its steps) /
//! time of six right-hand sides; the number of steps is printed before the measurements. Six evaluations are
//! timed two ways: independent (the CPU overlaps them) and chained, each output feeding the next input, which is
//! how the stages of a Runge-Kutta step depend on each other.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tumble::integrate::problems::{self, Kepler, LotkaVolterra};
use tumble::integrate::{solve, Method, OdeSystem, SaveAt, Settings};

fn lotka_volterra(c: &mut Criterion) {
    let p = problems::by_name("lotka-volterra").unwrap();
    let settings = Settings::tolerances(Method::Dopri5, 1e-8, 1e-8);
    let mut lv = LotkaVolterra { p: [1.5, 1.0, 3.0, 1.0] };
    let steps = solve(&mut lv, &settings, 0.0, &p.y0, p.t_end, &SaveAt::End).unwrap().report.steps;
    println!("lotka-volterra/dopri5 takes {steps} steps");
    let mut g = c.benchmark_group("lotka-volterra");
    g.bench_function("rhs x6 independent", |b| {
        let mut dy = [0.0; 2];
        let y = [1.1, 0.9];
        b.iter(|| {
            for _ in 0..6 {
                lv.rhs(black_box(0.0), black_box(&y), &mut dy).unwrap();
                black_box(&dy);
            }
        })
    });
    g.bench_function("rhs x6 chained", |b| {
        let mut dy = [0.0; 2];
        b.iter(|| {
            let mut y = black_box([1.1, 0.9]);
            for _ in 0..6 {
                lv.rhs(0.0, &y, &mut dy).unwrap();
                y = [y[0] + 1e-3 * dy[0], y[1] + 1e-3 * dy[1]];
            }
            black_box(y)
        })
    });
    g.bench_function("dopri5", |b| {
        b.iter(|| solve(&mut lv, black_box(&settings), 0.0, &p.y0, p.t_end, &SaveAt::End).unwrap())
    });
    g.bench_function("rk4 h=1e-3", |b| {
        let s = Settings::fixed(Method::Rk4, 1e-3);
        b.iter(|| solve(&mut lv, black_box(&s), 0.0, &p.y0, p.t_end, &SaveAt::End).unwrap())
    });
    g.finish();
}

fn kepler(c: &mut Criterion) {
    let p = Kepler::problem();
    let mut g = c.benchmark_group("kepler");
    for (name, settings) in [
        ("verlet h=1e-3", Settings::fixed(Method::Verlet, 1e-3)),
        ("dopri5 1e-8", Settings::tolerances(Method::Dopri5, 1e-8, 1e-8)),
        ("dop853 1e-10", Settings::tolerances(Method::Dop853, 1e-10, 1e-10)),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| solve(&mut Kepler, &settings, 0.0, &p.y0, p.t_end, &SaveAt::End).unwrap())
        });
    }
    g.finish();
}

/// Solves one stiff reference problem under the given settings.
fn bench_stiff(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    settings: Settings,
) {
    let problem = problems::by_name(name.split('/').next().unwrap()).unwrap();
    g.bench_function(name, |b| {
        b.iter(|| solve(&mut problem.system(), &settings, 0.0, &problem.y0, problem.t_end, &SaveAt::End).unwrap())
    });
}

fn stiff(c: &mut Criterion) {
    let mut g = c.benchmark_group("stiff");
    bench_stiff(&mut g, "rober/rodas4 1e-6", Settings::tolerances(Method::Rodas4, 1e-6, 1e-16));
    bench_stiff(&mut g, "rober/radau5 1e-8", Settings::tolerances(Method::Radau5, 1e-8, 1e-18));
    bench_stiff(&mut g, "van-der-pol/rodas4 1e-6", Settings::tolerances(Method::Rodas4, 1e-6, 1e-6));
    bench_stiff(&mut g, "van-der-pol/radau5 1e-6", Settings::tolerances(Method::Radau5, 1e-6, 1e-6));
    bench_stiff(&mut g, "hires/radau5 1e-8", Settings::tolerances(Method::Radau5, 1e-8, 1e-12));
    g.finish();
}

criterion_group!(benches, lotka_volterra, kepler, stiff);
criterion_main!(benches);

//! Criterion benchmarks of representative (method, problem) pairs, and the per-step overhead of Dormand-Prince on
//! Lotka-Volterra next to the cost of its six right-hand-side evaluations.
//!
//! Run: `cargo bench --bench integrators`. Per-step overhead = (time of `lotka-volterra/dopri5` / its steps) /
//! time of six right-hand sides; the number of steps is printed before the measurements. Six evaluations are
//! timed two ways: independent (the CPU overlaps them) and chained, each output feeding the next input, which is
//! how the stages of a Runge-Kutta step depend on each other.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tumble::integrate::problems::{self, Kepler, LotkaVolterra, Rober, VanDerPol};
use tumble::integrate::{solve, Method, OdeSystem, SaveAt, Settings};

fn lotka_volterra(c: &mut Criterion) {
    let p = problems::by_name("lotka-volterra").unwrap();
    let settings = Settings::tolerances(Method::Dopri5, 1e-8, 1e-8);
    let mut lv = LotkaVolterra {
        p: [1.5, 1.0, 3.0, 1.0],
    };
    let steps = solve(&mut lv, &settings, 0.0, &p.y0, p.t_end, &SaveAt::End)
        .unwrap()
        .report
        .steps;
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
        b.iter(|| {
            solve(
                &mut lv,
                black_box(&settings),
                0.0,
                &p.y0,
                p.t_end,
                &SaveAt::End,
            )
            .unwrap()
        })
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
        (
            "dopri5 1e-8",
            Settings::tolerances(Method::Dopri5, 1e-8, 1e-8),
        ),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| solve(&mut Kepler, &settings, 0.0, &p.y0, p.t_end, &SaveAt::End).unwrap())
        });
    }
    g.finish();
}

fn stiff(c: &mut Criterion) {
    let mut g = c.benchmark_group("stiff");
    let rober = Rober::problem();
    let s = Settings::tolerances(Method::Rodas4, 1e-6, 1e-14);
    g.bench_function("rober/rodas4 1e-6", |b| {
        b.iter(|| solve(&mut Rober, &s, 0.0, &rober.y0, rober.t_end, &SaveAt::End).unwrap())
    });
    let vdp = VanDerPol::problem();
    let s = Settings::tolerances(Method::Rodas4, 1e-6, 1e-6);
    g.bench_function("van-der-pol/rodas4 1e-6", |b| {
        b.iter(|| {
            solve(
                &mut VanDerPol { eps: 1e-6 },
                &s,
                0.0,
                &vdp.y0,
                vdp.t_end,
                &SaveAt::End,
            )
            .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, lotka_volterra, kepler, stiff);
criterion_main!(benches);

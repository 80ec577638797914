//! Solve time against contact count: the frictionless resting-contact QP and the frictional cone program of one
//! time step, on pyramids of boxes (one island each; every box above the bottom row rests on two).
//!
//! Run: `cargo bench -p tumble-contact --bench contact_solve`. The contact counts (16, 100, 1,024) and clarabel's
//! iteration counts are printed before the measurements; time per contact = time / contacts.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nalgebra::{Matrix3, Point3, Vector3};
use std::hint::black_box;
use tumble_contact::{
    resting_forces, velocity_step, BodyState, Contact, SolverSettings, StepSettings, VelocityProblem,
};

/// A 2D pyramid of boxes (half extents 0.5, 0.5, 0.25) with `base` boxes in the bottom row, on a static ground.
/// Contacts sit at the corners of each overlap rectangle: four under a bottom box, eight under any other (four on
/// each of the two boxes it rests on).
fn pyramid(base: usize, mu: f64) -> (Vec<BodyState>, Vec<Contact>) {
    let (hx, hy, hz, m) = (0.5, 0.5, 0.25, 1.0);
    let inertia =
        Matrix3::from_diagonal(&Vector3::new(hy * hy + hz * hz, hx * hx + hz * hz, hx * hx + hy * hy)) * (m / 3.0);
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let mut contacts = Vec::new();
    let mut rows: Vec<Vec<usize>> = Vec::new();
    for row in 0..base {
        let mut this_row = Vec::new();
        for k in 0..base - row {
            let x = 2.0 * hx * k as f64 + hx * row as f64;
            let z = hz + 2.0 * hz * row as f64;
            bodies.push(BodyState {
                force: Vector3::new(0.0, 0.0, -9.81 * m),
                ..BodyState::rigid(m, inertia, Point3::new(x, 0.0, z))
            });
            let me = bodies.len() - 1;
            this_row.push(me);
            // (supporting body, overlap from x0 to x1)
            let supports = if row == 0 {
                vec![(0, x - hx, x + hx)]
            } else {
                vec![(rows[row - 1][k], x - hx, x), (rows[row - 1][k + 1], x, x + hx)]
            };
            for (below, x0, x1) in supports {
                for (px, py) in [(x0, -hy), (x1, -hy), (x1, hy), (x0, hy)] {
                    contacts.push(
                        Contact::new(below, me, Point3::new(px, py, z - hz), Vector3::z_axis()).with_friction(mu),
                    );
                }
            }
        }
        rows.push(this_row);
    }
    (bodies, contacts)
}

fn solve_times(c: &mut Criterion) {
    let mut g = c.benchmark_group("contact_solve");
    g.sample_size(20);
    for base in [2, 5, 16] {
        let (bodies, frictionless) = pyramid(base, 0.0);
        let (_, frictional) = pyramid(base, 0.5);
        let n = frictionless.len();
        let qp = resting_forces(&bodies, &frictionless, &SolverSettings::default()).unwrap();
        let step = velocity_step(&VelocityProblem::new(&bodies, &frictional), &StepSettings::new(1.0 / 60.0)).unwrap();
        println!(
            "{n} contacts ({} boxes): QP {} iterations, cone program {} iterations",
            bodies.len() - 1,
            qp.iterations,
            step.iterations
        );
        g.bench_with_input(BenchmarkId::new("resting_qp", n), &n, |b, _| {
            b.iter(|| black_box(resting_forces(&bodies, &frictionless, &SolverSettings::default()).unwrap()))
        });
        g.bench_with_input(BenchmarkId::new("friction_cone", n), &n, |b, _| {
            b.iter(|| {
                black_box(
                    velocity_step(&VelocityProblem::new(&bodies, &frictional), &StepSettings::new(1.0 / 60.0)).unwrap(),
                )
            })
        });
    }
    g.finish();
}

criterion_group!(benches, solve_times);
criterion_main!(benches);

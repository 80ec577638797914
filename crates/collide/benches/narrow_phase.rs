//! Narrow-phase costs: the separating-plane test on a moving pair with and without the per-pair cache, and the three
//! collision-time methods on the same impacts.
//!
//! Run: `cargo bench -p tumble-collide --bench narrow_phase`. The moving pair: a 20-point convex hull circling a box
//! 2.5 apart and turning slowly, 200 poses, one test per pose (speed-up = uncached / cached time). Collision time:
//! a box tipping onto a plane, two approaching spheres, and a 1000 m/s sphere against a 1 cm wall, to 1e-10 s.

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use std::hint::black_box;
use tumble_collide::{
    separating_plane, time_of_impact, Motion, Polyhedron, SeparatingPlaneCache, Shape, ToiMethod, ToiOptions,
};

fn hull_points() -> Vec<Point3<f64>> {
    // 20 points on a squashed sphere (golden-angle spiral): a rounded hull with many faces and edges.
    (0..20)
        .map(|k| {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / 20.0;
            let r = (1.0 - z * z).sqrt();
            let phi = k as f64 * 2.399_963_229_728_653;
            Point3::new(0.6 * r * phi.cos(), 0.4 * r * phi.sin(), 0.5 * z)
        })
        .collect()
}

fn separating_planes(c: &mut Criterion) {
    let a = Polyhedron::from_shape(&Shape::convex_hull(&hull_points()).unwrap()).unwrap();
    let b = Polyhedron::from_shape(&Shape::cuboid(Vector3::new(0.3, 0.2, 0.4)).unwrap()).unwrap();
    let pa = Isometry3::identity();
    let poses: Vec<Isometry3<f64>> = (0..200)
        .map(|k| {
            let t = k as f64 * 0.002;
            Isometry3::from_parts(
                Translation3::new(2.5 * t.cos(), 2.5 * t.sin(), 0.1),
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.5 * t),
            )
        })
        .collect();
    let mut g = c.benchmark_group("separating_plane");
    g.bench_function("search every time", |bench| {
        bench.iter(|| poses.iter().filter(|pb| separating_plane(&a, &pa, &b, pb).is_some()).count())
    });
    g.bench_function("cached per pair", |bench| {
        let mut cache = SeparatingPlaneCache::new();
        bench.iter(|| poses.iter().filter(|pb| cache.test((0, 1), &a, &pa, &b, pb).is_some()).count())
    });
    g.finish();
}

fn collision_time(c: &mut Criterion) {
    let cuboid = Shape::cuboid(Vector3::new(0.6, 0.5, 0.2)).unwrap();
    let slab = Shape::cuboid(Vector3::new(10.0, 10.0, 1.0)).unwrap();
    let spin =
        Motion::new(Isometry3::translation(0.0, 0.0, 0.5), Vector3::zeros(), Vector3::new(0.0, 2.0, 0.0)).unwrap();
    let floor = Motion::stationary(Isometry3::translation(0.0, 0.0, -1.0));
    let (s1, s2) = (Shape::sphere(0.2).unwrap(), Shape::sphere(0.3).unwrap());
    let m1 = Motion::new(Isometry3::identity(), Vector3::new(1.5, 0.0, 0.0), Vector3::zeros()).unwrap();
    let m2 =
        Motion::new(Isometry3::translation(2.0, 0.0, 0.0), Vector3::new(-0.5, 0.0, 0.0), Vector3::zeros()).unwrap();
    let bullet = Shape::sphere(0.05).unwrap();
    let wall = Shape::cuboid(Vector3::new(0.005, 1.0, 1.0)).unwrap();
    let fly =
        Motion::new(Isometry3::translation(-1.0, 0.0, 0.0), Vector3::new(1000.0, 0.0, 0.0), Vector3::zeros()).unwrap();
    let stand = Motion::stationary(Isometry3::translation(5.0, 0.0, 0.0));
    let cases = [
        ("box tipping onto a slab", &cuboid, &spin, &slab, &floor, 1.0),
        ("two spheres", &s1, &m1, &s2, &m2, 1.0),
        ("sphere at 1000 m/s into a 1 cm wall", &bullet, &fly, &wall, &stand, 1.0 / 60.0),
    ];
    let mut g = c.benchmark_group("collision_time");
    for (name, a, ma, b, mb, t_end) in cases {
        for method in [ToiMethod::Bisection, ToiMethod::ConservativeAdvancement, ToiMethod::ShapeCast] {
            let options = ToiOptions { method, tolerance: 1e-10, max_iterations: 10_000 };
            let hit = time_of_impact(a, ma, b, mb, t_end, &options).unwrap().unwrap();
            println!("{name} / {method:?}: t = {:.12}, {} queries", hit.time, hit.iterations);
            g.bench_function(format!("{name}/{method:?}"), |bench| {
                bench.iter(|| black_box(time_of_impact(a, ma, b, mb, t_end, &options).unwrap()))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, separating_planes, collision_time);
criterion_main!(benches);

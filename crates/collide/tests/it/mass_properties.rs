//! Mass properties against closed forms, and every invalid shape refused with the argument's name.

use nalgebra::{Matrix3, Point3, Vector3};
use std::f64::consts::PI;
use tumble_collide::Shape;

/// Relative agreement; primitives and polyhedra are integrated exactly, so only round-off separates them (1e-12).
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-300)
}

fn diag_close(m: &Matrix3<f64>, d: [f64; 3]) {
    for i in 0..3 {
        for j in 0..3 {
            let expected = if i == j { d[i] } else { 0.0 };
            assert!((m[(i, j)] - expected).abs() <= 1e-12 * d.iter().cloned().fold(0.0, f64::max), "{m} vs {d:?}");
        }
    }
}

#[test]
fn sphere_is_two_fifths_m_r_squared() {
    let (r, rho) = (0.7, 1300.0);
    let p = Shape::sphere(r).unwrap().mass_properties(rho).unwrap();
    let m = rho * 4.0 / 3.0 * PI * r.powi(3);
    assert!(close(p.mass, m));
    diag_close(&p.inertia, [0.4 * m * r * r; 3]);
    assert_eq!(p.local_com, Vector3::zeros());
}

#[test]
fn box_is_m_b2_plus_c2_over_12() {
    let (a, b, c, rho) = (0.5, 0.25, 1.5, 800.0);
    let p = Shape::cuboid(Vector3::new(a, b, c)).unwrap().mass_properties(rho).unwrap();
    let m = rho * 8.0 * a * b * c;
    let (x, y, z) = (2.0 * a, 2.0 * b, 2.0 * c);
    assert!(close(p.mass, m));
    diag_close(&p.inertia, [m * (y * y + z * z) / 12.0, m * (x * x + z * z) / 12.0, m * (x * x + y * y) / 12.0]);
}

#[test]
fn cylinder_along_z() {
    let (h, r, rho) = (0.6, 0.2, 1000.0);
    let p = Shape::cylinder(h, r).unwrap().mass_properties(rho).unwrap();
    let m = rho * PI * r * r * 2.0 * h;
    let side = m * (3.0 * r * r + 4.0 * h * h) / 12.0;
    assert!(close(p.mass, m));
    diag_close(&p.inertia, [side, side, 0.5 * m * r * r]);
}

/// A capsule along z: a cylinder of height H = 2 half_height plus two hemispheres of total mass m_s, whose
/// inertia about the centre is m_s (2 r^2 / 5 + H^2 / 4 + 3 H r / 8) across and m_s 2 r^2 / 5 along.
#[test]
fn capsule_along_z() {
    let (h, r, rho) = (0.5, 0.3, 1000.0);
    let p = Shape::capsule(h, r).unwrap().mass_properties(rho).unwrap();
    let hh = 2.0 * h;
    let (mc, ms) = (rho * PI * r * r * hh, rho * 4.0 / 3.0 * PI * r.powi(3));
    let across = mc * (hh * hh / 12.0 + r * r / 4.0) + ms * (0.4 * r * r + hh * hh / 4.0 + 3.0 * hh * r / 8.0);
    let along = mc * r * r / 2.0 + ms * 0.4 * r * r;
    assert!(close(p.mass, mc + ms));
    diag_close(&p.inertia, [across, across, along]);
}

/// The hull of a box's corners has the box's mass properties; a hull away from the origin reports its centre.
#[test]
fn convex_hull_of_box_corners_is_the_box() {
    let (a, b, c) = (0.3, 0.4, 0.5);
    let shift = Vector3::new(2.0, -1.0, 0.5);
    let corners: Vec<Point3<f64>> = (0..8)
        .map(|k| {
            let s = |bit: usize| if k & (1 << bit) != 0 { 1.0 } else { -1.0 };
            Point3::new(s(0) * a, s(1) * b, s(2) * c) + shift
        })
        .collect();
    let hull = Shape::convex_hull(&corners).unwrap().mass_properties(500.0).unwrap();
    let cube = Shape::cuboid(Vector3::new(a, b, c)).unwrap().mass_properties(500.0).unwrap();
    assert!(close(hull.mass, cube.mass));
    assert!((hull.local_com - shift).norm() < 1e-12);
    assert!((hull.inertia - cube.inertia).norm() < 1e-12 * cube.inertia.norm());
}

fn name_of(e: tumble_collide::ShapeError) -> &'static str {
    e.name
}

#[test]
fn degenerate_shapes_are_refused_by_name() {
    assert_eq!(name_of(Shape::sphere(0.0).unwrap_err()), "radius");
    assert_eq!(name_of(Shape::sphere(-1.0).unwrap_err()), "radius");
    assert_eq!(name_of(Shape::sphere(f64::NAN).unwrap_err()), "radius");
    assert_eq!(name_of(Shape::cuboid(Vector3::new(1.0, 0.0, 1.0)).unwrap_err()), "half_extents");
    assert_eq!(name_of(Shape::cuboid(Vector3::new(1.0, 1.0, f64::INFINITY)).unwrap_err()), "half_extents");
    assert_eq!(name_of(Shape::capsule(0.0, 1.0).unwrap_err()), "half_height");
    assert_eq!(name_of(Shape::cylinder(1.0, -2.0).unwrap_err()), "radius");
    let square = [
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(1.0, 1.0, 0.0),
    ];
    assert_eq!(name_of(Shape::convex_hull(&square).unwrap_err()), "points");
    assert_eq!(name_of(Shape::convex_hull(&square[..3]).unwrap_err()), "points");
    let line: Vec<_> = (0..6).map(|k| Point3::new(k as f64, 0.0, 0.0)).collect();
    assert_eq!(name_of(Shape::convex_hull(&line).unwrap_err()), "points");
    let mut bad = square.to_vec();
    bad.push(Point3::new(0.0, 0.0, f64::NAN));
    assert_eq!(name_of(Shape::convex_hull(&bad).unwrap_err()), "points");
    assert_eq!(name_of(Shape::trimesh(&square, &[[0, 1, 9]]).unwrap_err()), "triangles");
    assert_eq!(name_of(Shape::trimesh(&square, &[]).unwrap_err()), "triangles");
    assert_eq!(name_of(Shape::half_space(Vector3::zeros()).unwrap_err()), "normal");
    let ground = Shape::half_space(Vector3::z()).unwrap();
    assert_eq!(name_of(ground.mass_properties(1.0).unwrap_err()), "shape");
    let mesh = Shape::trimesh(&square, &[[0, 1, 2], [1, 3, 2]]).unwrap();
    assert_eq!(name_of(mesh.mass_properties(1.0).unwrap_err()), "shape");
    assert_eq!(name_of(Shape::sphere(1.0).unwrap().mass_properties(0.0).unwrap_err()), "density");
}

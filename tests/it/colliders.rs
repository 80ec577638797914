//! Colliders and materials: compound mass properties against the parallel-axis theorem, the combine rule of two
//! materials, and a body whose second collider is the one that lands.

use nalgebra::{Isometry3, Matrix3, Vector3};
use std::f64::consts::PI;
use tumble::{Material, RigidBodyBuilder, Shape, World};

#[test]
fn two_balls_make_a_dumbbell_with_the_parallel_axis_inertia() {
    // Two balls of radius r, density rho, centres 2a apart along x: mass 2 m, centre of mass halfway, inertia
    // about it 2 (2/5 m r^2) about x and 2 (2/5 m r^2 + m a^2) about y and z.
    let (r, rho, a) = (0.2, 1000.0, 0.5);
    let m = 4.0 / 3.0 * PI * r * r * r * rho;
    let mut w = World::new();
    let ball = Shape::sphere(r).unwrap();
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(ball.clone(), rho).collider(ball, Isometry3::translation(2.0 * a, 0.0, 0.0)),
        )
        .unwrap();
    let body = w.body(b).unwrap();
    // 1e-12 relative: parry's ball mass properties are closed forms too.
    assert!((body.mass() - 2.0 * m).abs() < 1e-12 * m);
    let i0 = 0.4 * m * r * r;
    let want = Matrix3::from_diagonal(&Vector3::new(2.0 * i0, 2.0 * (i0 + m * a * a), 2.0 * (i0 + m * a * a)));
    assert!((body.inertia() - want).norm() < 1e-12 * want.norm(), "{}", body.inertia());
    let offsets: Vec<f64> = body.colliders().iter().map(|c| c.offset.translation.vector.x).collect();
    assert!((offsets[0] + a).abs() < 1e-15 && (offsets[1] - a).abs() < 1e-15, "{offsets:?}");
}

#[test]
fn materials_combine_to_the_larger_restitution_and_the_geometric_mean_friction() {
    let a = Material::new(0.8, 0.9);
    let b = Material::new(0.2, 0.1);
    let c = a.combine(&b, &Default::default());
    assert_eq!(c.restitution, 0.8);
    assert!((c.friction - 0.3).abs() < 1e-15);
    assert_eq!(a.combine(&Material::new(0.0, 0.0), &Default::default()).friction, 0.0);
    assert_eq!(a.combine(&b, &Default::default()), b.combine(&a, &Default::default()));
}

#[test]
fn the_offset_collider_is_the_one_that_lands() {
    // A dumbbell dropped upright, its second ball given as an extra collider 1 m below the first: in fast mode the
    // lower ball lands and the body comes to rest on it.
    let mut w = World::new();
    w.set_mode(tumble::Mode::fast(1.0 / 240.0)).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.8)).unwrap();
    let ball = Shape::sphere(0.1).unwrap();
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(ball.clone(), 1000.0)
                .collider(ball, Isometry3::translation(0.0, 0.0, -1.0))
                .position(Vector3::new(0.0, 0.0, 2.0))
                .restitution(0.0)
                .friction(0.8),
        )
        .unwrap();
    w.run(3.0, 0.5).unwrap();
    let body = w.body(b).unwrap();
    let lowest =
        body.colliders().iter().map(|c| (body.pose() * c.offset).translation.vector.z).fold(f64::MAX, f64::min);
    // the lower ball rests on the ground (centre at its radius, to fast mode's 1e-4 m), the body is still
    assert!((lowest - 0.1).abs() < 1e-4, "lowest collider centre at {lowest}");
}

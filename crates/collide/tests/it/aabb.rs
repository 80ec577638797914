//! World and swept bounding boxes against closed forms, and swept boxes holding every sampled point of a motion.

use crate::common;

use common::Rng;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::FRAC_PI_4;
use tumble_collide::{Aabb, Motion, Shape};

fn assert_box(b: &Aabb, min: [f64; 3], max: [f64; 3]) {
    // Rounding of a rotation by pi/4: a few ulps of the extents.
    for k in 0..3 {
        assert!((b.min[k] - min[k]).abs() < 1e-12, "min[{k}] = {} vs {}", b.min[k], min[k]);
        assert!((b.max[k] - max[k]).abs() < 1e-12, "max[{k}] = {} vs {}", b.max[k], max[k]);
    }
}

#[test]
fn boxes_of_posed_shapes_match_closed_forms() {
    let at = |x: f64, y: f64, z: f64| Isometry3::translation(x, y, z);
    let sphere = Shape::sphere(0.5).unwrap();
    assert_box(&sphere.aabb(&at(1.0, 2.0, 3.0)).unwrap(), [0.5, 1.5, 2.5], [1.5, 2.5, 3.5]);
    // A 2a x 2b box turned 45 degrees about z spans (a + b) / sqrt 2 either side in x and y.
    let cuboid = Shape::cuboid(Vector3::new(1.0, 0.5, 0.25)).unwrap();
    let turned =
        Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_axis_angle(&Vector3::z_axis(), FRAC_PI_4));
    let w = 1.5 / 2f64.sqrt();
    assert_box(&cuboid.aabb(&turned).unwrap(), [-w, -w, -0.25], [w, w, 0.25]);
    // Cylinders and capsules run along the body's z axis.
    let cylinder = Shape::cylinder(2.0, 0.5).unwrap();
    assert_box(&cylinder.aabb(&at(0.0, 0.0, 0.0)).unwrap(), [-0.5, -0.5, -2.0], [0.5, 0.5, 2.0]);
    let capsule = Shape::capsule(2.0, 0.5).unwrap();
    assert_box(&capsule.aabb(&at(0.0, 0.0, 0.0)).unwrap(), [-0.5, -0.5, -2.5], [0.5, 0.5, 2.5]);
    // A ground with normal +z at height 1 is bounded above only.
    let ground = Shape::half_space(Vector3::z()).unwrap().aabb(&at(5.0, 5.0, 1.0)).unwrap();
    assert_eq!(ground.max.z, 1.0);
    assert!(ground.min.z == f64::NEG_INFINITY && ground.max.x == f64::INFINITY && ground.min.x == f64::NEG_INFINITY);
}

#[test]
fn swept_box_holds_every_point_of_the_motion() {
    let mut rng = Rng(7);
    let shapes = [
        Shape::cuboid(Vector3::new(1.0, 0.1, 0.3)).unwrap(),
        Shape::cylinder(1.0, 0.2).unwrap(),
        Shape::capsule(0.7, 0.1).unwrap(),
        rng.polyhedral_shape(),
    ];
    for shape in &shapes {
        let (vertices, _) = shape.triangle_mesh(24, 1.0);
        for _ in 0..200 {
            let start = rng.pose(2.0);
            let end =
                Isometry3::from_parts(Translation3::from(start.translation.vector + rng.vector(3.0)), rng.rotation());
            let swept = shape.swept_aabb(&start, &end).unwrap();
            let motion = Motion::between(&start, &end, 1.0).unwrap();
            for k in 0..=64 {
                let pose = motion.pose_at(k as f64 / 64.0);
                for v in &vertices {
                    let p = pose * v;
                    // 1e-12: rounding of the pose composition at coordinates of a few units.
                    assert!(
                        swept.loosened(1e-12).contains(&p),
                        "{} escapes its swept box: {p:?} vs {swept:?}",
                        shape.kind()
                    );
                }
            }
            // and the sweep ends where the motion ends
            let e = motion.pose_at(1.0);
            assert!((e.translation.vector - end.translation.vector).norm() < 1e-12);
            assert!(e.rotation.angle_to(&end.rotation) < 1e-12);
        }
    }
}

#[test]
fn swept_box_of_a_pure_translation_is_the_union_of_the_end_boxes() {
    let shape = Shape::cuboid(Vector3::new(0.5, 0.5, 0.5)).unwrap();
    let b = shape.swept_aabb(&Isometry3::translation(0.0, 0.0, 0.0), &Isometry3::translation(3.0, 0.0, -1.0)).unwrap();
    assert_box(&b, [-0.5, -0.5, -1.5], [3.5, 0.5, 0.5]);
}

#[test]
fn bad_boxes_and_poses_are_refused() {
    let p = Point3::new(0.0, 0.0, 0.0);
    assert_eq!(Aabb::new(Point3::new(1.0, 0.0, 0.0), p).unwrap_err().name, "aabb");
    assert_eq!(Aabb::new(p, Point3::new(f64::NAN, 0.0, 0.0)).unwrap_err().name, "aabb");
    let sphere = Shape::sphere(1.0).unwrap();
    let bad = Isometry3::translation(f64::NAN, 0.0, 0.0);
    assert_eq!(sphere.aabb(&bad).unwrap_err().name, "pose");
    assert_eq!(sphere.swept_aabb(&Isometry3::identity(), &bad).unwrap_err().name, "end");
    assert_eq!(Motion::between(&Isometry3::identity(), &Isometry3::identity(), 0.0).unwrap_err().name, "dt");
    assert_eq!(
        Motion::new(Isometry3::identity(), Vector3::new(f64::INFINITY, 0.0, 0.0), Vector3::zeros()).unwrap_err().name,
        "linvel"
    );
}

//! Contact points, normals, distances and kinds against closed forms: sphere on a plane, a box flat on a plane and on
//! a box (four points each), box edge across box edge, a sphere on a box corner and in the corner of a room.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::FRAC_PI_4;
use tumble_collide::{contacts, ContactKind, Feature, Shape, ShapeContact};

// Contact points come from parry's clipping and GJK/EPA on shapes of unit size: 1e-9 covers their tolerances.
const TOL: f64 = 1e-9;

fn near(p: &Point3<f64>, q: &Point3<f64>) -> bool {
    (p - q).norm() < TOL
}

fn find<'a>(cs: &'a [ShapeContact], point_a: &Point3<f64>) -> &'a ShapeContact {
    cs.iter().find(|c| near(&c.point_a, point_a)).unwrap_or_else(|| panic!("no contact at {point_a:?} in {cs:#?}"))
}

#[test]
fn sphere_on_a_plane_touches_at_its_lowest_point() {
    let (r, h) = (0.3, 0.29);
    let sphere = Shape::sphere(r).unwrap();
    let ground = Shape::half_space(Vector3::z()).unwrap();
    let cs = contacts(&sphere, &Isometry3::translation(1.0, -2.0, h), &ground, &Isometry3::identity(), 0.0).unwrap();
    assert_eq!(cs.len(), 1);
    let c = &cs[0];
    assert!(
        near(&c.point_a, &Point3::new(1.0, -2.0, h - r)) && near(&c.point_b, &Point3::new(1.0, -2.0, 0.0)),
        "{c:?}"
    );
    assert!((c.normal.into_inner() - -Vector3::z()).norm() < TOL);
    assert!((c.distance - (h - r)).abs() < TOL);
    assert_eq!((c.kind, c.feature_a), (ContactKind::VertexFace, Feature::Curved));
    // Lifted by 5 mm: a contact only within the prediction distance, with a positive distance.
    let lifted = Isometry3::translation(1.0, -2.0, r + 0.005);
    assert!(contacts(&sphere, &lifted, &ground, &Isometry3::identity(), 0.001).unwrap().is_empty());
    let cs = contacts(&sphere, &lifted, &ground, &Isometry3::identity(), 0.01).unwrap();
    assert!(cs.len() == 1 && (cs[0].distance - 0.005).abs() < TOL, "{cs:?}");
}

#[test]
fn box_resting_flat_has_four_vertex_face_contacts_at_its_corners() {
    let (a, b, c, depth, yaw) = (0.5, 0.3, 0.2, 1e-3, 0.7);
    let cuboid = Shape::cuboid(Vector3::new(a, b, c)).unwrap();
    let turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw);
    let pose = Isometry3::from_parts(Translation3::new(0.4, 0.1, c - depth), turn);
    let ground = Shape::half_space(Vector3::z()).unwrap();
    // on a ground plane, and on a bigger box whose top face is at z = 0
    let slab = Shape::cuboid(Vector3::new(3.0, 3.0, 0.5)).unwrap();
    // the same box as a convex hull of its corners (parry's general polyhedron path)
    let corners: Vec<Point3<f64>> = (0..8)
        .map(|k| {
            Point3::new(
                if k & 1 == 0 { -a } else { a },
                if k & 2 == 0 { -b } else { b },
                if k & 4 == 0 { -c } else { c },
            )
        })
        .collect();
    let hull = Shape::convex_hull(&corners).unwrap();
    let under = [(&ground, Isometry3::identity()), (&slab, Isometry3::translation(0.0, 0.0, -0.5))];
    for (body, (other, at)) in [&cuboid, &hull].into_iter().flat_map(|s| under.iter().map(move |u| (s, u))) {
        let cs = contacts(body, &pose, other, at, 0.0).unwrap();
        assert_eq!(cs.len(), 4, "{cs:#?}");
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let corner = pose * Point3::new(sx * a, sy * b, -c);
            let k = find(&cs, &corner);
            assert!((k.distance + depth).abs() < TOL && (k.normal.z + 1.0).abs() < TOL, "{k:?}");
            assert!(near(&k.point_b, &Point3::new(corner.x, corner.y, 0.0)));
            assert_eq!(k.kind, ContactKind::VertexFace);
            assert!(matches!(k.feature_a, Feature::Vertex(_)), "{k:?}");
        }
    }
}

#[test]
fn equal_boxes_stacked_report_each_shared_corner_once() {
    let cube = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    let cs =
        contacts(&cube, &Isometry3::translation(0.0, 0.0, 1.0 - 1e-3), &cube, &Isometry3::identity(), 0.0).unwrap();
    assert_eq!(cs.len(), 4, "{cs:#?}");
    for c in &cs {
        assert!((c.distance + 1e-3).abs() < TOL && (c.normal.z + 1.0).abs() < TOL);
        assert!((c.point_a.x.abs() - 0.5).abs() < TOL && (c.point_a.y.abs() - 0.5).abs() < TOL);
    }
}

#[test]
fn crossed_box_edges_meet_in_one_edge_edge_contact() {
    // Cube A turned 45 degrees about x (top edge along x at height h), cube B turned 45 degrees about y (bottom edge
    // along y), B lowered so the edges cross 1e-3 deep at the z axis.
    let h = 0.5 * 2f64.sqrt();
    let cube = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    let pa =
        Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_axis_angle(&Vector3::x_axis(), FRAC_PI_4));
    let pb = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 2.0 * h - 1e-3),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_4),
    );
    let cs = contacts(&cube, &pa, &cube, &pb, 0.0).unwrap();
    assert_eq!(cs.len(), 1, "{cs:#?}");
    let c = &cs[0];
    assert_eq!(c.kind, ContactKind::EdgeEdge);
    assert!(near(&c.point_a, &Point3::new(0.0, 0.0, h)) && near(&c.point_b, &Point3::new(0.0, 0.0, h - 1e-3)), "{c:?}");
    assert!((c.normal.z - 1.0).abs() < TOL && (c.distance + 1e-3).abs() < TOL);
}

#[test]
fn sphere_on_a_box_corner_touches_along_the_diagonal() {
    // A box corner at (0.5, 0.5, 0.5) pressing 1e-3 into a sphere whose centre lies on the corner's diagonal.
    let (r, depth) = (0.3, 1e-3);
    let d = Vector3::repeat(1.0).normalize();
    let corner = Point3::new(0.5, 0.5, 0.5);
    let centre = corner + d * (r - depth);
    let cube = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    let sphere = Shape::sphere(r).unwrap();
    let cs =
        contacts(&cube, &Isometry3::identity(), &sphere, &Isometry3::translation(centre.x, centre.y, centre.z), 0.0)
            .unwrap();
    assert_eq!(cs.len(), 1, "{cs:#?}");
    let c = &cs[0];
    assert!(near(&c.point_a, &corner) && near(&c.point_b, &(centre - d * r)), "{c:?}");
    assert!((c.normal.into_inner() - d).norm() < TOL && (c.distance + depth).abs() < TOL);
    assert_eq!((c.kind, c.feature_b), (ContactKind::VertexFace, Feature::Curved));
    assert!(matches!(c.feature_a, Feature::Vertex(_)));
}

#[test]
fn sphere_in_the_corner_of_a_room_touches_floor_and_both_walls() {
    // Floor and two walls are boxes meeting at the origin; the sphere sits 1e-3 into each.
    let (r, depth) = (0.25, 1e-3);
    let s = r - depth;
    let sphere = Shape::sphere(r).unwrap();
    let slab = Shape::cuboid(Vector3::new(2.0, 2.0, 0.1)).unwrap();
    let floor = Isometry3::translation(2.0, 2.0, -0.1);
    let wall_x = Isometry3::from_parts(
        Translation3::new(-0.1, 2.0, 2.0),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
    );
    let wall_y = Isometry3::from_parts(
        Translation3::new(2.0, -0.1, 2.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2),
    );
    let at = Isometry3::translation(s, s, s);
    for (wall, axis) in [(floor, 2), (wall_x, 0), (wall_y, 1)] {
        let cs = contacts(&sphere, &at, &slab, &wall, 0.0).unwrap();
        assert_eq!(cs.len(), 1, "{cs:#?}");
        let c = &cs[0];
        let mut expected = Point3::new(s, s, s);
        expected[axis] = s - r;
        assert!(near(&c.point_a, &expected), "{c:?}");
        assert!((c.normal[axis] + 1.0).abs() < TOL && (c.distance + depth).abs() < TOL, "{c:?}");
    }
}

#[test]
fn capsule_lying_on_a_plane_touches_at_both_ends_of_its_segment() {
    let (hh, r, depth) = (0.5, 0.2, 1e-3);
    let capsule = Shape::capsule(hh, r).unwrap();
    let lying = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, r - depth),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
    );
    let ground = Shape::half_space(Vector3::z()).unwrap();
    let cs = contacts(&capsule, &lying, &ground, &Isometry3::identity(), 0.0).unwrap();
    assert_eq!(cs.len(), 2, "{cs:#?}");
    for x in [-hh, hh] {
        let c = find(&cs, &Point3::new(x, 0.0, -depth));
        assert!((c.distance + depth).abs() < TOL && c.kind == ContactKind::VertexFace);
    }
}

#[test]
fn bad_contact_queries_are_refused_by_name() {
    let ground = Shape::half_space(Vector3::z()).unwrap();
    let sphere = Shape::sphere(1.0).unwrap();
    let i = Isometry3::identity();
    assert_eq!(contacts(&ground, &i, &ground, &i, 0.0).unwrap_err().name, "shape");
    assert_eq!(contacts(&sphere, &i, &ground, &i, -1.0).unwrap_err().name, "prediction");
    assert_eq!(contacts(&sphere, &i, &ground, &i, f64::NAN).unwrap_err().name, "prediction");
    assert_eq!(
        contacts(&sphere, &Isometry3::translation(f64::INFINITY, 0.0, 0.0), &ground, &i, 0.0).unwrap_err().name,
        "pose_a"
    );
}

//! The separating-plane test against parry's intersection test on random convex pairs, the planes it returns checked
//! against the vertices, and the per-pair cache reused while a moving pair stays apart.

use crate::common;

use common::Rng;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use tumble_collide::{distance, intersects, separating_plane, PlaneSource, Polyhedron, SeparatingPlaneCache, Shape};

/// Whether the plane puts every vertex of A below it and every vertex of B above, by at least half its gap.
fn plane_separates(
    p: &tumble_collide::SeparatingPlane,
    a: &Polyhedron,
    pa: &Isometry3<f64>,
    b: &Polyhedron,
    pb: &Isometry3<f64>,
) -> bool {
    let n = p.normal.into_inner();
    // 1e-12: rounding of the vertex transforms at coordinates of a few units.
    let top_a = a.vertices().iter().map(|v| n.dot(&(pa * nalgebra::Point3::from(*v)).coords)).fold(f64::MIN, f64::max);
    let bottom_b =
        b.vertices().iter().map(|v| n.dot(&(pb * nalgebra::Point3::from(*v)).coords)).fold(f64::MAX, f64::min);
    top_a <= p.offset - 0.5 * p.gap + 1e-12 && bottom_b >= p.offset + 0.5 * p.gap - 1e-12
}

#[test]
fn agrees_with_parry_on_ten_thousand_random_convex_pairs() {
    let mut rng = Rng(11);
    let (mut agreed, mut borderline, mut separated, mut by_edges) = (0, 0, 0, 0);
    for pair in 0..12_000 {
        let (sa, sb) = (rng.polyhedral_shape(), rng.polyhedral_shape());
        let (pa, pb) = (rng.pose(0.2), rng.pose(0.8));
        let (a, b) = (Polyhedron::from_shape(&sa).unwrap(), Polyhedron::from_shape(&sb).unwrap());
        let ours = separating_plane(&a, &pa, &b, &pb);
        let parry_touching = intersects(&sa, &pa, &sb, &pb).unwrap();
        if let Some(p) = &ours {
            separated += 1;
            by_edges += matches!(p.source, PlaneSource::EdgePair { .. }) as usize;
            assert!(plane_separates(p, &a, &pa, &b, &pb), "pair {pair}: the plane does not separate");
            let d = distance(&sa, &pa, &sb, &pb).unwrap();
            // The slab between the bodies is never wider than their distance (1e-9: parry's GJK tolerance).
            assert!(p.gap <= d + 1e-9, "pair {pair}: gap {} exceeds distance {d}", p.gap);
        }
        if ours.is_none() == parry_touching {
            agreed += 1;
        } else {
            // Only a pair within 1e-9 of touching may be called either way.
            let d = distance(&sa, &pa, &sb, &pb).unwrap();
            let gap = ours.map_or(0.0, |p| p.gap);
            assert!(
                d < 1e-9 && gap < 1e-9,
                "pair {pair}: parry says touching = {parry_touching}, distance {d}, our gap {gap}"
            );
            borderline += 1;
        }
    }
    assert!(agreed >= 10_000 && borderline <= 10, "agreed {agreed}, borderline {borderline}");
    // Both outcomes and the edge-pair candidates must be well represented for the comparison to mean anything.
    assert!(separated > 3000 && 12_000 - separated > 3000, "separated {separated} of 12000");
    eprintln!("agreed {agreed}, borderline {borderline}, separated {separated}, by edge pairs {by_edges}");
    assert!(by_edges > 100, "only {by_edges} planes came from edge pairs");
}

#[test]
fn two_boxes_crossed_edge_on_edge_are_separated_only_by_an_edge_plane() {
    // Two unit cubes, one turned 45 degrees about x and one about y, stacked so that their edges cross with a gap of
    // 1e-3: no face plane separates them, only the plane through both edges.
    let h = 0.5 * 2f64.sqrt();
    let cube = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    let poly = Polyhedron::from_shape(&cube).unwrap();
    let pa = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_4),
    );
    let pb = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 2.0 * h + 1e-3),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_4),
    );
    let p = separating_plane(&poly, &pa, &poly, &pb).expect("separated by 1e-3");
    assert!(matches!(p.source, PlaneSource::EdgePair { .. }), "{:?}", p.source);
    assert!((p.normal.z - 1.0).abs() < 1e-12 && (p.gap - 1e-3).abs() < 1e-12, "{p:?}");
    let pb_touching = Isometry3::from_parts(Translation3::new(0.0, 0.0, 2.0 * h - 1e-3), pb.rotation);
    assert!(separating_plane(&poly, &pa, &poly, &pb_touching).is_none());
}

#[test]
fn cached_plane_is_reused_while_the_pair_moves_apart_and_dropped_on_contact() {
    let mut rng = Rng(12);
    let sa = rng.polyhedral_shape();
    let sb = Shape::cuboid(Vector3::new(0.3, 0.2, 0.4)).unwrap();
    let (a, b) = (Polyhedron::from_shape(&sa).unwrap(), Polyhedron::from_shape(&sb).unwrap());
    let pa = Isometry3::identity();
    let mut cache = SeparatingPlaneCache::new();
    // B circles A at a distance, turning slowly: 200 small moves.
    let steps = 200;
    for k in 0..steps {
        let t = k as f64 * 0.002;
        let pb = Isometry3::from_parts(
            Translation3::new(2.5 * t.cos(), 2.5 * t.sin(), 0.1),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.5 * t),
        );
        let cached = cache.test((0, 1), &a, &pa, &b, &pb).expect("apart");
        assert!(plane_separates(&cached, &a, &pa, &b, &pb));
        assert!(separating_plane(&a, &pa, &b, &pb).is_some());
    }
    assert_eq!(cache.hits() + cache.searches(), steps as u64);
    // Only the first test needs a search while the old plane keeps separating.
    assert!(cache.searches() <= 2, "searched {} times in {steps} small moves", cache.searches());
    // In contact: no plane, and the pair is forgotten.
    assert!(cache.test((0, 1), &a, &pa, &b, &Isometry3::identity()).is_none());
    assert!(cache.is_empty());
}

#[test]
fn curved_shapes_are_refused_by_name() {
    for s in [Shape::sphere(1.0).unwrap(), Shape::capsule(1.0, 0.5).unwrap(), Shape::cylinder(1.0, 0.5).unwrap()] {
        let e = Polyhedron::from_shape(&s).unwrap_err();
        assert_eq!(e.name, "shape");
        assert!(e.reason.contains(s.kind()), "{e}");
    }
}

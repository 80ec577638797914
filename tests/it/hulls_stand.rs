//! Convex hulls stand on their faces: upright n-gon prisms (5 to 64 sides, tall and flat) and seeded random hulls
//! put down on their largest face, on the ground, on a static box and on another resting hull, in both modes. After
//! 2 s the tilt is below 0.01 degree and the penetration within the mode's bound. (parry keeps four vertices of a
//! face; before the whole face was clipped and the four points chosen to hold the centre of mass, an octagonal
//! prism on the ground tipped over.)

use crate::common;
#[allow(unused_imports)]
use common::Lcg;
use nalgebra::{Point3, UnitQuaternion, Vector3};
use tumble::{BodyHandle, Material, Mode, RigidBodyBuilder, Shape, World};

/// The points of an upright prism of `sides` sides, radius `r`, height `h`, centred on the origin.
fn prism(sides: usize, r: f64, h: f64) -> Vec<Point3<f64>> {
    (0..sides)
        .flat_map(|k| {
            let a = std::f64::consts::TAU * k as f64 / sides as f64;
            [Point3::new(r * a.cos(), r * a.sin(), -h / 2.0), Point3::new(r * a.cos(), r * a.sin(), h / 2.0)]
        })
        .collect()
}

const MATERIAL: Material = Material::new(0.0, 0.5);

/// What the body stands on.
#[derive(Clone, Copy, Debug)]
enum Under {
    Ground,
    StaticBox,
    RestingHull,
}

/// Builds what the standing body stands on (`lower`: the points of the resting hull under it) and returns the
/// height of its top and the resting hull.
fn base(w: &mut World, under: Under, lower: &[Point3<f64>]) -> (f64, Option<BodyHandle>) {
    w.add_ground(0.0, MATERIAL).unwrap();
    match under {
        Under::Ground => (0.0, None),
        Under::StaticBox => {
            let slab = Shape::cuboid(Vector3::new(1.0, 1.0, 0.1)).unwrap();
            w.add_body(RigidBodyBuilder::fixed(Some(slab)).position(Vector3::new(0.0, 0.0, 0.1)).friction(0.5))
                .unwrap();
            (0.2, None)
        }
        Under::RestingHull => {
            // a hull resting on the ground (0.1 mm up), the standing one 0.1 mm over it
            let shape = Shape::convex_hull(lower).unwrap();
            let com = shape.mass_properties(1.0).unwrap().local_com.z;
            let (low, high) = span(lower);
            let below = w
                .add_body(
                    RigidBodyBuilder::from_shape(shape, 800.0)
                        .position(Vector3::new(0.0, 0.0, 1e-4 - low + com))
                        .friction(0.5)
                        .restitution(0.0),
                )
                .unwrap();
            (1e-4 + high - low, Some(below))
        }
    }
}

fn span(points: &[Point3<f64>]) -> (f64, f64) {
    points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p.z), hi.max(p.z)))
}

/// Stands the hull of `points` (centred on its centre of mass, its base face down, along -z) 0.1 mm over what
/// `under` gives (`lower`: the resting hull's points), runs 2 s and returns the largest turn of a dynamic body
/// (degrees), the deepest penetration, and the mode's bound.
fn stand(points: &[Point3<f64>], under: Under, fast: bool, lower: &[Point3<f64>]) -> (f64, f64, f64) {
    let mut w = World::new();
    if fast {
        w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
    }
    let (top, below) = base(&mut w, under, lower);
    let (low, _) = span(points);
    let shape = Shape::convex_hull(points).unwrap();
    let body = w
        .add_body(
            RigidBodyBuilder::from_shape(shape, 500.0)
                .position(Vector3::new(0.0, 0.0, top + 1e-4 - low))
                .friction(0.5)
                .restitution(0.0),
        )
        .unwrap();
    let run = w.run(2.0, 0.1).unwrap_or_else(|e| panic!("{under:?}: {e}"));
    let tilt = |h: BodyHandle| {
        let up = w.body(h).unwrap().orientation() * Vector3::z();
        up.z.clamp(-1.0, 1.0).acos().to_degrees()
    };
    let worst = [Some(body), below].iter().flatten().map(|&h| tilt(h)).fold(0.0, f64::max);
    let penetration = run.penetration.iter().copied().fold(w.report().max_penetration, f64::max);
    // accurate mode: the contact tolerance in force; fast mode: its goal at rest, 0.5 mm
    let bound = if fast { 5e-4 } else { w.report().contact_tolerance.expect("accurate mode reports it") };
    (worst, penetration, bound)
}

#[test]
fn upright_prisms_stand_on_the_ground_a_box_and_each_other_in_both_modes() {
    for fast in [false, true] {
        for sides in [5, 6, 8, 12, 24, 64] {
            for (r, h) in [(0.05, 0.2), (0.1, 0.02)] {
                for under in [Under::Ground, Under::StaticBox, Under::RestingHull] {
                    let p = prism(sides, r, h);
                    let (tilt, pen, bound) = stand(&p, under, fast, &p);
                    println!(
                        "measured: fast {fast}, {sides} sides, r {r}, h {h}, on {under:?}: tilt {tilt:.2e} deg, \
                         penetration {pen:.2e} m (bound {bound:.1e})"
                    );
                    assert!(tilt < 0.01, "fast {fast}, {sides} sides {r} x {h} on {under:?}: tilt {tilt} deg");
                    assert!(pen <= bound, "fast {fast}, {sides} sides on {under:?}: penetration {pen} m");
                }
            }
        }
    }
}

/// A seeded random hull (12 to 30 points in a random ellipsoid) and the outward normal of its largest face, whose
/// polygon holds the centre of mass's projection with a margin of a tenth of the face's size (else a body on it
/// tips, as it should: such hulls are drawn again).
fn random_hull(rng: &mut Lcg) -> (Vec<Point3<f64>>, Vector3<f64>) {
    loop {
        let axes = Vector3::new(rng.range(0.05, 0.2), rng.range(0.05, 0.2), rng.range(0.05, 0.2));
        let count = 12 + (rng.next() * 19.0) as usize;
        let points: Vec<Point3<f64>> = (0..count)
            .map(|_| {
                let d = Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize();
                Point3::from(d.component_mul(&axes))
            })
            .collect();
        let shape = Shape::convex_hull(&points).unwrap();
        let com = shape.mass_properties(1.0).unwrap().local_com;
        let poly = tumble_collide::Polyhedron::from_shape(&shape).unwrap();
        let faces = poly.faces().iter().map(|(n, d)| {
            let on: Vec<Vector3<f64>> =
                poly.vertices().iter().filter(|v| (n.dot(v) - d).abs() < 1e-9).copied().collect();
            (n.into_inner(), face_area(&on, n), on)
        });
        let (normal, area, on) = faces.fold((Vector3::z(), 0.0, Vec::new()), |b, f| if f.1 > b.1 { f } else { b });
        if margin(&on, &normal, &com) > 0.1 * area.sqrt() {
            // centred on the centre of mass, as the body's frame is
            return (points.iter().map(|p| p - com).collect(), normal);
        }
    }
}

/// The area of the convex polygon of `points` on the plane of normal `n`.
fn face_area(points: &[Vector3<f64>], n: &Vector3<f64>) -> f64 {
    let c = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
    let mut sorted: Vec<Vector3<f64>> = points.to_vec();
    let u = (points[0] - c).normalize();
    let w = n.cross(&u);
    sorted.sort_by(|a, b| (a - c).dot(&w).atan2((a - c).dot(&u)).total_cmp(&(b - c).dot(&w).atan2((b - c).dot(&u))));
    (0..sorted.len()).map(|i| (sorted[i] - c).cross(&(sorted[(i + 1) % sorted.len()] - c)).dot(n)).sum::<f64>() / 2.0
}

/// How far inside the polygon of `points` (on the plane of normal `n`) the projection of `p` lies (negative: out).
fn margin(points: &[Vector3<f64>], n: &Vector3<f64>, p: &Vector3<f64>) -> f64 {
    let c = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
    let u = (points[0] - c).normalize();
    let w = n.cross(&u);
    let mut sorted: Vec<Vector3<f64>> = points.to_vec();
    sorted.sort_by(|a, b| (a - c).dot(&w).atan2((a - c).dot(&u)).total_cmp(&(b - c).dot(&w).atan2((b - c).dot(&u))));
    (0..sorted.len())
        .map(|i| {
            let (a, b) = (sorted[i], sorted[(i + 1) % sorted.len()]);
            let e = (b - a).normalize();
            n.cross(&e).dot(&(p - a))
        })
        .fold(f64::MAX, f64::min)
}

/// Turns the hull so that its face of outward normal `normal` faces down.
fn face_down(points: &[Point3<f64>], normal: &Vector3<f64>) -> Vec<Point3<f64>> {
    let turn = UnitQuaternion::rotation_between(normal, &-Vector3::z())
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI));
    points.iter().map(|p| turn * p).collect()
}

#[test]
fn seeded_random_hulls_stand_on_their_largest_face_in_both_modes() {
    let mut rng = Lcg(2024);
    for case in 0..12 {
        let (points, normal) = random_hull(&mut rng);
        let down = face_down(&points, &normal);
        // the hull it rests on: its largest face drawn down 0.1 m, a prism whose top is that face
        let low = span(&down).0;
        let face: Vec<Point3<f64>> = down.iter().filter(|p| p.z < low + 1e-9).copied().collect();
        let lower: Vec<Point3<f64>> = face.iter().flat_map(|p| [*p, p - Vector3::z() * 0.1]).collect();
        for fast in [false, true] {
            for under in [Under::Ground, Under::StaticBox, Under::RestingHull] {
                let (tilt, pen, bound) = stand(&down, under, fast, &lower);
                println!(
                    "measured: random hull {case} ({} points), fast {fast}, on {under:?}: tilt {tilt:.2e} deg, \
                     penetration {pen:.2e} m (bound {bound:.1e})",
                    points.len()
                );
                assert!(tilt < 0.01, "hull {case}, fast {fast}, on {under:?}: tilt {tilt} deg");
                assert!(pen <= bound, "hull {case}, fast {fast}, on {under:?}: penetration {pen} m");
            }
        }
    }
}

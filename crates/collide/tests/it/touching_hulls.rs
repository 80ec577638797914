//! Seeded property test of hulls that touch exactly: the pieces of a fractured box, or of the box's wall of bricks,
//! placed as they were cut and moved together by a random rigid motion. Every pair touches without overlap, so
//! no contact of theirs may be deeper than rounding. At zero distance parry's GJK gives any normal of the touching
//! set, and its manifold along a brick's diagonal put contacts 0.27 m deep (`hull_axis.rs`).

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use tumble_collide::{contacts, Cells, Mesh, Shape, SplitMix};

/// A box of half extents `h` as a closed mesh.
fn cuboid(h: [f64; 3]) -> Mesh {
    let (v, t) = Shape::cuboid(Vector3::from(h)).unwrap().triangle_mesh(8, 1.0);
    Mesh::new(&v, &t, "box").unwrap()
}

/// The deepest contact of any two of `pieces` (their hulls), all at `pose`, with a prediction of 1 mm.
fn deepest(pieces: &[Mesh], pose: &Isometry3<f64>) -> f64 {
    let shapes: Vec<Shape> = pieces.iter().map(|p| Shape::hull_of(p).unwrap()).collect();
    let mut deepest = f64::INFINITY;
    for (i, a) in shapes.iter().enumerate() {
        for b in &shapes[i + 1..] {
            for c in contacts(a, pose, b, pose, 1e-3).unwrap() {
                deepest = deepest.min(c.distance);
            }
        }
    }
    deepest
}

/// A random rigid motion: a rotation about a random axis and a shift of up to 2 m.
fn motion(rng: &mut SplitMix) -> Isometry3<f64> {
    let mut unit = || 2.0 * rng.uniform() - 1.0;
    let axis = Vector3::new(unit(), unit(), unit());
    let shift = Vector3::new(unit(), unit(), unit()) * 2.0;
    Isometry3::from_parts(Translation3::from(shift), UnitQuaternion::from_scaled_axis(axis * 3.0))
}

/// Rounding allowance: the pieces' vertices are cut points exact to ~1e-16 of the size, moved by a rotation; 1e-9 m
/// on pieces a metre across is far above that and far below the 0.1-0.3 m errors the test guards against.
const ROUNDING: f64 = 1e-9;

#[test]
fn fractured_pieces_touch_without_overlap_in_any_pose() {
    let mut rng = SplitMix(48);
    for seed in 0..6 {
        let h = [0.2 + rng.uniform(), 0.05 + 0.3 * rng.uniform(), 0.2 + rng.uniform()];
        let pieces = cuboid(h).fracture(&Cells::random(12, seed)).unwrap();
        let pose = motion(&mut rng);
        let d = deepest(&pieces, &pose);
        assert!(d >= -ROUNDING, "seed {seed}: a contact {d} m deep between pieces that only touch");
    }
}

#[test]
fn a_wall_of_bricks_touches_without_overlap() {
    // bricks 0.3 x 0.2 x 0.15 m, touching face to face and, diagonally, edge to edge
    let points: Vec<Point3<f64>> = (0..4)
        .flat_map(|j| (0..4).map(move |i| Point3::new(-0.45 + 0.3 * i as f64, 0.0, -0.225 + 0.15 * j as f64)))
        .collect();
    let bricks = cuboid([0.6, 0.1, 0.3]).fracture(&Cells::at(points)).unwrap();
    let mut rng = SplitMix(7);
    for pose in [Isometry3::identity(), motion(&mut rng), motion(&mut rng)] {
        let d = deepest(&bricks, &pose);
        assert!(d >= -ROUNDING, "a contact {d} m deep between bricks that only touch");
    }
}

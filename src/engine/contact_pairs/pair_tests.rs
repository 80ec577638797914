//! The contact pairs' tests: manifolds kept, carried and reduced across steps on small inputs.

use super::*;
use nalgebra::{Translation3, UnitQuaternion};
use tumble_collide::contacts;

/// A seeded generator (the same numbers everywhere).
struct Lcg(u64);
impl Lcg {
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn unit(&mut self) -> Vector3<f64> {
        Vector3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0)).normalize()
    }
}

#[test]
fn a_pair_moved_less_than_the_reuse_limits_gets_the_fresh_manifolds_contacts_back() {
    // Seeded random boxes of 0.05 to 1 m, in random orientations, the second resting on the first's top face
    // (turned about its normal, off centre, up to 0.1% of its size deep), then moved by a random relative
    // motion within the reuse limits (a translation and a turn about a random axis). The carried contacts are
    // the fresh manifold's: every fresh contact within reach has a carried one of the same features, whose gap
    // differs by no more than the motion (a vertex on a face keeps its exact gap, measured anew from the poses;
    // only clipped points slide along the faces), and no carried contact is out of reach.
    let mut rng = Lcg(7);
    let (mut reused, mut exact) = (0, 0);
    for case in 0..300 {
        let ha = Vector3::new(rng.range(0.05, 1.0), rng.range(0.05, 1.0), rng.range(0.05, 1.0));
        let hb = Vector3::new(rng.range(0.05, 1.0), rng.range(0.05, 1.0), rng.range(0.05, 1.0));
        let (a, b) = (Shape::cuboid(ha).unwrap(), Shape::cuboid(hb).unwrap());
        let (ra, rb) = (a.bounding_radius(), b.bounding_radius());
        let pose_a = Isometry3::from_parts(
            Translation3::from(rng.unit() * rng.range(0.0, 5.0)),
            UnitQuaternion::from_scaled_axis(rng.unit() * rng.range(0.0, 3.0)),
        );
        let depth = rng.range(0.0, 1e-3) * ha.z.min(hb.z);
        let on_top = Vector3::new(rng.range(-0.5, 0.5) * ha.x, rng.range(-0.5, 0.5) * ha.y, ha.z + hb.z - depth);
        let turn = UnitQuaternion::from_scaled_axis(Vector3::z() * rng.range(-3.0, 3.0));
        let pose_b = pose_a * Isometry3::from_parts(Translation3::from(on_top), turn);
        let prediction = 1e-3;
        let mut pair = Pair::new((0, 1));
        let fresh = |pa: &Isometry3<f64>, pb: &Isometry3<f64>, p: f64| contacts(&a, pa, &b, pb, p);
        let mut carried = Vec::new();
        let how = pair
            .contacts((&a, &pose_a, ra), (&b, &pose_b, rb), prediction, |p| fresh(&pose_a, &pose_b, p), &mut carried)
            .unwrap();
        assert_eq!(how, Found::Computed);
        // the smaller box moved about its centre, within the reuse limits
        let size = ra.min(rb);
        let (distance, turn, _) = reuse_limits(size);
        let (moved, turned) = (rng.range(0.0, 0.9) * distance, rng.range(0.0, 0.9) * turn);
        // half the cases turn about a random axis (tilting the faces), half about the boxes' common normal, so
        // that the faces stay parallel and the fresh manifold keeps the carried one's normal
        let axis = if case % 2 == 0 { rng.unit() } else { Vector3::z() };
        let step = Isometry3::from_parts(
            Translation3::from(rng.unit() * moved),
            UnitQuaternion::from_scaled_axis(axis * turned),
        );
        // how far a point of the smaller box moved, at most (its turn about its centre, out to its radius)
        let motion = moved + turned * size;
        let (pose_a, moved_b) = if ra < rb { (pose_a * step, pose_b) } else { (pose_a, pose_b * step) };
        let refuse =
            |_| -> Result<_, ()> { panic!("case {case}: a pair moved below the reuse distance was computed again") };
        let how = pair.contacts((&a, &pose_a, ra), (&b, &moved_b, rb), prediction, refuse, &mut carried).unwrap();
        assert_eq!(how, Found::Reused);
        reused += 1;
        let now = fresh(&pose_a, &moved_b, prediction).unwrap();
        assert!(carried.iter().all(|c| c.distance <= prediction), "case {case}: a carried contact out of reach");
        for c in &now {
            let twin = carried.iter().find(|k| (k.feature_a, k.feature_b) == (c.feature_a, c.feature_b));
            // a fresh contact closer than the prediction less the motion is within reach of the carried manifold
            if c.distance <= prediction - motion {
                assert!(twin.is_some(), "case {case}: no carried contact for {c:?}");
            }
            let Some(twin) = twin else { continue };
            // its gap differs by no more than the motion, and with the faces parallel by the rounding of
            // coordinates of a few metres alone
            let gap = (twin.distance - c.distance).abs();
            let bound = if case % 2 == 1 { 1e-12 } else { motion + 1e-12 };
            assert!(gap <= bound, "case {case}: gaps {} and {} differ by {gap:e}", twin.distance, c.distance);
            exact += usize::from(gap <= 1e-12);
        }
    }
    assert_eq!(reused, 300);
    // boxes face to face touch at vertices on faces: with the faces parallel their gaps are carried exactly
    assert!(exact > 300, "{exact} contacts carried exactly");
}

#[test]
fn a_pair_moved_past_the_reuse_distance_or_with_a_curved_contact_is_computed_again() {
    let a = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    let b = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    let r = a.bounding_radius();
    let pose_a = Isometry3::identity();
    let pose_b = Isometry3::translation(0.0, 0.0, 1.0);
    let mut pair = Pair::new((0, 1));
    let mut out = Vec::new();
    let mut ask = |pb: &Isometry3<f64>| {
        pair.contacts((&a, &pose_a, r), (&b, pb, r), 1e-3, |p| contacts(&a, &pose_a, &b, pb, p), &mut out).unwrap()
    };
    let (distance, turn, _) = reuse_limits(r);
    assert_eq!(distance, REUSE_DISTANCE, "a metre cube keeps its manifold over a millimetre");
    assert!((REUSE_HALF_SINE - (0.5 * REUSE_TURN).sin()).abs() < 1e-17, "the turn's half sine");
    assert_eq!(ask(&pose_b), Found::Computed);
    assert_eq!(ask(&Isometry3::translation(0.0, 0.0, 1.0 + 0.5 * distance)), Found::Reused);
    assert_eq!(
        ask(&Isometry3::translation(0.0, 0.0, 1.0 + 2.0 * distance)),
        Found::Computed,
        "moved past the reuse distance"
    );
    let turned = |angle: f64| {
        let turn = UnitQuaternion::from_scaled_axis(Vector3::z() * angle);
        Isometry3::from_parts(Translation3::new(0.0, 0.0, 1.0 + 2.0 * distance), turn)
    };
    assert_eq!(ask(&turned(0.75 * turn)), Found::Reused);
    assert_eq!(ask(&turned(1.25 * turn)), Found::Computed, "turned past the reuse turn");
    // a ball on the box: always computed
    let ball = Shape::sphere(0.5).unwrap();
    let mut pair = Pair::new((0, 2));
    for _ in 0..2 {
        let compute = |p| contacts(&a, &pose_a, &ball, &pose_b, p);
        let how = pair.contacts((&a, &pose_a, r), (&ball, &pose_b, 0.5), 1e-3, compute, &mut out).unwrap();
        assert_eq!(how, Found::Computed, "a curved pair is never reused");
    }
}

//! Yes-or-no and how-far queries between two posed shapes (parry answers them).

use crate::aabb::check_pose;
use crate::error::ShapeError;
use crate::geometry::ParryView;
use crate::shape::Shape;
use nalgebra::Isometry3;
use parry3d_f64::query::details::distance_support_map_support_map;
use parry3d_f64::query::{DefaultQueryDispatcher, QueryDispatcher};

pub(crate) fn unsupported_pair(a: &Shape, b: &Shape) -> ShapeError {
    ShapeError::new("shape", format!("no geometric query between a {} and a {}", a.kind(), b.kind()))
}

/// Whether the two shapes share a point (touching counts).
pub fn intersects(a: &Shape, pose_a: &Isometry3<f64>, b: &Shape, pose_b: &Isometry3<f64>) -> Result<bool, ShapeError> {
    check_pose("pose_a", pose_a)?;
    check_pose("pose_b", pose_b)?;
    let (va, vb) = (ParryView::of(a), ParryView::of(b));
    let pos12 = va.pose(pose_a).inv_mul(&vb.pose(pose_b));
    DefaultQueryDispatcher
        .intersection_test(&pos12, va.as_dyn(), vb.as_dyn())
        .map(|r| r.intersecting)
        .map_err(|_| unsupported_pair(a, b))
}

/// The distance between the two shapes (0 when they touch or interpenetrate).
pub fn distance(a: &Shape, pose_a: &Isometry3<f64>, b: &Shape, pose_b: &Isometry3<f64>) -> Result<f64, ShapeError> {
    check_pose("pose_a", pose_a)?;
    check_pose("pose_b", pose_b)?;
    let (va, vb) = (ParryView::of(a), ParryView::of(b));
    let pos12 = va.pose(pose_a).inv_mul(&vb.pose(pose_b));
    if let (ParryView::Cuboid(ca), ParryView::Cuboid(cb)) = (&va, &vb) {
        // parry 0.31.1's box-box distance overestimates some gaps (dimforge/parry#431, up to 10x in our tests; its
        // own closest_points no longer uses that path): GJK instead.
        return Ok(distance_support_map_support_map(&pos12, ca, cb));
    }
    DefaultQueryDispatcher
        .distance(&pos12, va.as_dyn(), vb.as_dyn())
        .map(|r| r.distance)
        .map_err(|_| unsupported_pair(a, b))
}

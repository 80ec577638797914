//! The contact normal of two convex hulls checked against the hulls. Where two hulls touch exactly (the faces of a
//! fracture's pieces, glued until a bond breaks), parry's GJK finds them zero apart but its normal is any direction
//! of the touching set, and the manifold built along it reports points deep inside both (a brick beside another
//! came out 0.27 m into it). The hulls' separation along a face normal of either is a lower bound on how far apart
//! they are (or how little they overlap); where one face normal shows them further apart than parry's normal does,
//! parry's is not the contact's, and that face normal is taken instead.

use crate::convert::from_parry;
use nalgebra::{Unit, Vector3};
use parry3d_f64::math::Pose;
use parry3d_f64::shape::Shape as ParryShape;

/// How far apart `b` is from `a` along `n` (world, from A toward B): B's lowest vertex less A's highest (negative
/// when they overlap along it).
fn gap(a: &[Vector3<f64>], b: &[Vector3<f64>], n: &Vector3<f64>) -> f64 {
    let top = a.iter().map(|p| n.dot(p)).fold(f64::NEG_INFINITY, f64::max);
    let bottom = b.iter().map(|p| n.dot(p)).fold(f64::INFINITY, f64::min);
    bottom - top
}

/// A hull's vertices and outward face normals (world), or `None` if the part is not a hull.
fn hull(shape: &dyn ParryShape, pose: &Pose) -> Option<(Vec<Vector3<f64>>, Vec<Vector3<f64>>)> {
    let hull = shape.as_convex_polyhedron()?;
    let vertices = hull.points().iter().map(|p| from_parry(pose * *p)).collect();
    let normals = hull.faces().iter().map(|f| from_parry(pose.rotation * f.normal)).collect();
    Some((vertices, normals))
}

/// For two hulls `a` and `b` (parts at their world poses) in contact along `normal` (from A toward B): the face
/// normal of either hull (A's outward, or B's inward) along which they are furthest apart, if that is further (by
/// 1e-9 of their size) than along `normal`; `None` if none is, or for other parts.
pub(crate) fn sounder_normal(
    a: &dyn ParryShape,
    pose_a: &Pose,
    b: &dyn ParryShape,
    pose_b: &Pose,
    normal: &Unit<Vector3<f64>>,
) -> Option<Unit<Vector3<f64>>> {
    let ((va, fa), (vb, fb)) = (hull(a, pose_a)?, hull(b, pose_b)?);
    let size = va.iter().chain(&vb).map(|p| p.amax()).fold(1e-300, f64::max);
    let eps = 1e-9 * size;
    let along = gap(&va, &vb, normal);
    let candidates = fa.iter().copied().chain(fb.iter().map(|n| -n));
    let (best, apart) = candidates
        .map(|n| (n, gap(&va, &vb, &n)))
        .fold((Vector3::zeros(), f64::NEG_INFINITY), |best, c| if c.1 > best.1 { c } else { best });
    (apart > along + eps).then(|| Unit::new_normalize(best))
}

//! Contact geometry of a touching or interpenetrating pair, from parry's contact manifolds: points on both surfaces, a
//! common normal, signed distance and the kind of contact (a `ShapeContact`, `contact_point.rs`). Where parry's manifold
//! of hulls is partial (a face of more than four vertices, a hull on a plane, two hulls touching exactly), their
//! faces are taken whole in `face_contact.rs`.

use crate::aabb::check_pose;
use crate::contact_point::{kind, Feature, ShapeContact};
use crate::convert::{from_parry, point_from_parry};
use crate::error::ShapeError;
use crate::face_contact::{clipped_contacts, hull_plane_contacts, long_face_contacts};
use crate::geometry::ParryView;
use crate::hull_axis::sounder_normal;
use crate::proximity::unsupported_pair;
use crate::shape::Shape;
use nalgebra::{Isometry3, Point3, Unit};
use parry3d_f64::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
use parry3d_f64::shape::{FeatureId, Shape as ParryShape};

/// The feature of `shape` that parry's id names (a point of a sphere or capsule is of its curved surface).
fn feature(shape: &Shape, id: FeatureId) -> Feature {
    if matches!(shape, Shape::Sphere { .. } | Shape::Capsule { .. }) {
        return Feature::Curved;
    }
    match id {
        FeatureId::Vertex(i) => Feature::Vertex(i),
        FeatureId::Edge(i) => Feature::Edge(i),
        FeatureId::Face(i) => Feature::Face(i),
        _ => Feature::Unknown,
    }
}

/// The contact points of `a` at `pose_a` and `b` at `pose_b` closer than `prediction` (>= 0; 0 = touching or
/// interpenetrating only). Duplicate points (both shapes' vertices at one place) are reported once, and parry's
/// deepest-point fallback only when it adds depth.
pub fn contacts(
    a: &Shape,
    pose_a: &Isometry3<f64>,
    b: &Shape,
    pose_b: &Isometry3<f64>,
    prediction: f64,
) -> Result<Vec<ShapeContact>, ShapeError> {
    check_pose("pose_a", pose_a)?;
    check_pose("pose_b", pose_b)?;
    if !(prediction.is_finite() && prediction >= 0.0) {
        return Err(ShapeError::new("prediction", format!("must be finite and >= 0, got {prediction}")));
    }
    let (va, vb) = (ParryView::of(a), ParryView::of(b));
    let (pa, pb) = (va.pose(pose_a), vb.pose(pose_b));
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    DefaultQueryDispatcher
        .contact_manifolds(&pa.inv_mul(&pb), va.as_dyn(), vb.as_dyn(), prediction, &mut manifolds, &mut None)
        .map_err(|_| unsupported_pair(a, b))?;
    let mut out: Vec<ShapeContact> = Vec::new();
    for m in &manifolds {
        let sa = m.subshape_poses.as_ref().and_then(|s| s.pos1).map_or(pa, |s| pa * s);
        let sb = m.subshape_poses.as_ref().and_then(|s| s.pos2).map_or(pb, |s| pb * s);
        let Some(normal) = Unit::try_new(from_parry(sa.rotation * m.local_n1), 1e-12) else { continue };
        // A hull's face of more than four vertices: parry keeps four of them, the whole face is clipped here.
        let (ta, tb) = (va.triangle(m.subshape1), vb.triangle(m.subshape2));
        let (ca, cb) = (va.piece(m.subshape1), vb.piece(m.subshape2));
        let part_a: &dyn ParryShape = ta.as_ref().map(|t| t as &dyn ParryShape).or(ca).unwrap_or(va.as_dyn());
        let part_b: &dyn ParryShape = tb.as_ref().map(|t| t as &dyn ParryShape).or(cb).unwrap_or(vb.as_dyn());
        // a compound's features are numbered within each piece: the piece's number goes into the id
        let tag = |c: ShapeContact| ShapeContact {
            feature_a: ca.map_or(c.feature_a, |_| in_piece(c.feature_a, m.subshape1)),
            feature_b: cb.map_or(c.feature_b, |_| in_piece(c.feature_b, m.subshape2)),
            ..c
        };
        let planar = part_a.as_halfspace().is_some() || part_b.as_halfspace().is_some();
        if let Some(all) = planar.then(|| hull_plane_contacts(part_a, &sa, part_b, &sb, normal, prediction)).flatten() {
            for c in all.into_iter().map(tag) {
                if !out.iter().any(|o| same_place(o, &c)) {
                    out.push(c);
                }
            }
            continue;
        }
        // two hulls touching exactly: parry's normal may be any direction (`hull_axis.rs`)
        let sounder = sounder_normal(part_a, &sa, part_b, &sb, &normal);
        if let Some(all) = sounder.and_then(|n| clipped_contacts(part_a, &sa, part_b, &sb, n, prediction)) {
            for c in all.into_iter().map(tag) {
                if !out.iter().any(|o| same_place(o, &c)) {
                    out.push(c);
                }
            }
            continue;
        }
        if !m.points.is_empty() {
            if let Some(whole) = long_face_contacts(part_a, &sa, part_b, &sb, normal, prediction) {
                // the faces parry's normal picks may not be the touching ones (an irregular hull's): then parry's
                // own points, nearer, are kept besides
                let nearest = whole.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min);
                let parry = m.points.iter().map(|p| p.dist).fold(f64::INFINITY, f64::min);
                for c in whole.into_iter().map(tag) {
                    if !out.iter().any(|o| same_place(o, &c)) {
                        out.push(c);
                    }
                }
                if nearest <= parry + 1e-9 * (1.0 + parry.abs()) {
                    continue;
                }
            }
        }
        let labelled = m.points.iter().filter(|p| !p.fid1.is_unknown() || !p.fid2.is_unknown());
        let deepest_labelled = labelled.map(|p| p.dist).fold(f64::INFINITY, f64::min);
        for p in m.points.iter().filter(|p| p.dist <= prediction) {
            let (fa, fb) = (feature(a, p.fid1.unpack()), feature(b, p.fid2.unpack()));
            let unknown = p.fid1.is_unknown() && p.fid2.is_unknown();
            if unknown && p.dist >= deepest_labelled - 1e-12 * (1.0 + p.dist.abs()) {
                continue;
            }
            let c = tag(ShapeContact {
                point_a: point_from_parry(sa.transform_point(p.local_p1)),
                point_b: point_from_parry(sb.transform_point(p.local_p2)),
                normal,
                distance: p.dist,
                kind: kind(fa, fb),
                feature_a: fa,
                feature_b: fb,
            });
            if !out.iter().any(|o| same_place(o, &c)) {
                out.push(c);
            }
        }
    }
    Ok(out)
}

/// A piece's feature as a feature of its compound: the piece number in the id's upper 16 bits (pieces and their
/// features number fewer than 65536).
fn in_piece(f: Feature, piece: u32) -> Feature {
    let id = |i: u32| (piece << 16) | (i & 0xffff);
    match f {
        Feature::Vertex(i) => Feature::Vertex(id(i)),
        Feature::Edge(i) => Feature::Edge(id(i)),
        Feature::Face(i) => Feature::Face(id(i)),
        other => other,
    }
}

/// Whether two contacts sit at the same place (to 1e-9 relative).
fn same_place(x: &ShapeContact, y: &ShapeContact) -> bool {
    let close = |p: &Point3<f64>, q: &Point3<f64>| (p - q).norm() <= 1e-9 * (1.0 + p.coords.amax());
    close(&x.point_a, &y.point_a) && close(&x.point_b, &y.point_b)
}

//! Face contacts of convex hulls whose faces have more than four vertices. parry's polygonal features hold four
//! vertices, so its manifold of a hull's octagonal face keeps the face's first four (all on one side of it) and a
//! prism on the ground tips over. Here both touching features are taken whole, along the manifold's normal, and
//! their overlap is clipped in the plane across it: every vertex of the overlap is a contact point.

use crate::contact_point::{kind, Feature, ShapeContact};
use crate::convert::{from_parry, point_from_parry, to_parry};
use nalgebra::{Point3, Unit, Vector2, Vector3};
use parry3d_f64::math::Pose;
use parry3d_f64::shape::{PolygonalFeature, Shape as ParryShape};

/// Faces of more vertices than this are cut short by parry's polygonal features.
const PARRY_FACE_VERTICES: usize = 4;

/// What one shape shows the other along the normal: a convex polygon, segment or point (world), its vertices in order.
struct Polygon {
    points: Vec<Point3<f64>>,
    /// The feature of each vertex.
    vertices: Vec<Feature>,
    /// The feature of each edge, from vertex k to vertex k + 1.
    edges: Vec<Feature>,
    face: Feature,
}

/// Whether `shape` is a hull whose face toward `dir` (world) has more vertices than parry keeps.
fn long_face(shape: &dyn ParryShape, pose: &Pose, dir: Vector3<f64>) -> bool {
    shape.as_convex_polyhedron().is_some_and(|hull| {
        let local = pose.rotation.inverse() * to_parry(&dir);
        let face = best_face(hull.faces().iter().map(|f| f.normal.dot(local)));
        hull.faces()[face].num_vertices_or_edges as usize > PARRY_FACE_VERTICES
    })
}

/// The index of the largest of `dots` (the first of equals).
fn best_face(dots: impl Iterator<Item = f64>) -> usize {
    dots.enumerate().fold((0, f64::NEG_INFINITY), |best, (i, d)| if d > best.1 { (i, d) } else { best }).0
}

/// The feature of `shape` at `pose` that faces `dir` (world), or `None` for shapes this does not handle (rounded
/// ones, composites, half-spaces: a hull against a half-space is `hull_plane_contacts`').
fn side(shape: &dyn ParryShape, pose: &Pose, dir: Vector3<f64>) -> Option<Polygon> {
    let local = pose.rotation.inverse() * to_parry(&dir);
    if let Some(hull) = shape.as_convex_polyhedron() {
        let f = best_face(hull.faces().iter().map(|f| f.normal.dot(local)));
        let face = &hull.faces()[f];
        let range =
            face.first_vertex_or_edge as usize..(face.first_vertex_or_edge + face.num_vertices_or_edges) as usize;
        let vids = &hull.vertices_adj_to_face()[range.clone()];
        return Some(Polygon {
            points: vids.iter().map(|&v| point_from_parry(pose * hull.points()[v as usize])).collect(),
            vertices: vids.iter().map(|&v| Feature::Vertex(v)).collect(),
            edges: hull.edges_adj_to_face()[range].iter().map(|&e| Feature::Edge(e)).collect(),
            face: Feature::Face(f as u32),
        });
    }
    if shape.as_halfspace().is_some() {
        return None;
    }
    let (pfm, radius) = shape.as_polygonal_feature_map()?;
    if radius != 0.0 {
        return None;
    }
    let mut feature = PolygonalFeature::default();
    pfm.local_support_feature(local, &mut feature);
    let n = feature.num_vertices;
    if n == 0 {
        return None;
    }
    let code = |id: parry3d_f64::shape::PackedFeatureId| match id.unpack() {
        parry3d_f64::shape::FeatureId::Vertex(i) => Feature::Vertex(i),
        parry3d_f64::shape::FeatureId::Edge(i) => Feature::Edge(i),
        parry3d_f64::shape::FeatureId::Face(i) => Feature::Face(i),
        _ => Feature::Unknown,
    };
    Some(Polygon {
        points: feature.vertices[..n].iter().map(|&p| point_from_parry(pose * p)).collect(),
        vertices: feature.vids[..n].iter().map(|&v| code(v)).collect(),
        edges: feature.eids[..n].iter().map(|&e| code(e)).collect(),
        face: code(feature.fid),
    })
}

/// The contacts of a convex hull and a half-space (parts `a` and `b` in either order, at their world poses) along
/// `normal` (world, from A toward B): the vertices closer to the plane than `prediction` of the hull's face that
/// holds its lowest vertex and faces the plane most, on the plane's face. parry's manifold takes the face whose
/// normal is nearest the plane's wherever it is, and on an irregular hull (a decomposition's pieces, a rounded
/// blob's hull) that face need not hold the lowest vertex: a tilted piece's deepest corner went unseen. `None` for
/// other pairs.
pub(crate) fn hull_plane_contacts(
    a: &dyn ParryShape,
    pose_a: &Pose,
    b: &dyn ParryShape,
    pose_b: &Pose,
    normal: Unit<Vector3<f64>>,
    prediction: f64,
) -> Option<Vec<ShapeContact>> {
    let (hull, hull_pose, plane, plane_pose, hull_is_a) =
        match (a.as_convex_polyhedron(), b.as_halfspace(), a.as_halfspace(), b.as_convex_polyhedron()) {
            (Some(h), Some(p), _, _) => (h, pose_a, p, pose_b, true),
            (_, _, Some(p), Some(h)) => (h, pose_b, p, pose_a, false),
            _ => return None,
        };
    let m = from_parry(plane_pose.rotation * plane.normal);
    let offset = m.dot(&from_parry(plane_pose.translation));
    let n = normal.into_inner();
    // the lowest vertex, and of its faces the one turned most toward the plane
    let down = hull_pose.rotation.inverse() * to_parry(&-m);
    let points = hull.points();
    let lowest =
        (0..points.len()).fold(0, |best, i| if points[i].dot(down) > points[best].dot(down) { i } else { best });
    let vertex = &hull.vertices()[lowest];
    let first = vertex.first_adj_face_or_edge as usize;
    let around = &hull.faces_adj_to_vertex()[first..first + vertex.num_adj_faces_or_edge as usize];
    let faces = hull.faces();
    let chosen = around.get(best_face(around.iter().map(|&f| faces[f as usize].normal.dot(down))));
    let ids: Vec<u32> = match chosen {
        Some(&f) => {
            let f = &faces[f as usize];
            let range = f.first_vertex_or_edge as usize..(f.first_vertex_or_edge + f.num_vertices_or_edges) as usize;
            hull.vertices_adj_to_face()[range].to_vec()
        }
        None => vec![lowest as u32],
    };
    let mut out = Vec::new();
    for i in ids {
        let q = point_from_parry(*hull_pose * points[i as usize]);
        let height = m.dot(&q.coords) - offset;
        if height > prediction {
            continue;
        }
        let on_plane = q - m * height;
        let (point_a, point_b, feature_a, feature_b) = if hull_is_a {
            (q, on_plane, Feature::Vertex(i), Feature::Face(0))
        } else {
            (on_plane, q, Feature::Face(0), Feature::Vertex(i))
        };
        out.push(ShapeContact {
            point_a,
            point_b,
            normal,
            distance: n.dot(&(point_b - point_a)),
            kind: kind(feature_a, feature_b),
            feature_a,
            feature_b,
        });
    }
    Some(out)
}

/// The contacts of parts `a` at `pose_a` and `b` at `pose_b` (parry shapes and world poses) along `normal` (world,
/// from A toward B) closer than `prediction`, when one of them is a hull whose face toward the other has more than
/// four vertices; `None` when parry's own manifold is whole.
pub(crate) fn long_face_contacts(
    a: &dyn ParryShape,
    pose_a: &Pose,
    b: &dyn ParryShape,
    pose_b: &Pose,
    normal: Unit<Vector3<f64>>,
    prediction: f64,
) -> Option<Vec<ShapeContact>> {
    let n = normal.into_inner();
    if !(long_face(a, pose_a, n) || long_face(b, pose_b, -n)) {
        return None;
    }
    clipped_contacts(a, pose_a, b, pose_b, normal, prediction)
}

/// The contacts of parts `a` at `pose_a` and `b` at `pose_b` along `normal` (world, from A toward B) closer than
/// `prediction`: the feature of each facing the other, taken whole, and their overlap clipped in the plane across
/// the normal; `None` for shapes this does not handle (`side`).
pub(crate) fn clipped_contacts(
    a: &dyn ParryShape,
    pose_a: &Pose,
    b: &dyn ParryShape,
    pose_b: &Pose,
    normal: Unit<Vector3<f64>>,
    prediction: f64,
) -> Option<Vec<ShapeContact>> {
    let n = normal.into_inner();
    let (pa, pb) = (side(a, pose_a, n)?, side(b, pose_b, -n)?);
    let mut out = Vec::new();
    let mut push = |point_a: Point3<f64>, point_b: Point3<f64>, feature_a: Feature, feature_b: Feature| {
        let distance = n.dot(&(point_b - point_a));
        if distance <= prediction {
            out.push(ShapeContact {
                point_a,
                point_b,
                normal,
                distance,
                kind: kind(feature_a, feature_b),
                feature_a,
                feature_b,
            });
        }
    };
    let frame = Frame::across(n);
    let (qa, qb) = (frame.flatten(&pa.points), frame.flatten(&pb.points));
    let scale = pa.points.iter().chain(&pb.points).map(|p| p.coords.amax()).fold(1e-300, f64::max);
    let eps = 1e-9 * scale;
    for q in overlap(&qa, &qb, eps) {
        let (Some(xa), Some(xb)) = (frame.lift(q, &pa, &qa), frame.lift(q, &pb, &qb)) else { return None };
        push(xa, xb, label(q, &pa, &qa, eps), label(q, &pb, &qb, eps));
    }
    Some(out)
}

/// An orthonormal frame (u, w) of the plane across a normal.
struct Frame {
    n: Vector3<f64>,
    u: Vector3<f64>,
    w: Vector3<f64>,
}

impl Frame {
    fn across(n: Vector3<f64>) -> Frame {
        let pick = if n.x.abs() < 0.6 { Vector3::x() } else { Vector3::y() };
        let u = n.cross(&pick).normalize();
        Frame { n, u, w: n.cross(&u) }
    }

    fn flatten(&self, points: &[Point3<f64>]) -> Vec<Vector2<f64>> {
        points.iter().map(|p| Vector2::new(self.u.dot(&p.coords), self.w.dot(&p.coords))).collect()
    }

    /// The point of polygon `p` (flattened to `flat`) over the plane point `q`, along the normal.
    fn lift(&self, q: Vector2<f64>, p: &Polygon, flat: &[Vector2<f64>]) -> Option<Point3<f64>> {
        let x0 = Point3::from(self.u * q.x + self.w * q.y);
        match p.points.len() {
            1 => Some(p.points[0]),
            2 => {
                let d = flat[1] - flat[0];
                let s = if d.norm_squared() > 0.0 {
                    ((q - flat[0]).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                Some(p.points[0] + (p.points[1] - p.points[0]) * s)
            }
            _ => {
                let m = plane_normal(&p.points)?;
                let along = m.dot(&self.n);
                if along.abs() < 1e-9 {
                    return None;
                }
                Some(x0 + self.n * (m.dot(&(p.points[0] - x0)) / along))
            }
        }
    }
}

/// The unit normal of a planar polygon (Newell's method), `None` if it has no area.
fn plane_normal(points: &[Point3<f64>]) -> Option<Vector3<f64>> {
    let c = points.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / points.len() as f64;
    let mut m = Vector3::zeros();
    for (i, p) in points.iter().enumerate() {
        m += (p.coords - c).cross(&(points[(i + 1) % points.len()].coords - c));
    }
    m.try_normalize(0.0)
}

/// The vertices of the overlap of two flat convex features (polygons, segments or points; at least one with area).
pub(crate) fn overlap(a: &[Vector2<f64>], b: &[Vector2<f64>], eps: f64) -> Vec<Vector2<f64>> {
    let (clip, subject) = if a.len() >= b.len() { (a, b) } else { (b, a) };
    if clip.len() < 3 {
        return Vec::new();
    }
    let clip = counter_clockwise(clip);
    let mut out: Vec<Vector2<f64>> = match subject.len() {
        1 => subject.iter().copied().filter(|&p| inside(&clip, p, eps)).collect(),
        2 => clip_segment(&clip, subject[0], subject[1], eps),
        _ => clip_polygon(&clip, subject, eps),
    };
    out.dedup_by(|x, y| (*x - *y).norm() <= eps);
    if out.len() > 1 && (out[0] - out[out.len() - 1]).norm() <= eps {
        out.pop();
    }
    out
}

fn counter_clockwise(p: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
    let area: f64 = (0..p.len()).map(|i| p[i].perp(&p[(i + 1) % p.len()])).sum();
    if area < 0.0 {
        p.iter().rev().copied().collect()
    } else {
        p.to_vec()
    }
}

fn inside(ccw: &[Vector2<f64>], p: Vector2<f64>, eps: f64) -> bool {
    (0..ccw.len()).all(|i| edge_side(ccw[i], ccw[(i + 1) % ccw.len()], p) >= -eps)
}

/// Signed distance of `p` to the left of the edge (a, b).
fn edge_side(a: Vector2<f64>, b: Vector2<f64>, p: Vector2<f64>) -> f64 {
    let d = b - a;
    let len = d.norm();
    if len == 0.0 {
        0.0
    } else {
        d.perp(&(p - a)) / len
    }
}

/// The part of the segment (p, q) inside the convex polygon `ccw`: its two ends (Cyrus-Beck).
fn clip_segment(ccw: &[Vector2<f64>], p: Vector2<f64>, q: Vector2<f64>, eps: f64) -> Vec<Vector2<f64>> {
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for i in 0..ccw.len() {
        let (a, b) = (ccw[i], ccw[(i + 1) % ccw.len()]);
        let (sp, sq) = (edge_side(a, b, p) + eps, edge_side(a, b, q) + eps);
        if sp < 0.0 && sq < 0.0 {
            return Vec::new();
        }
        if sp < 0.0 {
            lo = lo.max(sp / (sp - sq));
        } else if sq < 0.0 {
            hi = hi.min(sp / (sp - sq));
        }
    }
    if lo > hi {
        return Vec::new();
    }
    vec![p + (q - p) * lo, p + (q - p) * hi]
}

/// The convex polygon `subject` clipped by the convex polygon `ccw` (Sutherland-Hodgman).
fn clip_polygon(ccw: &[Vector2<f64>], subject: &[Vector2<f64>], eps: f64) -> Vec<Vector2<f64>> {
    let mut out = subject.to_vec();
    for i in 0..ccw.len() {
        let (a, b) = (ccw[i], ccw[(i + 1) % ccw.len()]);
        let input = std::mem::take(&mut out);
        for k in 0..input.len() {
            let (p, q) = (input[k], input[(k + 1) % input.len()]);
            let (sp, sq) = (edge_side(a, b, p) + eps, edge_side(a, b, q) + eps);
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                out.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The feature of polygon `p` (flattened to `flat`) at the plane point `q`: a vertex, an edge or the face.
fn label(q: Vector2<f64>, p: &Polygon, flat: &[Vector2<f64>], eps: f64) -> Feature {
    let near = 16.0 * eps;
    if let Some(k) = flat.iter().position(|v| (v - q).norm() <= near) {
        return p.vertices[k];
    }
    for k in 0..flat.len().min(if flat.len() == 2 { 1 } else { flat.len() }) {
        let (a, b) = (flat[k], flat[(k + 1) % flat.len()]);
        let d = b - a;
        let s = (q - a).dot(&d) / d.norm_squared().max(1e-300);
        if (0.0..=1.0).contains(&s) && edge_side(a, b, q).abs() <= near {
            return p.edges[k];
        }
    }
    if flat.len() >= 3 {
        p.face
    } else {
        p.edges.first().copied().unwrap_or(Feature::Unknown)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(c: f64, h: f64) -> Vec<Vector2<f64>> {
        vec![
            Vector2::new(c - h, c - h),
            Vector2::new(c + h, c - h),
            Vector2::new(c + h, c + h),
            Vector2::new(c - h, c + h),
        ]
    }

    fn area(p: &[Vector2<f64>]) -> f64 {
        0.5 * (0..p.len()).map(|i| p[i].perp(&p[(i + 1) % p.len()])).sum::<f64>().abs()
    }

    #[test]
    fn overlapping_squares_clip_to_their_common_square() {
        // [0, 2]^2 and [1, 3]^2 share [1, 2]^2 of area 1
        let o = overlap(&square(1.0, 1.0), &square(2.0, 1.0), 1e-12);
        assert_eq!(o.len(), 4);
        // the clip keeps points within eps of an edge: the area may grow by about eps times the perimeter (4)
        assert!((area(&o) - 1.0).abs() < 1e-11, "area {}", area(&o));
    }

    #[test]
    fn a_segment_is_cut_at_the_polygon() {
        let o = overlap(&square(0.0, 1.0), &[Vector2::new(-3.0, 0.5), Vector2::new(3.0, 0.5)], 0.0);
        assert_eq!(o.len(), 2);
        assert!((o[0] - Vector2::new(-1.0, 0.5)).norm() < 1e-12 && (o[1] - Vector2::new(1.0, 0.5)).norm() < 1e-12);
    }
}

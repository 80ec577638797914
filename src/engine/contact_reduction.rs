//! Contact reduction for the velocity-level steps (fast mode, accurate mode's contact steps): at most four points
//! per collider pair and contact plane (a decomposed mesh touches along several), chosen to keep the deepest point and the largest support area (the quadrilateral of greatest
//! area among the manifold's points, greedily), and to hold the centre of mass of the body the contact carries
//! wherever the whole contact polygon holds it (a prism on its face stands on the points that hold it up).

use crate::engine::found_contact::{pair_runs, FoundContact};
use crate::engine::support_polygon::hold;
use nalgebra::{Point3, Vector3};
use std::collections::BTreeMap;
use tumble_contact::BodyState;

/// At most `MAX_POINTS` contacts per collider pair.
pub(crate) const MAX_POINTS: usize = 4;

/// Keeps, per collider pair, the deepest contact, the one farthest from it, the one spanning the largest triangle
/// with those two, and the one adding the most area outside that triangle (in the order found otherwise). A box
/// on a face keeps its four corners; the rows of the conic program drop from up to eight per pair to four. If those
/// four leave out the centre of mass of a body of the pair (seen along the normal, the body pressed hardest into
/// the other first) that the whole polygon holds, they are chosen again to hold it (`support_polygon::hold`).
/// `states` are the actors' (indexed as the contacts' bodies; statics may be missing).
pub(crate) fn reduce(found: Vec<FoundContact>, states: &[BodyState]) -> Vec<FoundContact> {
    if found.len() <= MAX_POINTS {
        return found;
    }
    let kept = reduce_indices(&found, states);
    if kept.len() == found.len() {
        return found;
    }
    let mut keep = vec![false; found.len()];
    kept.into_iter().for_each(|k| keep[k] = true);
    found.into_iter().zip(keep).filter_map(|(f, k)| k.then_some(f)).collect()
}

/// The indices (in order) of the contacts `reduce` keeps.
pub(crate) fn reduce_indices(found: &[FoundContact], states: &[BodyState]) -> Vec<usize> {
    if found.len() <= MAX_POINTS {
        return (0..found.len()).collect();
    }
    // The scene gives each pair's contacts together, pairs in order: then the groups are runs, found without a map.
    let groups: Vec<Vec<usize>> = match pair_runs(found, |f| f.key.colliders) {
        Some(runs) => runs.into_iter().filter(|r| r.len() > MAX_POINTS).map(|r| r.collect()).collect(),
        None => {
            let mut groups: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
            for (i, f) in found.iter().enumerate() {
                groups.entry(f.key.colliders).or_default().push(i);
            }
            groups.into_values().filter(|g| g.len() > MAX_POINTS).collect()
        }
    };
    if groups.is_empty() {
        return (0..found.len()).collect();
    }
    let mut keep = vec![true; found.len()];
    for members in &groups {
        members.iter().for_each(|&i| keep[i] = false);
    }
    for cluster in groups.iter().flat_map(|members| normal_clusters(found, members)) {
        if cluster.len() <= MAX_POINTS {
            cluster.iter().for_each(|&i| keep[i] = true);
            continue;
        }
        let members = &cluster;
        let points: Vec<Point3<f64>> = members.iter().map(|&i| found[i].contact.point).collect();
        let deepest = deepest(members.iter().map(|&i| found[i].contact.distance));
        let c = &found[members[0]].contact;
        let targets = centres(c.a, c.b, c.normal.into_inner(), states);
        for k in hold(&points, deepest, select(&points, deepest), &targets, &c.normal) {
            keep[members[k]] = true;
        }
    }
    (0..found.len()).filter(|&k| keep[k]).collect()
}

/// The place of the deepest of these gaps (the first of equals; 0 if none): the reduction's first point.
pub(crate) fn deepest(gaps: impl Iterator<Item = f64>) -> usize {
    gaps.enumerate().min_by(|a, b| a.1.total_cmp(&b.1)).map_or(0, |(k, _)| k)
}

/// Normals within this angle's cosine (10 degrees) are one contact plane.
const SAME_PLANE: f64 = 0.984_807_753_012_208;

/// A pair's contacts split by normal, in the order found: a convex pair's share one normal (one group), a
/// decomposed mesh's come from several pieces, each touching along its own normal, and each plane is reduced alone
/// (reduced together, the four points kept would cover one piece and leave the others' contacts out of the step).
fn normal_clusters(found: &[FoundContact], members: &[usize]) -> Vec<Vec<usize>> {
    let mut clusters: Vec<(Vector3<f64>, Vec<usize>)> = Vec::new();
    for &i in members {
        let n = found[i].contact.normal.into_inner();
        match clusters.iter_mut().find(|(m, _)| m.dot(&n) >= SAME_PLANE) {
            Some((_, c)) => c.push(i),
            None => clusters.push((n, vec![i])),
        }
    }
    clusters.into_iter().map(|(_, c)| c).collect()
}

/// The centres of mass of the dynamic bodies of a contact of `a` and `b` along `normal` (from A to B), the one the
/// applied forces press harder into the other first.
fn centres(a: usize, b: usize, normal: Vector3<f64>, states: &[BodyState]) -> Vec<Point3<f64>> {
    let mut pressed: Vec<(f64, Point3<f64>)> = Vec::with_capacity(2);
    if let Some(s) = states.get(a).filter(|s| s.inv_mass > 0.0) {
        pressed.push((s.force.dot(&normal), s.position));
    }
    if let Some(s) = states.get(b).filter(|s| s.inv_mass > 0.0) {
        pressed.push((-s.force.dot(&normal), s.position));
    }
    if pressed.len() == 2 && pressed[1].0 > pressed[0].0 {
        pressed.swap(0, 1);
    }
    pressed.into_iter().map(|(_, p)| p).collect()
}

/// Indices of up to four of `points` starting from `first`, greedily maximising the area they span.
pub(crate) fn select(points: &[Point3<f64>], first: usize) -> Vec<usize> {
    let best = |score: &dyn Fn(&Point3<f64>) -> f64| {
        (0..points.len()).map(|k| (k, score(&points[k]))).fold((first, 0.0), |acc, s| if s.1 > acc.1 { s } else { acc })
    };
    let p0 = points[first];
    let (second, d) = best(&|p| (p - p0).norm_squared());
    if d == 0.0 {
        return vec![first];
    }
    let p1 = points[second];
    let (third, a) = best(&|p| (p1 - p0).cross(&(p - p0)).norm());
    if a == 0.0 {
        return vec![first, second];
    }
    let p2 = points[third];
    let n: Vector3<f64> = (p1 - p0).cross(&(p2 - p0)).normalize();
    // Area a point adds outside the triangle: the largest outward triangle it makes with an edge.
    let outside = |p: &Point3<f64>| {
        [(p0, p1), (p1, p2), (p2, p0)].iter().map(|(a, b)| -(b - a).cross(&(p - a)).dot(&n)).fold(0.0, f64::max)
    };
    let (fourth, added) = best(&outside);
    if added == 0.0 {
        vec![first, second, third]
    } else {
        vec![first, second, third, fourth]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_face_keeps_its_corners() {
        // the eight points of a clipped face: four corners and four edge midpoints of the unit square
        let pts: Vec<Point3<f64>> =
            [(0., 0.), (1., 0.), (1., 1.), (0., 1.), (0.5, 0.), (1., 0.5), (0.5, 1.), (0., 0.5)]
                .iter()
                .map(|&(x, y)| Point3::new(x, y, 0.0))
                .collect();
        let mut from_corner = select(&pts, 0);
        from_corner.sort();
        assert_eq!(from_corner, vec![0, 1, 2, 3]);
    }

    #[test]
    fn collinear_points_keep_the_two_ends() {
        let pts: Vec<Point3<f64>> = (0..6).map(|k| Point3::new(k as f64, 0.0, 0.0)).collect();
        assert_eq!(select(&pts, 2), vec![2, 5]);
    }
}

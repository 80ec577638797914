//! A closed triangle surface cut by a plane: the part on the plane's negative side, closed again by a cap on the
//! plane (the cut's outlines triangulated, holes kept), so that it is a closed surface still.

use crate::error::ShapeError;
use nalgebra::{Point3, Vector3};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::BTreeMap;

/// A closed surface being cut: its vertices and counter-clockwise triangles (seen from outside).
#[derive(Clone, Debug, Default)]
pub(crate) struct Surface {
    pub vertices: Vec<Point3<f64>>,
    pub triangles: Vec<[u32; 3]>,
}

/// Which side of the plane a vertex is on, within the cut's tolerance.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Below,
    On,
    Above,
}

impl Surface {
    /// The part of the surface where `normal . p <= offset`, closed by a cap on the plane; points within `tolerance`
    /// of the plane count as on it, and the cap's slivers (twice their area below `sliver`) are flipped away. An empty surface where nothing is below the plane; the surface itself where
    /// nothing is above it. An error where the cut's outline cannot be triangulated (outlines that cross: a
    /// surface that is not closed or crosses itself).
    pub fn below(
        &self,
        normal: &Vector3<f64>,
        offset: f64,
        tolerance: f64,
        sliver: f64,
    ) -> Result<Surface, ShapeError> {
        let distance: Vec<f64> = self.vertices.iter().map(|p| normal.dot(&p.coords) - offset).collect();
        let side: Vec<Side> = distance
            .iter()
            .map(|&d| {
                if d < -tolerance {
                    Side::Below
                } else if d > tolerance {
                    Side::Above
                } else {
                    Side::On
                }
            })
            .collect();
        if !side.contains(&Side::Above) {
            return Ok(self.clone());
        }
        if !side.contains(&Side::Below) {
            return Ok(Surface::default());
        }
        let mut out = Surface { vertices: self.vertices.clone(), triangles: Vec::new() };
        // each crossed edge's point on the plane, made once for both triangles that share the edge
        let mut crossings: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        for t in &self.triangles {
            let sides = t.map(|i| side[i as usize]);
            if !sides.contains(&Side::Above) {
                if sides.iter().all(|s| *s == Side::On) && self.normal(t).dot(normal) <= 0.0 {
                    continue; // a face on the plane with the solid above it: not part of the part below
                }
                out.triangles.push(*t);
                continue;
            }
            if !sides.contains(&Side::Below) {
                continue;
            }
            // the triangle clipped to the plane's negative side (Sutherland-Hodgman): three or four corners
            let mut polygon: Vec<u32> = Vec::with_capacity(4);
            for k in 0..3 {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                if side[i as usize] != Side::Above {
                    polygon.push(i);
                }
                let crossed = matches!(
                    (side[i as usize], side[j as usize]),
                    (Side::Below, Side::Above) | (Side::Above, Side::Below)
                );
                if crossed {
                    let key = (i.min(j), i.max(j));
                    let at = *crossings.entry(key).or_insert_with(|| {
                        let (a, b) = (key.0 as usize, key.1 as usize);
                        let s = distance[a] / (distance[a] - distance[b]);
                        out.vertices.push(self.vertices[a] + (self.vertices[b] - self.vertices[a]) * s);
                        (out.vertices.len() - 1) as u32
                    });
                    polygon.push(at);
                }
            }
            for k in 1..polygon.len() - 1 {
                out.triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
            }
        }
        out.cap(normal)?;
        out.flip_slivers(sliver);
        Ok(out)
    }

    /// The outward normal (not of unit length) of triangle `t`.
    fn normal(&self, t: &[u32; 3]) -> Vector3<f64> {
        let [a, b, c] = t.map(|i| self.vertices[i as usize]);
        (b - a).cross(&(c - a))
    }

    /// Closes the surface's open outlines, all on the plane of `normal`: each edge that only one triangle has is
    /// the edge of a cap, whose triangles (a constrained Delaunay triangulation of the outlines, the faces inside
    /// them kept) face along `normal`.
    fn cap(&mut self, normal: &Vector3<f64>) -> Result<(), ShapeError> {
        let mut edges: BTreeMap<(u32, u32), i32> = BTreeMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                *edges.entry((i.min(j), i.max(j))).or_insert(0) += if i < j { 1 } else { -1 };
            }
        }
        // the cap's edges: each open edge turned round (a triangle's edge i -> j is the cap's j -> i)
        let open: Vec<(u32, u32)> = edges
            .iter()
            .filter(|(_, &count)| count != 0)
            .map(|(&(i, j), &count)| if count > 0 { (j, i) } else { (i, j) })
            .collect();
        if open.is_empty() {
            return Ok(());
        }
        let seed = if normal.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
        let u = normal.cross(&seed).normalize();
        let v = normal.normalize().cross(&u);
        let flat = |i: u32| {
            let p = self.vertices[i as usize].coords;
            Point2::new(p.dot(&u), p.dot(&v))
        };
        let failed = |why: &str| ShapeError::new("mesh", format!("could not be cut: {why}"));
        let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> = ConstrainedDelaunayTriangulation::new();
        let mut index_of = BTreeMap::new();
        let mut handle_of = BTreeMap::new();
        for &(i, j) in &open {
            for k in [i, j] {
                if let std::collections::btree_map::Entry::Vacant(e) = handle_of.entry(k) {
                    let h = cdt.insert(flat(k)).map_err(|_| failed("a point of the cut is not finite"))?;
                    if index_of.insert(h, k).is_some() {
                        return Err(failed("two points of the cut at one place"));
                    }
                    e.insert(h);
                }
            }
        }
        for &(i, j) in &open {
            let (a, b) = (handle_of[&i], handle_of[&j]);
            if !cdt.can_add_constraint(a, b) {
                return Err(failed("its outlines cross (the surface is not closed, or crosses itself)"));
            }
            cdt.add_constraint(a, b);
        }
        // a face is inside the cap where it lies left of an outline's edge (the outlines run round the cap counter-
        // clockwise); the others take the side of the faces they meet across edges that are no outline's, and any
        // left over (none but in a cap of separate pieces) the outlines' winding round their centres
        let directed: std::collections::BTreeSet<(u32, u32)> = open.iter().copied().collect();
        let faces: Vec<_> = cdt.inner_faces().collect();
        let mut inside: Vec<Option<bool>> = vec![None; cdt.num_all_faces()];
        let mut queue = std::collections::VecDeque::new();
        for f in &faces {
            for e in f.adjacent_edges() {
                let (x, y) = (index_of[&e.from().fix()], index_of[&e.to().fix()]);
                let side = if directed.contains(&(x, y)) {
                    Some(true)
                } else if directed.contains(&(y, x)) {
                    Some(false)
                } else {
                    None
                };
                if side.is_some() && inside[f.fix().index()].is_none() {
                    inside[f.fix().index()] = side;
                    queue.push_back(*f);
                }
            }
        }
        while let Some(f) = queue.pop_front() {
            let side = inside[f.fix().index()];
            for e in f.adjacent_edges() {
                if cdt.is_constraint_edge(e.as_undirected().fix()) {
                    continue;
                }
                if let Some(g) = e.rev().face().as_inner() {
                    if inside[g.fix().index()].is_none() {
                        inside[g.fix().index()] = side;
                        queue.push_back(g);
                    }
                }
            }
        }
        let outline: Vec<(Point2<f64>, Point2<f64>)> = open.iter().map(|&(i, j)| (flat(i), flat(j))).collect();
        for f in &faces {
            let [a, b, c] = f.vertices().map(|h| index_of[&h.fix()]);
            let kept = inside[f.fix().index()].unwrap_or_else(|| {
                let [pa, pb, pc] = [a, b, c].map(flat);
                winding(&outline, Point2::new((pa.x + pb.x + pc.x) / 3.0, (pa.y + pb.y + pc.y) / 3.0)) > 0
            });
            if kept {
                self.triangles.push([a, b, c]);
            }
        }
        Ok(())
    }
}

impl Surface {
    /// Flips away slivers: a triangle of next to no area (twice its area at most `smallest`: three nearly collinear
    /// points of a cut across a flat face) has its longest edge flipped with the triangle across it, where both
    /// new triangles face as that one does. The surface stays closed and bounds the same solid to rounding.
    pub fn flip_slivers(&mut self, smallest: f64) {
        let mut stuck = vec![false; self.triangles.len()];
        for _ in 0..2 * self.triangles.len() {
            let found =
                (0..self.triangles.len()).find(|&i| !stuck[i] && self.normal(&self.triangles[i]).norm() <= smallest);
            let Some(s) = found else { return };
            let t = self.triangles[s];
            // the longest edge x -> y, and m the point across it
            let len = |k: usize| (self.vertices[t[(k + 1) % 3] as usize] - self.vertices[t[k] as usize]).norm();
            let k = (0..3).max_by(|&a, &b| len(a).total_cmp(&len(b))).expect("three edges");
            let (x, y, m) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let across = self.triangles.iter().position(|u| (0..3).any(|q| u[q] == y && u[(q + 1) % 3] == x));
            let flipped = across.and_then(|n| {
                let u = self.triangles[n];
                let w = (0..3).map(|q| u[q]).find(|&v| v != x && v != y)?;
                let facing = self.normal(&u);
                let (first, second) = ([x, w, m], [w, y, m]);
                let fits = self.normal(&first).dot(&facing) > 0.0 && self.normal(&second).dot(&facing) > 0.0;
                fits.then_some((n, first, second))
            });
            match flipped {
                Some((n, first, second)) => {
                    self.triangles[s] = first;
                    self.triangles[n] = second;
                }
                None => stuck[s] = true,
            }
        }
    }
}

/// How many times the closed outlines (directed segments) wind counter-clockwise round `p`.
fn winding(outline: &[(Point2<f64>, Point2<f64>)], p: Point2<f64>) -> i32 {
    let mut turns = 0;
    for (a, b) in outline {
        let left = (b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y);
        if a.y <= p.y && b.y > p.y && left > 0.0 {
            turns += 1;
        } else if b.y <= p.y && a.y > p.y && left < 0.0 {
            turns -= 1;
        }
    }
    turns
}

#[cfg(test)]
mod tests {
    use super::Surface;
    use crate::shape::Shape;
    use nalgebra::Vector3;

    /// The volume a closed surface bounds (the divergence theorem over its triangles).
    fn volume(s: &Surface) -> f64 {
        s.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| s.vertices[i as usize].coords);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }

    /// Whether every edge is met once each way (closed and consistently wound).
    fn closed(s: &Surface) -> bool {
        let mut edges = std::collections::BTreeMap::new();
        for t in &s.triangles {
            for k in 0..3 {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                *edges.entry((i.min(j), i.max(j))).or_insert(0i32) += if i < j { 1 } else { -1 };
            }
        }
        edges.values().all(|&c| c == 0)
    }

    #[test]
    fn a_box_cut_again_and_again_stays_closed_and_its_two_sides_make_it_whole() {
        // seeded planes through a 0.6 x 0.4 x 0.2 box (whose faces are two triangles each: cuts across them meet
        // nearly collinear points, the caps' hard case); each part closed, no sliver left, and the parts on the
        // two sides of a plane adding up to the part cut (1e-15 of the box's volume: rounding)
        let (v, t) = Shape::cuboid(Vector3::new(0.3, 0.2, 0.1)).unwrap().triangle_mesh(8, 1.0);
        let whole = Surface { vertices: v, triangles: t };
        let mut seed = 1u64;
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
        };
        for _ in 0..300 {
            let mut part = whole.clone();
            for _ in 0..6 {
                let n = Vector3::new(random(), random(), random()).normalize();
                let offset = random() * 0.1;
                let below = part.below(&n, offset, 1e-11, 1e-13).unwrap();
                let above = part.below(&-n, -offset, 1e-11, 1e-13).unwrap();
                for side in [&below, &above] {
                    assert!(closed(side));
                    assert!(side.triangles.iter().all(|t| side.normal(t).norm() > 1e-13), "a sliver is left");
                }
                assert!((volume(&below) + volume(&above) - volume(&part)).abs() < 1e-15 * 0.048);
                if below.triangles.is_empty() {
                    break;
                }
                part = below;
            }
        }
    }
}

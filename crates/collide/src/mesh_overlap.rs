//! Whether two closed meshes' solids overlap, not only touch: a point lies strictly inside both, by the generalized
//! winding number (the solid angle a mesh's triangles subtend, over 4 pi: 1 inside, 0 outside, a fraction on the
//! surface). The points tried: the centres of a grid of cells over where the two boxes overlap (two solids that
//! cross, or one inside the other, share some cell centre unless their shared part is thinner than a cell), and each
//! mesh's vertices there (a thin overlap has the vertices of one inside the other). Solids that share a face have no
//! such point. What a file's meshes merged into one would count twice in the mass.

use crate::surface_mesh::Mesh;
use nalgebra::{Point3, Vector3};

/// A point counts as inside at a winding number above this (on a flat face it is 1/2, at a convex edge or vertex
/// less; only a point exactly at a deep concave corner comes near 1 without being inside).
const INSIDE: f64 = 0.99;
/// Cells along each axis of the grid over the boxes' overlap.
const CELLS: usize = 6;

/// Whether some point lies strictly inside both `a` and `b`.
pub(crate) fn solids_overlap(a: &Mesh, b: &Mesh) -> bool {
    let ((lo_a, hi_a), (lo_b, hi_b)) = (bounds(a), bounds(b));
    let (lo, hi) = (lo_a.sup(&lo_b), hi_a.inf(&hi_b));
    if (0..3).any(|i| hi[i] <= lo[i]) {
        return false;
    }
    let inside_both = |p: &Point3<f64>| winding(a, p) > INSIDE && winding(b, p) > INSIDE;
    let cell = (hi - lo) / CELLS as f64;
    let centres = (0..CELLS * CELLS * CELLS).map(|k| {
        let index = Vector3::new(k % CELLS, k / CELLS % CELLS, k / (CELLS * CELLS)).map(|i| i as f64 + 0.5);
        Point3::from(lo + cell.component_mul(&index))
    });
    let within = |p: &&Point3<f64>| (0..3).all(|i| lo[i] < p[i] && p[i] < hi[i]);
    let vertices = a.vertices().iter().chain(b.vertices()).filter(within).copied();
    centres.chain(vertices).any(|p| inside_both(&p))
}

pub(crate) fn bounds(m: &Mesh) -> (Vector3<f64>, Vector3<f64>) {
    m.vertices().iter().fold((Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY)), |(lo, hi), p| {
        (lo.inf(&p.coords), hi.sup(&p.coords))
    })
}

/// The generalized winding number of closed mesh `m` about `p` (Van Oosterom and Strackee's solid angle of each
/// triangle, summed, over 4 pi).
pub(crate) fn winding(m: &Mesh, p: &Point3<f64>) -> f64 {
    let v = m.vertices();
    let total: f64 = m
        .triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| v[k as usize] - p);
            let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
            let numerator = a.dot(&b.cross(&c));
            let denominator = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::solids_overlap;
    use crate::shape::Shape;
    use crate::surface_mesh::Mesh;
    use nalgebra::{Point3, Vector3};

    /// A box of half extents `h` centred at `c`, as a closed mesh (the box shape's own triangles, moved).
    fn cuboid(c: [f64; 3], h: [f64; 3]) -> Mesh {
        let (v, t) = Shape::cuboid(Vector3::from(h)).unwrap().triangle_mesh(3, 1.0);
        let moved: Vec<Point3<f64>> = v.iter().map(|p| p + Vector3::from(c)).collect();
        Mesh::new(&moved, &t, "box").unwrap()
    }

    #[test]
    fn crossing_nested_and_apart_solids_are_told_from_touching_ones() {
        let unit = cuboid([0.0; 3], [0.5; 3]);
        // a plus sign: no vertex of either inside the other
        let bar_x = cuboid([0.0; 3], [1.0, 0.1, 0.1]);
        let bar_y = cuboid([0.0; 3], [0.1, 1.0, 0.1]);
        assert!(solids_overlap(&bar_x, &bar_y), "crossing bars");
        assert!(solids_overlap(&unit, &cuboid([0.0; 3], [0.1; 3])), "one inside the other");
        assert!(solids_overlap(&unit, &cuboid([0.9, 0.0, 0.0], [0.5; 3])), "a tenth shared");
        assert!(!solids_overlap(&unit, &cuboid([1.0, 0.0, 0.0], [0.5; 3])), "sharing a face");
        assert!(!solids_overlap(&unit, &cuboid([1.0, 0.3, 0.2], [0.5; 3])), "touching on part of a face");
        assert!(!solids_overlap(&unit, &cuboid([3.0, 0.0, 0.0], [0.5; 3])), "apart");
        // an L of two boxes that touch along part of a face
        let foot = cuboid([0.0, 0.0, -0.4], [1.0, 0.1, 0.1]);
        let leg = cuboid([-0.9, 0.0, 0.2], [0.1, 0.1, 0.5]);
        assert!(!solids_overlap(&foot, &leg), "an L");
        // a thin sliver shared (thinner than a grid cell): a vertex of one is inside the other
        assert!(solids_overlap(&unit, &cuboid([0.0, 0.0, 0.99], [0.3, 0.3, 0.5])), "a sliver");
    }
}

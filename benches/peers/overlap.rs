//! The deepest overlap of a scene of boxes resting on the ground z = 0, computed exactly from the poses the same way
//! for every engine (each peer includes this file): for each pair of boxes whose bounding boxes meet, the
//! separating-axis depth over the 15 axes of two boxes (the least push that parts them, exact for convex
//! polyhedra), and for each box how far its lowest corner is below the ground. An engine's own contact manifolds
//! are not used: Rapier keeps a pair's manifold for up to 5 cm of motion, and its distances are then stale.

use nalgebra::{Isometry3, Vector3};

/// A box: half extents and pose.
pub type Boxed = (Vector3<f64>, Isometry3<f64>);

/// How deep two boxes overlap (0 if they do not).
pub fn box_depth((ha, pa): &Boxed, (hb, pb): &Boxed) -> f64 {
    let (ra, rb) = (pa.rotation.to_rotation_matrix(), pb.rotation.to_rotation_matrix());
    let a: [Vector3<f64>; 3] = std::array::from_fn(|i| ra.matrix().column(i).into_owned());
    let b: [Vector3<f64>; 3] = std::array::from_fn(|i| rb.matrix().column(i).into_owned());
    let t = pb.translation.vector - pa.translation.vector;
    let mut depth = f64::INFINITY;
    let mut axes: Vec<Vector3<f64>> = a.iter().chain(&b).copied().collect();
    for x in &a {
        for y in &b {
            let c = x.cross(y);
            // parallel edges give no axis of their own (a face normal covers them)
            if c.norm() > 1e-9 {
                axes.push(c.normalize());
            }
        }
    }
    for l in axes {
        let reach = |h: &Vector3<f64>, e: &[Vector3<f64>; 3]| (0..3).map(|i| h[i] * e[i].dot(&l).abs()).sum::<f64>();
        let overlap = reach(ha, &a) + reach(hb, &b) - t.dot(&l).abs();
        if overlap <= 0.0 {
            return 0.0;
        }
        depth = depth.min(overlap);
    }
    depth
}

/// How far a box's lowest corner is below z = 0 (0 if none is).
pub fn ground_depth((h, p): &Boxed) -> f64 {
    let r = p.rotation.to_rotation_matrix();
    let reach: f64 = (0..3).map(|i| h[i] * r.matrix()[(2, i)].abs()).sum();
    (reach - p.translation.vector.z).max(0.0)
}

/// The deepest overlap among `boxes` and the ground z = 0: bounding boxes swept along x, pairs that meet tested.
pub fn deepest(boxes: &[Boxed]) -> f64 {
    let bounds: Vec<(Vector3<f64>, Vector3<f64>)> = boxes
        .iter()
        .map(|(h, p)| {
            let r = p.rotation.to_rotation_matrix();
            let reach = Vector3::from_fn(|k, _| (0..3).map(|i| h[i] * r.matrix()[(k, i)].abs()).sum());
            (p.translation.vector - reach, p.translation.vector + reach)
        })
        .collect();
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&i, &j| bounds[i].0.x.total_cmp(&bounds[j].0.x));
    let mut worst = boxes.iter().map(ground_depth).fold(0.0, f64::max);
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if bounds[j].0.x > bounds[i].1.x {
                break;
            }
            let meet = (1..3).all(|c| bounds[j].0[c] <= bounds[i].1[c] && bounds[i].0[c] <= bounds[j].1[c]);
            if meet {
                worst = worst.max(box_depth(&boxes[i], &boxes[j]));
            }
        }
    }
    worst
}

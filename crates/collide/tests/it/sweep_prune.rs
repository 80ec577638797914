//! Property tests of the sort-and-sweep broad phase: on many random scenes (including boxes that touch exactly,
//! zero-size boxes, unbounded boxes, and scenes that move between calls) it reports exactly the pairs brute force does.

use crate::common;

use common::Rng;
use nalgebra::{Point3, Vector3};
use tumble_collide::{brute_force_pairs, Aabb, SortAndSweep};

fn sorted(mut v: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    v.sort_unstable();
    v
}

/// Boxes with corners on an integer grid, so that many touch exactly along a face, an edge or a corner, and some
/// have zero size on one or more axes.
fn grid_scene(rng: &mut Rng, n: usize, cells: u64) -> Vec<Aabb> {
    (0..n)
        .map(|_| {
            let lo = Vector3::new(rng.below(cells) as f64, rng.below(cells) as f64, rng.below(cells) as f64);
            let size = Vector3::new(rng.below(3) as f64, rng.below(3) as f64, rng.below(3) as f64);
            Aabb::new(Point3::from(lo), Point3::from(lo + size)).unwrap()
        })
        .collect()
}

/// Boxes of random real sizes spread unevenly (one axis much longer), so the sweep axis matters.
fn spread_scene(rng: &mut Rng, n: usize) -> Vec<Aabb> {
    let stretch = Vector3::new(rng.range(1.0, 40.0), rng.range(1.0, 40.0), rng.range(1.0, 40.0));
    (0..n)
        .map(|_| {
            let c = Point3::from(rng.vector(1.0).component_mul(&stretch));
            let h = Vector3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            Aabb::new(c - h, c + h).unwrap()
        })
        .collect()
}

fn check(sap: &mut SortAndSweep, boxes: &[Aabb], what: &str) {
    let got = sorted(sap.update(boxes).unwrap().to_vec());
    assert_eq!(got, sorted(brute_force_pairs(boxes)), "{what}: sweep and brute force disagree");
    assert!(got.iter().all(|&(i, j)| i < j), "{what}: pairs must be (i, j) with i < j");
}

#[test]
fn sweep_equals_brute_force_on_grid_scenes_with_touching_and_zero_size_boxes() {
    let mut rng = Rng(1);
    let mut total = 0;
    for scene in 0..300 {
        let n = 1 + rng.below(120) as usize;
        let cells = 1 + rng.below(12);
        let boxes = grid_scene(&mut rng, n, cells);
        total += brute_force_pairs(&boxes).len();
        check(&mut SortAndSweep::new(), &boxes, &format!("grid scene {scene}"));
    }
    assert!(total > 10_000, "the scenes must produce many pairs to mean anything, got {total}");
}

#[test]
fn sweep_equals_brute_force_on_scenes_that_move_between_calls() {
    let mut rng = Rng(2);
    for scene in 0..60 {
        let mut sap = SortAndSweep::new();
        let n = 50 + rng.below(400) as usize;
        let mut boxes = spread_scene(&mut rng, n);
        check(&mut sap, &boxes, &format!("scene {scene} start"));
        for step in 0..20 {
            // Mostly small moves (coherence), sometimes a jump, sometimes a whole-scene squash that changes the axis.
            let squash = rng.below(10) == 0;
            let axis_scale = Vector3::new(rng.range(0.05, 1.0), 1.0, rng.range(0.05, 1.0));
            for b in &mut boxes {
                let shift = if rng.below(50) == 0 { rng.vector(20.0) } else { rng.vector(0.05) };
                let (mut lo, mut hi) = (b.min + shift, b.max + shift);
                if squash {
                    lo = Point3::from(lo.coords.component_mul(&axis_scale));
                    hi = Point3::from(hi.coords.component_mul(&axis_scale));
                }
                *b = Aabb::new(lo, hi).unwrap();
            }
            check(&mut sap, &boxes, &format!("scene {scene} step {step}"));
        }
    }
}

#[test]
fn sweep_handles_unbounded_boxes_and_changing_counts() {
    let mut rng = Rng(3);
    let mut sap = SortAndSweep::new();
    for round in 0..40 {
        let n = 20 + rng.below(100) as usize;
        let mut boxes = spread_scene(&mut rng, n);
        // a ground: unbounded except above z = 0
        let inf = f64::INFINITY;
        boxes.push(Aabb::new(Point3::new(-inf, -inf, -inf), Point3::new(inf, inf, 0.0)).unwrap());
        check(&mut sap, &boxes, &format!("round {round}"));
    }
}

#[test]
fn sweep_equals_brute_force_when_boxes_grow_past_and_shrink_below_the_column_width() {
    // Boxes that become huge or unbounded are swept differently from the rest (tested against every box): switching
    // back and forth between the two must not lose or duplicate a pair.
    let mut rng = Rng(8);
    for scene in 0..30 {
        let mut sap = SortAndSweep::new();
        let n = 100 + rng.below(300) as usize;
        let mut boxes = spread_scene(&mut rng, n);
        for step in 0..30 {
            for b in &mut boxes {
                let c = b.center() + rng.vector(0.1);
                let h = match rng.below(40) {
                    0 => Vector3::repeat(rng.range(10.0, 60.0)),
                    1 => Vector3::new(f64::INFINITY, rng.range(0.0, 1.0), 0.5),
                    _ => Vector3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0)),
                };
                let c = if c.iter().all(|x| x.is_finite()) { c } else { Point3::from(rng.vector(20.0)) };
                *b = Aabb::new(c - h, c + h).unwrap();
            }
            check(&mut sap, &boxes, &format!("scene {scene} step {step}"));
        }
    }
}

#[test]
fn coherent_scene_needs_few_swaps_and_no_full_sort() {
    let mut rng = Rng(4);
    let mut boxes = spread_scene(&mut rng, 2000);
    let mut sap = SortAndSweep::new();
    sap.update(&boxes).unwrap();
    assert!(sap.stats().full_sort, "the first call sorts from scratch");
    sap.update(&boxes).unwrap();
    assert_eq!((sap.stats().swaps, sap.stats().full_sort), (0, false), "an unchanged scene needs no swaps");
    for b in &mut boxes {
        let s = rng.vector(1e-3);
        *b = Aabb::new(b.min + s, b.max + s).unwrap();
    }
    sap.update(&boxes).unwrap();
    let stats = sap.stats();
    // Moves of 1e-3 among 2000 boxes spread over tens of units reorder only a few neighbours.
    assert!(!stats.full_sort && stats.swaps < boxes.len(), "{stats:?}");
}

#[test]
fn sweep_axis_follows_the_spread() {
    let mut rng = Rng(5);
    let boxes: Vec<Aabb> = (0..500)
        .map(|_| {
            let c = Point3::new(rng.range(-1.0, 1.0), rng.range(-100.0, 100.0), rng.range(-1.0, 1.0));
            Aabb::new(c, c + Vector3::repeat(0.1)).unwrap()
        })
        .collect();
    let mut sap = SortAndSweep::new();
    sap.update(&boxes).unwrap();
    assert_eq!(sap.axis(), 1, "the centres spread along y");
}

#[test]
fn a_bad_box_is_refused_and_leaves_the_broad_phase_as_it_was() {
    let mut rng = Rng(6);
    let boxes = spread_scene(&mut rng, 100);
    let mut sap = SortAndSweep::new();
    let before = sap.update(&boxes).unwrap().to_vec();
    let mut bad = boxes.clone();
    bad[17] = Aabb { min: Point3::new(0.0, f64::NAN, 0.0), max: Point3::new(1.0, 1.0, 1.0) };
    let err = sap.update(&bad).unwrap_err();
    assert_eq!(err.name, "boxes");
    assert!(err.reason.contains("box 17"), "{err}");
    assert_eq!(sap.pairs(), &before[..]);
    bad[17] = Aabb { min: Point3::new(2.0, 0.0, 0.0), max: Point3::new(1.0, 1.0, 1.0) };
    assert_eq!(sap.update(&bad).unwrap_err().name, "boxes");
}

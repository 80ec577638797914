//! Broad phase on 1,000, 10,000 and 100,000 moving boxes: our sort-and-sweep against parry's BVH, both reporting
//! every overlapping pair each update, in the same run.
//!
//! Run: `cargo bench -p tumble-collide --bench broad_phase`. The scene: boxes of half size 0.2 to 0.6 scattered at a
//! density of 0.25 per unit volume (about one overlapping pair per box), each moving at about 1 m/s and bouncing off
//! the walls, advanced by 1/60 s per update; eight precomputed frames are played forward and back so that every
//! update is a small move. parry's BVH is updated the way Rapier's broad phase does it (update the leaves, optimise
//! incrementally, refit) and then traversed against itself for all pairs, without change detection.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nalgebra::{Point3, Vector3};
use parry3d_f64::bounding_volume::Aabb as ParryAabb;
use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use std::hint::black_box;
use tumble_collide::{Aabb, SortAndSweep, SplitMix as Rng};

const FRAMES: usize = 8;

/// `FRAMES` successive frames of n moving boxes.
fn frames(n: usize) -> Vec<Vec<Aabb>> {
    let mut rng = Rng(n as u64);
    let side = (n as f64 / 0.25).cbrt();
    let mut centres: Vec<Vector3<f64>> =
        (0..n).map(|_| Vector3::new(rng.uniform(), rng.uniform(), rng.uniform()) * side).collect();
    let mut velocities: Vec<Vector3<f64>> =
        (0..n).map(|_| Vector3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 2.0).collect();
    let halves: Vec<f64> = (0..n).map(|_| 0.2 + 0.4 * rng.uniform()).collect();
    let mut out = Vec::with_capacity(FRAMES);
    for _ in 0..FRAMES {
        out.push(
            centres
                .iter()
                .zip(&halves)
                .map(|(c, h)| Aabb {
                    min: Point3::from(c - Vector3::repeat(*h)),
                    max: Point3::from(c + Vector3::repeat(*h)),
                })
                .collect(),
        );
        for (c, v) in centres.iter_mut().zip(velocities.iter_mut()) {
            *c += *v / 60.0;
            for k in 0..3 {
                if c[k] < 0.0 || c[k] > side {
                    v[k] = -v[k];
                }
            }
        }
    }
    out
}

/// Frame index of update `i`: 0, 1, ..., 7, 6, ..., 1, 0, 1, ... (every update a small move).
fn ping_pong(i: usize) -> usize {
    let p = i % (2 * FRAMES - 2);
    if p < FRAMES {
        p
    } else {
        2 * FRAMES - 2 - p
    }
}

fn to_parry(b: &Aabb) -> ParryAabb {
    ParryAabb::new(Vector::new(b.min.x, b.min.y, b.min.z), Vector::new(b.max.x, b.max.y, b.max.z))
}

struct ParryBroadPhase {
    tree: Bvh,
    workspace: BvhWorkspace,
    pairs: Vec<(u32, u32)>,
}

impl ParryBroadPhase {
    fn new(boxes: &[Aabb]) -> Self {
        let leaves: Vec<ParryAabb> = boxes.iter().map(to_parry).collect();
        ParryBroadPhase {
            tree: Bvh::from_leaves(BvhBuildStrategy::default(), &leaves),
            workspace: BvhWorkspace::default(),
            pairs: Vec::new(),
        }
    }

    fn update(&mut self, boxes: &[Aabb]) -> usize {
        for (i, b) in boxes.iter().enumerate() {
            self.tree.insert_or_update_partially(to_parry(b), i as u32, 0.0);
        }
        self.tree.optimize_incremental(&mut self.workspace);
        self.tree.refit(&mut self.workspace);
        self.pairs.clear();
        let pairs = &mut self.pairs;
        self.tree.traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |a, b| pairs.push((a.min(b), a.max(b))));
        self.pairs.len()
    }
}

fn broad_phase(c: &mut Criterion) {
    let mut g = c.benchmark_group("broad_phase");
    g.sample_size(20);
    for n in [1_000, 10_000, 100_000] {
        let frames = frames(n);
        // Both must find the same pairs, or the comparison means nothing.
        let mut sap = SortAndSweep::new();
        let mut ours = sap.update(&frames[0]).unwrap().to_vec();
        let mut peer = ParryBroadPhase::new(&frames[0]);
        peer.update(&frames[0]);
        ours.sort_unstable();
        peer.pairs.sort_unstable();
        assert_eq!(ours, peer.pairs, "sort-and-sweep and parry's BVH disagree on {n} boxes");
        println!("{n} boxes: {} pairs, {:?}", ours.len(), sap.stats());
        g.bench_with_input(BenchmarkId::new("sort_and_sweep", n), &frames, |b, frames| {
            let mut i = 0;
            b.iter(|| {
                i += 1;
                black_box(sap.update(&frames[ping_pong(i)]).unwrap().len())
            })
        });
        g.bench_with_input(BenchmarkId::new("parry_bvh", n), &frames, |b, frames| {
            let mut i = 0;
            b.iter(|| {
                i += 1;
                black_box(peer.update(&frames[ping_pong(i)]))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, broad_phase);
criterion_main!(benches);

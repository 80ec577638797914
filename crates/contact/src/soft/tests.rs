//! Unit test of the soft step: its AVX2 sweeps give the same bits as the portable ones.

use super::*;
use nalgebra::{Matrix3, Point3};
use std::sync::atomic::Ordering;

#[test]
fn the_portable_and_the_avx2_sweeps_give_the_same_bits() {
    // Seeded random stacks of one to four boxes (masses 1 to 1000 kg, random velocities, spins, gaps,
    // materials and warm starts), each box also touching the next stack's (one island across stacks, so
    // bundles fill with rows of many colours). On a processor without AVX2 both runs take the portable path.
    let mut seed = 77u64;
    let mut next = move |lo: f64, hi: f64| {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let (mut contacts, mut warm) = (Vec::new(), Vec::new());
    let mut last_stack: Vec<usize> = Vec::new();
    for s in 0..40 {
        let x = 1.0 * s as f64;
        let mut stack = Vec::new();
        for k in 0..(1 + (next(0.0, 4.0) as usize)) {
            let m = 10f64.powf(next(0.0, 3.0));
            let mut b = BodyState::rigid(m, Matrix3::identity() * (m / 6.0), Point3::new(x, 0.0, 0.5 + k as f64));
            b.force = Vector3::new(0.0, 0.0, -m * 9.81);
            b.velocity = Vector3::new(next(-1.0, 1.0), next(-1.0, 1.0), next(-1.0, 0.0));
            b.angular_velocity = Vector3::new(next(-1.0, 1.0), next(-1.0, 1.0), next(-1.0, 1.0));
            bodies.push(b);
            let me = bodies.len() - 1;
            let below = stack.last().copied().unwrap_or(0);
            let mut touch = |a: usize, p: Point3<f64>, n: Vector3<f64>| {
                let c = Contact::new(a, me, p, nalgebra::Unit::new_normalize(n));
                contacts.push(
                    c.with_friction(next(0.0, 1.0)).with_restitution(next(0.0, 0.5)).with_distance(next(-1e-3, 1e-3)),
                );
                warm.push(SoftImpulse {
                    normal: next(0.0, m * 9.81 / 60.0),
                    tangent: Vector3::new(next(-1.0, 1.0), next(-1.0, 1.0), 0.0),
                });
            };
            for (cx, cy) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                touch(below, Point3::new(x + cx, cy, k as f64), Vector3::z());
            }
            if let Some(&left) = last_stack.get(k) {
                touch(left, Point3::new(x - 0.5, 0.0, 0.5 + k as f64), Vector3::x());
            }
            stack.push(me);
        }
        last_stack = stack;
    }
    let settings = SoftSettings { threads: 1, ..Default::default() };
    bundle::PORTABLE.store(false, Ordering::Relaxed);
    let fastest = soft_step(&SoftProblem::new(&bodies, &contacts, &warm), 1.0 / 60.0, &settings).unwrap();
    bundle::PORTABLE.store(true, Ordering::Relaxed);
    let portable = soft_step(&SoftProblem::new(&bodies, &contacts, &warm), 1.0 / 60.0, &settings).unwrap();
    bundle::PORTABLE.store(false, Ordering::Relaxed);
    assert_eq!(fastest, portable);
    assert_eq!(fastest.islands, 1);
}

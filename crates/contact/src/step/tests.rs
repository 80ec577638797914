//! The velocity step's island split held to the joined program's answer.

use super::*;
use nalgebra::{Matrix3, Point3, Unit};

/// A seeded uniform number in [0, 1).
fn uniform(state: &mut u64) -> f64 {
    *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn islands_solved_apart_give_the_joined_programs_answer() {
    // Seeded rows of boxes on a floor (random masses 0.1-10 kg, sizes, spins, speeds toward or away from their
    // neighbours, gaps 0-5 mm, friction 0-1, lagged floor bounds): each box's contacts with the next are apart
    // and unbound, so the split solves the boxes apart and joins them where an answer would close a gap. The
    // joined program's velocities are unique (its objective is strictly convex in them): the split's must equal
    // them to the solver's accuracy (its residual tolerance of the step's velocity scale; 1e-6 of the largest
    // speed allows the two answers' own errors).
    let (mut split_somewhere, mut joined_somewhere) = (false, false);
    for seed in 0..60u64 {
        let mut r = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5;
        let h = 1.0 / 240.0;
        let n = 2 + (uniform(&mut r) * 6.0) as usize;
        let mut bodies = vec![BodyState::fixed(Point3::origin())];
        let mut contacts = Vec::new();
        let mut bounds = Vec::new();
        let mut x = 0.0;
        for k in 0..n {
            let (m, half) = (0.1 + 9.9 * uniform(&mut r), 0.05 + 0.1 * uniform(&mut r));
            let inertia = Matrix3::identity() * (m * half * half * 2.0 / 3.0);
            let speed = 2.0 * (uniform(&mut r) - 0.5);
            let mut b = BodyState::rigid(m, inertia, Point3::new(x + half, 0.0, half));
            b.velocity = Vector3::new(speed, 0.0, -0.01 * uniform(&mut r));
            b.angular_velocity = Vector3::new(0.0, 2.0 * (uniform(&mut r) - 0.5), 0.0);
            b.force = Vector3::new(0.0, 0.0, -9.81 * m);
            let mu = uniform(&mut r);
            for dy in [-half, half] {
                let point = Point3::new(x + half, dy, 0.0);
                contacts.push(Contact::new(0, k + 1, point, Unit::new_normalize(Vector3::z())).with_friction(mu));
                bounds.push(9.81 * m * h * 0.5);
            }
            if k + 1 < n {
                let gap = 0.005 * uniform(&mut r);
                let point = Point3::new(x + 2.0 * half, 0.0, half);
                let c =
                    Contact { distance: gap, ..Contact::new(k + 1, k + 2, point, Unit::new_normalize(Vector3::x())) };
                contacts.push(c.with_friction(mu));
                bounds.push(0.0);
            }
            x += 2.0 * half + 0.005 * uniform(&mut r);
            bodies.push(b);
        }
        // the gaps are the contacts' own: x above only spaces the boxes for the points
        let problem = VelocityProblem::new(&bodies, &contacts).lagged(&bounds);
        let settings = StepSettings { threads: 1, ..StepSettings::new(h) };
        let split = step(&problem, &settings, true).unwrap();
        let joined = step(&problem, &settings, false).unwrap();
        let scale = bodies.iter().map(|b| b.velocity.norm() + 9.81 * h).fold(0.0, f64::max);
        for (k, (a, b)) in split.velocities.iter().zip(&joined.velocities).enumerate() {
            let d = (a.linear - b.linear).norm() + (a.angular - b.angular).norm() * 0.15;
            assert!(d <= 1e-6 * scale, "seed {seed}, body {k}: {d:e} of {scale:e}");
        }
        split_somewhere |= split.islands > joined.islands;
        joined_somewhere |= split.islands < n && joined.islands == 1;
    }
    assert!(split_somewhere && joined_somewhere, "some rows solve apart, and some join where a gap closes");
}

//! The velocity step's own Newton solver against clarabel, the reference, on seeded random islands: towers and trees
//! of 1 to 30 rigid bodies and particles with masses from 1e-2 to 1e2 kg, random inertias, velocities, frictions,
//! restitutions, gaps and lagged normal impulses, with and without joint rows. Both must give the same velocities,
//! and (where the impulses are fixed by the velocities) the same impulses, to the program's tolerance; and the
//! Newton method must answer every island itself.
#![cfg(feature = "clarabel")]

use crate::common;

use nalgebra::{Matrix3, Point3, Unit, Vector3};
use tumble_contact::{
    velocity_step, BilateralKind, BilateralRow, BodyState, Contact, StepMethod, StepSettings, VelocityProblem,
    VelocityStep,
};

const G: f64 = 9.81;
const H: f64 = 0.01;

struct Island {
    bodies: Vec<BodyState>,
    contacts: Vec<Contact>,
    lagged: Vec<f64>,
    joints: Vec<BilateralRow>,
    /// Each body's parent in the tree of contacts (the net wrench between a body and its parent is fixed by the
    /// velocities when the contacts form a tree and no joint closes a loop).
    parent: Vec<usize>,
}

/// A random island: body 0 is the static ground; body k rests on a random earlier one through 1-4 points.
fn random_island(seed: u64, joints: bool) -> Island {
    let mut u = common::uniform(seed);
    let n = 1 + (u() * 30.0) as usize;
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let mut parent = vec![0];
    let mut contacts = Vec::new();
    let mut lagged = Vec::new();
    for k in 1..=n {
        let m = 10f64.powf(-2.0 + 4.0 * u());
        let p = Point3::new(u() - 0.5, u() - 0.5, k as f64 * 0.3);
        let mut b = if u() < 0.2 {
            BodyState::particle(m, p, Vector3::zeros())
        } else {
            let i = Matrix3::from_diagonal(&Vector3::new(0.01 + u(), 0.01 + u(), 0.01 + u())) * (m * 0.05);
            let mut b = BodyState::rigid(m, i, p);
            b.angular_velocity = Vector3::new(u() - 0.5, u() - 0.5, u() - 0.5) * 2.0;
            b
        };
        b.velocity = Vector3::new(u() - 0.5, u() - 0.5, u() - 0.5) * 2.0;
        b.force = Vector3::new(0.0, 0.0, -m * G);
        let on = (u() * k as f64) as usize;
        parent.push(on);
        let normal = Unit::new_normalize(Vector3::new(0.5 * (u() - 0.5), 0.5 * (u() - 0.5), 1.0));
        let (mu, e) = (if u() < 0.2 { 0.0 } else { 1.2 * u() }, if u() < 0.5 { 0.0 } else { 0.5 * u() });
        let points = if b.rotates() { 1 + (u() * 4.0) as usize } else { 1 };
        for _ in 0..points {
            let at = p + Vector3::new(u() - 0.5, u() - 0.5, -0.1) * 0.2;
            let gap = 1e-3 * (u() - 0.2);
            contacts.push(Contact::new(on, k, at, normal).with_friction(mu).with_restitution(e).with_distance(gap));
            lagged.push(if u() < 0.3 { 0.0 } else { 2.0 * u() * m * G * H / points as f64 });
        }
        bodies.push(b);
    }
    let mut rows = Vec::new();
    if joints && n >= 2 {
        for _ in 0..1 + (u() * 3.0) as usize {
            let a = 1 + (u() * n as f64) as usize % n;
            let b = 1 + (a + (u() * (n - 1) as f64) as usize) % n;
            if a == b {
                continue;
            }
            let dir = |u: &mut dyn FnMut() -> f64| Vector3::new(u() - 0.5, u() - 0.5, u() - 0.5);
            let (lin, ang_a, ang_b) = (dir(&mut u), dir(&mut u), dir(&mut u));
            let (ang_a, ang_b) = (
                if bodies[a].rotates() { ang_a } else { Vector3::zeros() },
                if bodies[b].rotates() { ang_b } else { Vector3::zeros() },
            );
            let kind = match (u() * 3.0) as usize {
                0 => BilateralKind::Equal,
                1 => BilateralKind::AtLeast,
                _ => BilateralKind::Motor { max_impulse: u() * 0.1 },
            };
            rows.push(BilateralRow { a, b, lin, ang_a, ang_b, speed: 0.1 * (u() - 0.5), kind });
        }
    }
    Island { bodies, contacts, lagged, joints: rows, parent }
}

fn solve(island: &Island, method: StepMethod) -> VelocityStep {
    let problem =
        VelocityProblem::new(&island.bodies, &island.contacts).lagged(&island.lagged).bilateral(&island.joints);
    velocity_step(&problem, &StepSettings { method, threads: 1, ..StepSettings::new(H) }).unwrap()
}

/// The island's velocity scale: its free speeds and g h.
fn speed_scale(island: &Island) -> f64 {
    island.bodies.iter().map(|b| b.velocity.norm() + b.angular_velocity.norm()).fold(G * H, f64::max)
}

#[test]
fn newton_and_clarabel_agree_on_random_islands() {
    let (mut worst_v, mut worst_p) = (0.0f64, 0.0f64);
    let (mut newton, mut calls) = (0, 0);
    for seed in 0..200u64 {
        let island = random_island(seed, seed % 2 == 1);
        let (ours, reference) = (solve(&island, StepMethod::Newton), solve(&island, StepMethod::Clarabel));
        newton += ours.newton_calls;
        calls += ours.solver_calls;
        assert_eq!(reference.newton_calls, 0, "seed {seed}: clarabel alone was asked for");
        // Velocities, weighed by the bodies' masses: both answers pass the step's test (momentum balance and
        // complementarity to `complementarity_tolerance`, 1e-6, of the island's impulse scale, its heaviest
        // body's momentum at the velocity scale). Checked by hand on seeds 0, 2 and 4, the two answers' objectives
        // agree to 1e-12 relative with constraint violations below 1e-10 m/s: both are optimal to about 1e-12, and
        // near the optimum the objective is quadratic in the velocities, so they agree to about its square root,
        // 1e-6 of the momentum scale (measured: 5e-6 at most); 1e-5.
        let v_scale = speed_scale(&island);
        let heaviest = island.bodies.iter().filter(|b| b.is_dynamic()).map(|b| 1.0 / b.inv_mass).fold(0.0, f64::max);
        for (k, (a, b)) in ours.velocities.iter().zip(&reference.velocities).enumerate() {
            let body = &island.bodies[k];
            if !body.is_dynamic() {
                continue;
            }
            let linear = (a.linear - b.linear).norm() / body.inv_mass;
            let angular = (body.inertia * (a.angular - b.angular)).norm(); // lever arms of about a metre
            let d = linear.max(angular) / (heaviest * v_scale);
            worst_v = worst_v.max(d);
            assert!(d < 1e-5, "seed {seed}: body {k}'s momentum differs by {d:.1e} of the island's scale");
        }
        // Impulses: where contacts form a tree (no joints), the net impulse between each body and its parent is fixed
        // by the velocities (momentum balance, leaf to root), though its split among a pair's points may not be.
        if island.joints.is_empty() {
            // the impulse scale: the island's whole mass at its velocity scale (a pair carries all above it)
            let mass: f64 = island.bodies.iter().filter(|b| b.is_dynamic()).map(|b| 1.0 / b.inv_mass).sum();
            let p_scale = v_scale * mass;
            for k in 1..island.bodies.len() {
                let net = |out: &VelocityStep| -> Vector3<f64> {
                    island
                        .contacts
                        .iter()
                        .enumerate()
                        .filter(|(_, c)| c.b == k)
                        .map(|(i, c)| c.normal.into_inner() * out.normal_impulses[i] + out.friction_impulses[i])
                        .sum()
                };
                let d = (net(&ours) - net(&reference)).norm() / p_scale;
                worst_p = worst_p.max(d);
                assert!(d < 1e-5, "seed {seed}: body {k}'s impulse from {} differs by {d:.1e}", island.parent[k]);
            }
        }
    }
    println!("largest differences: velocities {worst_v:.1e}, impulses {worst_p:.1e} of their scales");
    println!("the Newton method answered {newton} of {calls} island solves");
    assert_eq!(newton, calls, "every island is the Newton method's");
}

#[test]
fn the_joint_rows_impulses_balance_each_bodys_momentum_with_the_contacts() {
    // Each moving body's change of momentum over the step, M (v - v_free), is the sum of the impulses on it: its
    // contacts' (normal and friction, on B, at the contact point) and its joint rows' (J^T times each row's
    // impulse): so the joint impulses a step returns are the ones it applied, for both solvers. Bound: 1e-6 of the
    // island's momentum scale (the programs' answers are checked to 1e-6 of it, see above; measured below).
    let mut worst = 0.0f64;
    for seed in (1..200u64).step_by(2) {
        let island = random_island(seed, true);
        let scale = speed_scale(&island)
            * island.bodies.iter().filter(|b| b.is_dynamic()).map(|b| 1.0 / b.inv_mass).fold(0.0, f64::max);
        for method in [StepMethod::Newton, StepMethod::Clarabel] {
            let out = solve(&island, method);
            assert_eq!(out.joint_impulses.len(), island.joints.len());
            for (k, body) in island.bodies.iter().enumerate().filter(|(_, b)| b.is_dynamic()) {
                let free = tumble_contact::free_velocity(body, &StepSettings::new(H));
                let mut linear = (out.velocities[k].linear - free.linear) / body.inv_mass;
                let mut angular = body.inertia * (out.velocities[k].angular - free.angular);
                for (i, c) in island.contacts.iter().enumerate() {
                    let p = c.normal.into_inner() * out.normal_impulses[i] + out.friction_impulses[i];
                    let sign = if c.b == k {
                        1.0
                    } else if c.a == k {
                        -1.0
                    } else {
                        continue;
                    };
                    linear -= p * sign;
                    angular -= (c.point - body.position).cross(&p) * sign;
                }
                for (r, &p) in island.joints.iter().zip(&out.joint_impulses) {
                    if r.b == k {
                        linear -= r.lin * p;
                        angular -= r.ang_b * p;
                    }
                    if r.a == k {
                        linear += r.lin * p;
                        angular -= r.ang_a * p;
                    }
                }
                if !body.rotates() {
                    angular = Vector3::zeros();
                }
                let d = linear.norm().max(angular.norm()) / scale;
                worst = worst.max(d);
                assert!(d < 1e-9, "seed {seed}, {method:?}: body {k}'s momentum is off by {d:.1e} of the scale");
            }
        }
    }
    println!("largest momentum imbalance with the joint impulses: {worst:.1e} of the scale");
}

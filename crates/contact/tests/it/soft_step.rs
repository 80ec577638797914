//! The soft step against the exact cone program and closed forms on small scenes: a box resting on the ground
//! carries its weight (the step's normal impulses sum to m g h, as the exact program's do), a box sliding on the
//! ground decelerates at mu g, a particle landing with restitution e leaves at e times its closing speed, a box
//! approaching from a gap stops at it (speculative contact), islands give the same bits on any thread count, and a
//! spring is semi-implicit Euler at the substep.
#![cfg(feature = "clarabel")]

use crate::common;

use nalgebra::{Matrix3, Point3, UnitQuaternion, Vector3};
use tumble_contact::{
    soft_step, velocity_step, BodyState, Contact, SoftImpulse, SoftProblem, SoftSettings, SoftSpring, SpringLaw,
    StepSettings, VelocityProblem,
};

const G: f64 = 9.81;
const H: f64 = 1.0 / 60.0;

/// A cube of half extent 0.5 m and mass m resting on the ground (body 0) at its four bottom corners, moving at `v`.
fn cube_on_ground(m: f64, v: Vector3<f64>, mu: f64) -> (Vec<BodyState>, Vec<Contact>) {
    let inertia = Matrix3::identity() * (m / 6.0);
    let mut cube = BodyState::rigid(m, inertia, Point3::new(0.0, 0.0, 0.5));
    cube.force = Vector3::new(0.0, 0.0, -m * G);
    cube.velocity = v;
    let corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
        .map(|(x, y)| Contact::new(0, 1, Point3::new(x, y, 0.0), Vector3::z_axis()).with_friction(mu));
    (vec![BodyState::fixed(Point3::origin()), cube], corners.to_vec())
}

/// A run of the cube on the ground by the soft step: the cube's pose and velocities carried from step to step, its
/// four bottom corners the contacts (point on the ground under the corner, gap the corner's height), each step
/// warm-started from the last. Returns the last step's summed normal impulse, the cube's velocity and its height,
/// and the last step's residual.
fn run_cube(m: f64, v: Vector3<f64>, mu: f64, z0: f64, steps: usize) -> (f64, Vector3<f64>, f64, f64) {
    let (mut bodies, _) = cube_on_ground(m, v, mu);
    bodies[1].position.z = z0;
    let mut q = UnitQuaternion::identity();
    let mut warm = vec![SoftImpulse::default(); 4];
    let (mut sum, mut residual) = (0.0, 0.0);
    for _ in 0..steps {
        let contacts: Vec<Contact> = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .iter()
            .map(|&(x, y)| {
                let corner = bodies[1].position + q * Vector3::new(x, y, -0.5);
                Contact::new(0, 1, Point3::new(corner.x, corner.y, 0.0), Vector3::z_axis())
                    .with_friction(mu)
                    .with_distance(corner.z)
            })
            .collect();
        let out = soft_step(&SoftProblem::new(&bodies, &contacts, &warm), H, &SoftSettings::default()).unwrap();
        warm.clone_from(&out.impulses);
        sum = out.normal_impulses.iter().sum();
        residual = out.residual;
        bodies[1].position += out.displacements[1];
        q = out.rotations[1] * q;
        bodies[1].velocity = out.velocities[1].linear;
        bodies[1].angular_velocity = out.velocities[1].angular;
    }
    (sum, bodies[1].velocity, bodies[1].position.z, residual)
}

#[test]
fn a_resting_box_carries_its_weight_like_the_exact_program() {
    let m = 1000.0;
    let (bodies, contacts) = cube_on_ground(m, Vector3::zeros(), 0.5);
    let exact =
        velocity_step(&VelocityProblem::new(&bodies, &contacts).lagged(&[m * G * H / 4.0; 4]), &StepSettings::new(H))
            .unwrap();
    let exact_sum: f64 = exact.normal_impulses.iter().sum();
    // The exact program carries m g h to its solver tolerance (1e-8 relative).
    assert!((exact_sum - m * G * H).abs() < 1e-6 * m * G * H, "exact {exact_sum}");
    // The soft step over a second of steps, as in a run: once the contact springs have settled, the same impulse
    // (to 1e-9 relative: what remains of the settling after 60 overdamped steps) and the box at rest, sunk by what
    // the springs need to carry it: the four corners (effective mass m / 4 each, a quarter of the load) settle at
    // g / (2 pi f)^2 for the static stiffness f = 2 x a quarter of the substep rate (480 substeps a second: 240 Hz),
    // 4.3e-6 m; within 1% (the settling's remainder).
    let (soft_sum, v, z, residual) = run_cube(m, Vector3::zeros(), 0.5, 0.5, 60);
    let sink = 0.5 - z;
    let bound = 1.01 * G / (2.0 * std::f64::consts::PI * 240.0f64).powi(2);
    println!("measured: weight impulse exact {exact_sum:.9e}, soft {soft_sum:.9e}, m g h {:.9e}; sunk {sink:.3e} m (bound {bound:.1e})", m * G * H);
    assert!((soft_sum - m * G * H).abs() < 1e-9 * m * G * H, "soft {soft_sum}");
    assert!(v.norm() < 1e-9, "the box stays at rest: {v}");
    assert!(sink > 0.98 * bound && sink < bound, "sunk {sink}");
    // settled, the step meets the exact contact conditions: no approach, no slip, to 1e-9 m/s; the first step,
    // from no warm start, ends with the springs still taking up the load: the box approaches the floor
    let (_, v1, _, first) = run_cube(m, Vector3::zeros(), 0.5, 0.5, 1);
    println!("measured: residual of the settled box {residual:.2e} m/s, of the first step {first:.2e} m/s");
    assert!(residual < 1e-9, "residual {residual}");
    assert!(first > 1e-6 && first >= -v1.z - 1e-12, "first residual {first}, speed {v1}");
}

#[test]
fn a_sliding_box_decelerates_at_mu_g() {
    // v = 2 m/s along x, mu = 0.5: a step takes mu g h of speed, exactly, in both solvers (friction at its Coulomb
    // bound, carried by the normal impulse m g h).
    let (m, mu, v) = (10.0, 0.5, 2.0);
    let (bodies, contacts) = cube_on_ground(m, Vector3::new(v, 0.0, 0.0), mu);
    let exact =
        velocity_step(&VelocityProblem::new(&bodies, &contacts).lagged(&[m * G * H / 4.0; 4]), &StepSettings::new(H))
            .unwrap();
    // the soft step in a run: settled on the ground first (1 s at rest), then one step sliding at v
    let (_, _, z, _) = run_cube(m, Vector3::zeros(), mu, 0.5, 60);
    let (_, after, _, _) = run_cube(m, Vector3::new(v, 0.0, 0.0), mu, z, 1);
    let expected = v - mu * G * H;
    let (ve, vs) = (exact.velocities[1].linear.x, after.x);
    println!("measured: speed after a step: exact {ve:.12}, soft {vs:.12}, v - mu g h {expected:.12}");
    // exact: to its solver tolerance on a 2 m/s scale; soft: friction at the bound in every substep, carried by the
    // normal impulse of a box that starts the step on springs settled to its weight; the first sliding step's
    // friction torque shifts load between the corners, which the sweeps follow a little late (1.6e-6 m/s measured,
    // 2e-5 of the step's change of speed; bound 5e-6 m/s)
    assert!((ve - expected).abs() < 1e-6, "exact {ve}");
    assert!((vs - expected).abs() < 5e-6, "soft {vs}");
}

#[test]
fn a_particle_lands_with_restitution_e() {
    // A particle 1 mm above the ground closing at 3 m/s with e = 0.5: it reaches the ground within the step (the
    // contact is speculative) and leaves at e times the speed it closed at when the step began, 1.5 m/s, less
    // nothing: gravity is off here.
    let p = BodyState::particle(2.0, Point3::new(0.0, 0.0, 1e-3), Vector3::new(0.0, 0.0, -3.0));
    let c = Contact::new(0, 1, Point3::origin(), Vector3::z_axis()).with_restitution(0.5).with_distance(1e-3);
    let out = soft_step(
        &SoftProblem::new(&[BodyState::fixed(Point3::origin()), p], &[c], &[SoftImpulse::default()]),
        H,
        &SoftSettings::default(),
    )
    .unwrap();
    let vz = out.velocities[1].linear.z;
    println!("measured: landing particle leaves at {vz:.12} m/s, ends {:.3e} m up", 1e-3 + out.displacements[1].z);
    assert!((vz - 1.5).abs() < 1e-12, "vz {vz}");
    assert!(1e-3 + out.displacements[1].z >= -1e-12, "never below the ground");
}

#[test]
fn a_speculative_contact_stops_a_body_at_its_gap() {
    // A cube 1 cm above the ground falling at 5 m/s (it would move 8.3 cm in the step): it stops on the ground,
    // not in it, restitution 0.
    let (_, v, z, residual) = run_cube(10.0, Vector3::new(0.0, 0.0, -5.0), 0.5, 0.51, 1);
    let bottom = z - 0.5;
    println!("measured: a cube falling at 5 m/s from 1 cm ends {bottom:.3e} m above the ground at {:.3e} m/s", v.z);
    // The substep that reaches the ground closes the gap to what the corners' Gauss-Seidel sweeps leave: the first
    // corner stops the whole cube and tips it, so it stops short (1.4 mm measured; bound 2 mm) and never sinks
    // into the ground beyond the spring's 1e-4 m.
    assert!(bottom > -1e-4 && bottom < 2e-3, "bottom at {bottom}");
    assert!(v.z.abs() < 0.1, "stopped: {v}");
    // the step ends with the cube apart from the floor and no corner pushing: that end meets the exact contact
    // conditions (free flight), whatever made it stop short, so its residual is zero
    println!("measured: residual of the landing step {residual:.2e} m/s");
    assert!(residual == 0.0, "residual {residual}");
    // and the next steps set it down: after 1 s it rests on its springs
    let (_, v, z, _) = run_cube(10.0, Vector3::new(0.0, 0.0, -5.0), 0.5, 0.51, 60);
    println!("measured: after 1 s at z - 0.5 = {:.3e} m, {:.3e} m/s", z - 0.5, v.norm());
    assert!((z - 0.5).abs() < 1e-4 && v.norm() < 1e-6, "z {z}, v {v}");
}

#[test]
fn islands_give_the_same_bits_on_any_thread_count() {
    // 160 separate stacks of two cubes, one island each: 1,280 contacts, past the 1,000 from which the soft step
    // spreads its batches over threads.
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let mut contacts = Vec::new();
    for s in 0..160 {
        let x = 3.0 * s as f64;
        for k in 0..2 {
            let m = 1.0 + s as f64 + 10.0 * k as f64;
            let mut b = BodyState::rigid(m, Matrix3::identity() * (m / 6.0), Point3::new(x, 0.0, 0.5 + k as f64));
            b.force = Vector3::new(0.0, 0.0, -m * G);
            b.velocity = Vector3::new(0.1 * k as f64, 0.0, -0.2);
            bodies.push(b);
            let below = if k == 0 { 0 } else { bodies.len() - 2 };
            for (cx, cy) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                let c = Contact::new(below, bodies.len() - 1, Point3::new(x + cx, cy, k as f64), Vector3::z_axis());
                contacts.push(c.with_friction(0.4).with_restitution(0.3));
            }
        }
    }
    let warm = vec![SoftImpulse::default(); contacts.len()];
    let run = |threads| {
        soft_step(&SoftProblem::new(&bodies, &contacts, &warm), H, &SoftSettings { threads, ..Default::default() })
            .unwrap()
    };
    let one = run(1);
    for threads in [2, 3, 0] {
        assert_eq!(run(threads), one, "{threads} threads");
    }
    assert_eq!(one.islands, 160);
}

#[test]
fn one_large_island_gives_the_same_bits_on_any_thread_count() {
    // A 16 x 16 grid of boxes on the ground, each touching its right and back neighbours: one island of 1,505
    // contacts, past the 1,000 from which an island's colours are spread over threads. Seeded random masses (1 to
    // 8 kg: a mass ratio under 10, whose passes have a fixed number of sweeps, the ones spread), velocities, spins,
    // gaps, frictions, restitutions and warm starts, and a kinematic box moving through one corner (read by several
    // rows, written by none).
    let mut uniform = common::uniform(99);
    let mut next = move |lo: f64, hi: f64| lo + (hi - lo) * uniform();
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let mut kinematic = BodyState::fixed(Point3::new(-1.0, -1.0, 0.5));
    kinematic.velocity = Vector3::new(0.3, 0.2, 0.0);
    bodies.push(kinematic);
    let index = |i: usize, j: usize| 2 + 16 * i + j;
    let (mut contacts, mut warm) = (Vec::new(), Vec::new());
    for i in 0..16 {
        for j in 0..16 {
            let m = 10f64.powf(next(0.0, 0.9));
            let (x, y) = (1.0 * i as f64, 1.0 * j as f64);
            let mut b = BodyState::rigid(m, Matrix3::identity() * (m / 6.0), Point3::new(x, y, 0.5));
            b.force = Vector3::new(0.0, 0.0, -m * G);
            b.velocity = Vector3::new(next(-0.5, 0.5), next(-0.5, 0.5), next(-0.5, 0.0));
            b.angular_velocity = Vector3::new(next(-1.0, 1.0), next(-1.0, 1.0), next(-1.0, 1.0));
            bodies.push(b);
            let me = index(i, j);
            let mut touch = |a: usize, p: Point3<f64>, n: Vector3<f64>, scale: f64| {
                let c = Contact::new(a, me, p, nalgebra::Unit::new_normalize(n));
                contacts.push(
                    c.with_friction(next(0.0, 1.0)).with_restitution(next(0.0, 0.5)).with_distance(next(-1e-3, 1e-3)),
                );
                warm.push(SoftImpulse {
                    normal: next(0.0, scale),
                    tangent: Vector3::new(next(-1.0, 1.0), next(-1.0, 1.0), 0.0),
                });
            };
            for (cx, cy) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                touch(0, Point3::new(x + cx, y + cy, 0.0), Vector3::z(), m * G * H);
            }
            if i > 0 {
                touch(index(i - 1, j), Point3::new(x - 0.5, y, 0.5), Vector3::x(), 1.0);
            }
            if j > 0 {
                touch(index(i, j - 1), Point3::new(x, y - 0.5, 0.5), Vector3::y(), 1.0);
            }
            if i == 0 && j == 0 {
                touch(1, Point3::new(x - 0.5, y - 0.5, 0.5), Vector3::new(1.0, 1.0, 0.0), 1.0);
            }
        }
    }
    assert_eq!(contacts.len(), 1024 + 2 * 16 * 15 + 1);
    let run = |threads| {
        soft_step(&SoftProblem::new(&bodies, &contacts, &warm), H, &SoftSettings { threads, ..Default::default() })
            .unwrap()
    };
    let one = run(1);
    assert_eq!(one.islands, 1);
    for threads in [2, 3, 4, 0] {
        assert_eq!(run(threads), one, "{threads} threads");
    }
}

#[test]
fn islands_solved_together_give_the_bits_each_gives_alone() {
    // The soft step gathers small islands into batches whose rows it sweeps side by side. Seeded random stacks of
    // one to three boxes (masses 1 to 1000 kg, so some stacks have the large mass ratio that sweeps until settled),
    // random velocities, spins, gaps, materials and warm starts: every body's velocities, displacement and turn,
    // and every contact's impulses, must be the bits the same stack gives solved on its own.
    let mut uniform = common::uniform(2026);
    let mut next = move |lo: f64, hi: f64| lo + (hi - lo) * uniform();
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let (mut contacts, mut warm, mut stacks) = (Vec::new(), Vec::new(), Vec::new());
    for s in 0..150 {
        let x = 3.0 * s as f64;
        let (first_body, first_contact) = (bodies.len(), contacts.len());
        for k in 0..(1 + (next(0.0, 3.0) as usize)) {
            let m = 10f64.powf(next(0.0, 3.0));
            let mut b = BodyState::rigid(m, Matrix3::identity() * (m / 6.0), Point3::new(x, 0.0, 0.5 + k as f64));
            b.force = Vector3::new(0.0, 0.0, -m * G);
            b.velocity = Vector3::new(next(-1.0, 1.0), next(-1.0, 1.0), next(-1.0, 0.0));
            b.angular_velocity = Vector3::new(next(-1.0, 1.0), next(-1.0, 1.0), next(-1.0, 1.0));
            bodies.push(b);
            let below = if k == 0 { 0 } else { bodies.len() - 2 };
            for (cx, cy) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                let c = Contact::new(below, bodies.len() - 1, Point3::new(x + cx, cy, k as f64), Vector3::z_axis());
                contacts.push(
                    c.with_friction(next(0.0, 1.0)).with_restitution(next(0.0, 0.5)).with_distance(next(-1e-3, 1e-3)),
                );
                warm.push(SoftImpulse {
                    normal: next(0.0, m * G * H),
                    tangent: Vector3::new(next(-1.0, 1.0), 0.0, 0.0),
                });
            }
        }
        stacks.push((first_body..bodies.len(), first_contact..contacts.len()));
    }
    let settings = SoftSettings { threads: 1, ..Default::default() };
    let together = soft_step(&SoftProblem::new(&bodies, &contacts, &warm), H, &settings).unwrap();
    assert!(together.islands == 150);
    for (s, (own_bodies, own_contacts)) in stacks.into_iter().enumerate() {
        // the floor, then the stack's boxes; contacts renumbered to match
        let start = own_bodies.start;
        let local = |k: usize| if k == 0 { 0 } else { k - start + 1 };
        let alone_bodies: Vec<BodyState> =
            std::iter::once(bodies[0]).chain(own_bodies.clone().map(|k| bodies[k])).collect();
        let alone_contacts: Vec<Contact> =
            contacts[own_contacts.clone()].iter().map(|c| Contact { a: local(c.a), b: local(c.b), ..*c }).collect();
        let alone =
            soft_step(&SoftProblem::new(&alone_bodies, &alone_contacts, &warm[own_contacts.clone()]), H, &settings)
                .unwrap();
        for k in own_bodies {
            let j = local(k);
            assert_eq!(alone.velocities[j], together.velocities[k], "stack {s}, body {k}");
            assert_eq!(alone.displacements[j], together.displacements[k], "stack {s}, body {k}");
            assert_eq!(alone.rotations[j], together.rotations[k], "stack {s}, body {k}");
        }
        assert_eq!(alone.impulses[..], together.impulses[own_contacts.clone()], "stack {s}");
        assert_eq!(alone.normal_impulses[..], together.normal_impulses[own_contacts], "stack {s}");
    }
}

/// A spring between a falling particle and a fixed point is evaluated at every substep: the step is semi-implicit
/// Euler at h / n written out by hand (force from the substep's start, then the move), to rounding. Forces taken
/// once a step and spread over the substeps moved the particle by (n + 1) / (2 n) of h^2 F / m, which adds energy
/// to an undamped spring at any step (the cloth drape diverged).
#[test]
fn a_spring_is_semi_implicit_euler_at_the_substep() {
    let (m, k, c, l0) = (0.2, 300.0, 0.4, 0.5);
    let anchor = Point3::new(0.0, 0.0, 2.0);
    let mut p = BodyState::particle(m, Point3::new(0.3, -0.1, 1.2), Vector3::new(0.5, 0.2, -1.0));
    p.force = Vector3::new(0.0, 0.0, -m * G);
    let bodies = [BodyState::fixed(anchor), p];
    let zero = Vector3::zeros();
    let law = SpringLaw { stiffness: k, damping: c, rest_length: l0 };
    let spring = SoftSpring { a: 1, b: 0, ra: zero, rb: zero, law };
    let settings = SoftSettings { threads: 1, ..Default::default() };
    let out = soft_step(&SoftProblem::new(&bodies, &[], &[]).springs(&[spring]), H, &settings).unwrap();
    let hs = H / settings.substeps as f64;
    let (mut x, mut v) = (p.position, p.velocity);
    for _ in 0..settings.substeps {
        let d = x - anchor;
        let n = d / d.norm();
        let f = -n * (k * (d.norm() - l0) + c * v.dot(&n));
        v += f * (hs / m);
        v += Vector3::new(0.0, 0.0, -G) * hs;
        x += v * hs;
    }
    let (dx, dv) = ((p.position + out.displacements[1] - x).norm(), (out.velocities[1].linear - v).norm());
    println!("measured: spring step against semi-implicit Euler at the substep: {dx:.1e} m, {dv:.1e} m/s");
    assert!(dx < 1e-14 && dv < 1e-13, "{dx} m, {dv} m/s");
    assert_eq!(out.islands, 1, "the spring makes an island of its particle");

    // an undamped spring keeps its energy over 2,000 steps (spread once-a-step forces: 40 times it, then more)
    let spring = SoftSpring { law: SpringLaw { damping: 0.0, ..law }, ..spring };
    let mut p = BodyState::particle(m, Point3::new(0.0, 0.0, 2.0 - l0 - 0.1), Vector3::zeros());
    let energy =
        |p: &BodyState| 0.5 * m * p.velocity.norm_squared() + 0.5 * k * ((anchor - p.position).norm() - l0).powi(2);
    let start = energy(&p);
    let mut worst = 0.0f64;
    for _ in 0..2000 {
        let bodies = [BodyState::fixed(anchor), p];
        let out = soft_step(&SoftProblem::new(&bodies, &[], &[]).springs(&[spring]), H, &settings).unwrap();
        p.position += out.displacements[1];
        p.velocity = out.velocities[1].linear;
        worst = worst.max((energy(&p) / start - 1.0).abs());
    }
    // semi-implicit Euler keeps a modified energy: the energy itself oscillates by about h_s omega / 2 of itself
    // (0.040 here) and does not drift; forces spread over the substeps raised it 18% a step
    let bound = hs * (k / m).sqrt();
    println!(
        "measured: undamped spring, largest energy change over 2,000 steps {worst:.3e} of its start ({bound:.3e})"
    );
    assert!(worst < bound, "{worst}");
}

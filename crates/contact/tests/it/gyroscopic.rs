//! The gyroscopic switch of the velocity step and the soft step: off (the default), a free body's angular velocity
//! moves by h I^-1 tau alone; on, by h I^-1 (tau - w x I w), which gains kinetic energy at a torque-free spin.

use nalgebra::{Matrix3, Point3, Rotation3, Vector3};
use tumble_contact::{free_velocity, soft_step, BodyState, SoftProblem, SoftSettings, StepSettings};

const H: f64 = 1.0 / 240.0;

/// A seeded uniform number in [lo, hi).
fn uniform(state: &mut u64, lo: f64, hi: f64) -> f64 {
    *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    lo + (hi - lo) * ((*state >> 11) as f64 / (1u64 << 53) as f64)
}

/// A seeded random rigid body: mass 0.1-10 kg, principal moments 0.01-1 kg m^2 (any triangle), turned at random,
/// spinning at up to 50 rad/s, under a random torque (`torque` of up to 1 N m, else none).
fn random_body(r: &mut u64, torque: bool) -> BodyState {
    let mut u = |lo, hi| uniform(r, lo, hi);
    let moments = Vector3::new(u(0.01, 1.0), u(0.01, 1.0), u(0.01, 1.0));
    let turn = Rotation3::new(Vector3::new(u(-3.0, 3.0), u(-3.0, 3.0), u(-3.0, 3.0)));
    let inertia = turn.matrix() * Matrix3::from_diagonal(&moments) * turn.matrix().transpose();
    let mut b = BodyState::rigid(u(0.1, 10.0), inertia, Point3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)));
    b.angular_velocity = Vector3::new(u(-50.0, 50.0), u(-50.0, 50.0), u(-50.0, 50.0));
    if torque {
        b.torque = Vector3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0));
    }
    b
}

fn energy(b: &BodyState, w: &Vector3<f64>) -> f64 {
    0.5 * w.dot(&(b.inertia * w))
}

#[test]
fn the_free_velocity_takes_the_gyroscopic_term_only_when_asked() {
    // 200 seeded random bodies, with and without a torque. Off, w' = w + h I^-1 tau; on, w' = w + h I^-1 (tau - w x
    // I w) (Euler's equations, explicit). Bound: 1e-12 of the spin, rounding of a few products.
    let mut r = 11u64;
    for case in 0..200 {
        let b = random_body(&mut r, case % 2 == 0);
        let inv = b.inertia.try_inverse().expect("positive definite");
        let w = b.angular_velocity;
        let off = free_velocity(&b, &StepSettings::new(H)).angular;
        let on = free_velocity(&b, &StepSettings { gyroscopic: true, ..StepSettings::new(H) }).angular;
        let scale = 1e-12 * w.norm();
        assert!((off - (w + inv * b.torque * H)).norm() <= scale, "case {case}: off");
        assert!((on - (w + inv * (b.torque - w.cross(&(b.inertia * w))) * H)).norm() <= scale, "case {case}: on");
    }
}

#[test]
fn without_a_torque_the_default_step_keeps_the_spin_and_the_explicit_term_gains_its_closed_form_energy() {
    // Torque-free: off, the step keeps w (its angular momentum I w) and so the kinetic energy exactly. On, since
    // w . (w x I w) = 0, the energy rises by h^2/2 g^T I^-1 g, g = w x I w, every step: the pumping the default
    // avoids. Bound on that gain: 1e-6 of it (the energies are differences of numbers up to 1e4 times larger, at
    // 1e-16 each).
    let mut r = 5u64;
    let mut gained = 0;
    for case in 0..200 {
        let b = random_body(&mut r, false);
        let w = b.angular_velocity;
        let off = free_velocity(&b, &StepSettings::new(H)).angular;
        assert_eq!(off, w, "case {case}: a torque-free step keeps the spin");
        let on = free_velocity(&b, &StepSettings { gyroscopic: true, ..StepSettings::new(H) }).angular;
        let g = w.cross(&(b.inertia * w));
        let expected = 0.5 * H * H * g.dot(&(b.inertia.try_inverse().expect("positive definite") * g));
        let gain = energy(&b, &on) - energy(&b, &w);
        assert!((gain - expected).abs() <= 1e-6 * expected + 1e-12 * energy(&b, &w), "case {case}: {gain} {expected}");
        gained += usize::from(gain > 0.0);
    }
    assert_eq!(gained, 200, "the explicit term gains energy at every random spin");
}

#[test]
fn the_soft_steps_free_motion_follows_the_same_switch() {
    // Bodies touching nothing move by the soft step's substeps, whose angular acceleration is the velocity step's:
    // after the step each has the velocity step's free velocity, with the switch off and on. Bound: 1e-12 of the
    // spin (eight substeps' sums against one product).
    let mut r = 3u64;
    let bodies: Vec<BodyState> = (0..50).map(|k| random_body(&mut r, k % 2 == 0)).collect();
    for gyroscopic in [false, true] {
        let settings = SoftSettings { threads: 1, gyroscopic, ..Default::default() };
        let out = soft_step(&SoftProblem::new(&bodies, &[], &[]), H, &settings).unwrap();
        for (k, b) in bodies.iter().enumerate() {
            let free = free_velocity(b, &StepSettings { gyroscopic, ..StepSettings::new(H) });
            let scale = 1e-12 * b.angular_velocity.norm();
            assert!((out.velocities[k].angular - free.angular).norm() <= scale, "body {k}, gyroscopic {gyroscopic}");
        }
    }
}

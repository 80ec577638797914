//! Particles against closed forms: free fall and a projectile; the chapter's damped particle equation
//! m x'' + d x' + h x = 0 in its under-, critically and over-damped regimes; two masses on a spring.

use nalgebra::Vector3;
use tumble::integrate::problems::DampedOscillator;
use tumble::{Attachment, Method, ParticleBuilder, Settings, SpringBuilder, World};

const G: f64 = 9.81;

/// The trajectory is quadratic in t, which RK4 and Dormand-Prince integrate exactly: only round-off remains
/// (1e-10 over 120 frames).
#[test]
fn projectile_matches_closed_form() {
    for settings in [Settings::fixed(Method::Rk4, 0.01), Settings::tolerances(Method::Dopri5, 1e-8, 1e-10)] {
        let mut w = World::new();
        w.set_integrator(settings.clone()).unwrap();
        let (x0, v0) = (Vector3::new(0.0, 1.0, 2.0), Vector3::new(3.0, -1.0, 7.0));
        w.add_particle(ParticleBuilder::new(0.3).position(x0).velocity(v0)).unwrap();
        let run = w.run(2.0, 1.0 / 60.0).unwrap();
        let g = Vector3::new(0.0, 0.0, -G);
        for f in 0..run.frames() {
            let t = run.times[f];
            let (x, v) = (x0 + v0 * t + 0.5 * g * t * t, v0 + g * t);
            assert!((run.particle_position(f, 0) - x).norm() < 1e-10, "{} at t = {t}", settings.method);
            assert!((run.particle_velocity(f, 0) - v).norm() < 1e-10, "{} at t = {t}", settings.method);
        }
    }
}

/// One particle per regime, no gravity, restoring stiffness h = 4 and mass 1 (w0 = 2): damping 0.8 (zeta = 0.2),
/// 4 (zeta = 1), 10 (zeta = 2.5). Dormand-Prince at rtol = atol = 1e-11 follows the closed form to 1e-8 along the
/// whole run (the global error is about the tolerance times the number of steps).
#[test]
fn damped_particle_three_regimes() {
    for (damping, regime) in [(0.8, "under"), (4.0, "critical"), (10.0, "over")] {
        let mut w = World::new();
        w.set_gravity(Vector3::zeros()).unwrap();
        w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-11, 1e-11)).unwrap();
        let x0 = Vector3::new(1.0, -0.5, 0.25);
        let v0 = Vector3::new(0.0, 2.0, -1.0);
        w.add_particle(ParticleBuilder::new(1.0).position(x0).velocity(v0).damping(damping).stiffness(4.0)).unwrap();
        let run = w.run(5.0, 0.05).unwrap();
        let osc = DampedOscillator { mass: 1.0, damping, stiffness: 4.0 };
        for f in 0..run.frames() {
            for k in 0..3 {
                let (x, v) = osc.exact(run.times[f], x0[k], v0[k]);
                let e = (run.particle_position(f, 0)[k] - x).abs().max((run.particle_velocity(f, 0)[k] - v).abs());
                assert!(e < 1e-8, "{regime}-damped, t = {}: error {e:e}", run.times[f]);
            }
        }
    }
}

/// Two masses on a spring in free space: the centre of mass keeps its velocity, the separation oscillates about
/// the rest length with w = sqrt(k / mu), mu = m1 m2 / (m1 + m2). Dormand-Prince at 1e-11: 1e-8.
#[test]
fn two_masses_on_a_spring() {
    let (m1, m2, k, l0) = (1.0, 3.0, 50.0, 1.0);
    let mut w = World::new();
    w.set_gravity(Vector3::zeros()).unwrap();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-11, 1e-11)).unwrap();
    let a = w
        .add_particle(
            ParticleBuilder::new(m1).position(Vector3::new(-0.9, 0.0, 0.0)).velocity(Vector3::new(0.0, 1.0, 0.0)),
        )
        .unwrap();
    let b = w
        .add_particle(
            ParticleBuilder::new(m2).position(Vector3::new(0.6, 0.0, 0.0)).velocity(Vector3::new(0.0, 1.0, 0.0)),
        )
        .unwrap();
    w.add_spring(SpringBuilder::new(Attachment::Particle(a), Attachment::Particle(b)).stiffness(k).rest_length(l0))
        .unwrap();
    let run = w.run(3.0, 0.01).unwrap();
    let omega = (k * (m1 + m2) / (m1 * m2)).sqrt();
    let p0 = run.momentum(0);
    for f in 0..run.frames() {
        let t = run.times[f];
        let sep = run.particle_position(f, 1) - run.particle_position(f, 0);
        let expected = l0 + (1.5 - l0) * (omega * t).cos();
        assert!((sep.x - expected).abs() < 1e-8, "t = {t}: separation {} vs {expected}", sep.x);
        assert!((run.momentum(f) - p0).norm() < 1e-12 * p0.norm().max(1.0), "momentum at t = {t}");
    }
}

/// A particle hanging from a fixed point by a spring oscillates vertically about the stretched length
/// l0 + m g / k with w = sqrt(k / m); the total energy (kinetic + gravity + spring) is conserved to 1e-9.
#[test]
fn particle_hanging_from_a_fixed_point() {
    let (m, k, l0) = (0.5, 80.0, 1.0);
    let mut w = World::new();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-11, 1e-11)).unwrap();
    let p = w.add_particle(ParticleBuilder::new(m).position(Vector3::new(0.0, 0.0, -l0))).unwrap();
    w.add_spring(
        SpringBuilder::new(Attachment::Particle(p), Attachment::Point(Vector3::zeros())).stiffness(k).rest_length(l0),
    )
    .unwrap();
    let run = w.run(2.0, 0.01).unwrap();
    let (stretch, omega) = (m * G / k, (k / m).sqrt());
    let e0 = run.energy(0);
    for f in 0..run.frames() {
        let t = run.times[f];
        let z = -(l0 + stretch) + stretch * (omega * t).cos();
        assert!((run.particle_position(f, 0).z - z).abs() < 1e-9, "t = {t}");
        assert!((run.energy(f) - e0).abs() < 1e-9 * e0.abs().max(1.0), "energy at t = {t}");
    }
}

//! Stiff springs at animation steps: implicit Euler stays finite and stable; explicit Euler reports divergence
//! instead of producing NaN, and leaves the world exactly as it was.

use tumble::scenes::Cloth;
use tumble::{Method, Settings, WorldError};

fn stiff_cloth(k: f64) -> (tumble::World, Vec<tumble::ParticleHandle>) {
    Cloth { n: 10, size: 1.0, mass: 0.5, stiffness: k, damping: 1.0, pin_stiffness: 10.0 * k }.build().unwrap()
}

/// k = 1e6 and 1e8 N/m on 5 g particles (w = sqrt(k/m) up to 1.4e5 rad/s) at h = 1/60: implicit Euler runs 5 s,
/// every position stays finite and within 1 m of the pins' height (the cloth hangs, it cannot stretch), and the
/// kinetic energy at the end is below 1% of the potential energy released (the motion has damped out).
#[test]
fn implicit_euler_is_stable_on_stiff_cloth() {
    for k in [1e6, 1e8] {
        let (mut w, ps) = stiff_cloth(k);
        w.set_integrator(Settings::fixed(Method::ImplicitEuler, 1.0 / 60.0)).unwrap();
        let run = w.run(5.0, 1.0 / 60.0).unwrap();
        for f in 0..run.frames() {
            for i in 0..ps.len() {
                let p = run.particle_position(f, i);
                assert!(p.iter().all(|c| c.is_finite()) && (p.z - 1.0).abs() < 1.0, "k = {k}: particle {i} at {p:?}");
            }
        }
        let last = run.frames() - 1;
        let released = run.potential_energy[0] - run.potential_energy[last];
        assert!(
            released > 0.0 && run.kinetic_energy[last] < 0.01 * released,
            "k = {k}: {} vs {released}",
            run.kinetic_energy[last]
        );
        assert_eq!(run.report.integrator.steps, 300);
    }
}

/// The same cloth with explicit Euler at h = 1/60: every step multiplies the fastest mode by about
/// h sqrt(k / m) = 240, so the run must fail with a divergence error (not NaN), and the world must be exactly as
/// before the call: same time, same positions and velocities bit for bit.
#[test]
fn explicit_euler_reports_divergence_and_leaves_the_world_unchanged() {
    let (mut w, ps) = stiff_cloth(1e6);
    w.set_integrator(Settings::fixed(Method::Euler, 1.0 / 60.0)).unwrap();
    w.step(1.0 / 60.0).unwrap();
    let before: Vec<_> = ps.iter().map(|&p| w.particle(p).unwrap().clone()).collect();
    let t = w.time();
    let err = w.run(5.0, 1.0 / 60.0).unwrap_err();
    match &err {
        WorldError::Simulation(tumble::integrate::OdeError::Divergence { .. }) => {}
        other => panic!("expected a divergence error, got {other:?}"),
    }
    assert_eq!(w.time(), t);
    for (p, b) in ps.iter().zip(&before) {
        assert_eq!(w.particle(*p).unwrap(), b, "the world changed after a failed run");
    }
    let err = (0..100).find_map(|_| w.step(1.0 / 60.0).err()).expect("stepping on must diverge too");
    assert!(matches!(err, WorldError::Simulation(_)), "{err:?}");
    assert!(w.particles().all(|(_, p)| p.position().iter().all(|c| c.is_finite())));
}

//! The report's energy fields against closed forms: `energy_change` (every mode: the change of kinetic plus
//! potential energy over the calls reported) and `energy_gain` (fast mode: the largest rise over one step).

use nalgebra::Vector3;
use tumble::{
    AccurateSettings, FastSettings, Material, Method, Mode, ParticleBuilder, RigidBodyBuilder, Settings, Shape, World,
};

const G: f64 = 9.81;

#[test]
fn a_damped_particle_loses_the_closed_form_energy_in_smooth_mode() {
    // m x'' = -c x', no gravity: v = v0 exp(-c t / m), so the energy changes by m v0^2 / 2 (exp(-2 c t / m) - 1).
    let (m, c, v0, t) = (2.0, 0.7, 3.0, 1.5);
    let mut w = World::new();
    w.set_gravity(Vector3::zeros()).unwrap();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-11, 1e-13)).unwrap();
    w.add_particle(ParticleBuilder::new(m).velocity(Vector3::new(v0, 0.0, 0.0)).damping(c)).unwrap();
    w.step(0.5).unwrap();
    w.step(t - 0.5).unwrap();
    let expected = 0.5 * m * v0 * v0 * ((-2.0 * c * t / m).exp() - 1.0);
    let r = w.report();
    println!("measured: energy change {:.12e} J, closed form {expected:.12e} J", r.energy_change);
    // Dopri5 at rtol 1e-11 keeps the velocity to about 1e-10 relative: the energy to twice that.
    assert!((r.energy_change - expected).abs() < 1e-9 * expected.abs(), "{} vs {expected}", r.energy_change);
    assert_eq!(r.energy_gain, None, "a per-step gain is fast mode's");
}

/// A 0.5 m box of 500 kg/m^3 (62.5 kg) on a floor of friction 0.5, sent along x at 3 m/s, run for 1 s (it stops
/// after 0.61 s): the energy lost is its kinetic energy, 281.25 J.
fn sliding_box(mode: Mode) -> (World, f64) {
    let mut w = World::new();
    w.set_mode(mode).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let shape = Shape::cuboid(Vector3::repeat(0.25)).unwrap();
    let b = RigidBodyBuilder::from_shape(shape, 500.0)
        .position(Vector3::new(0.0, 0.0, 0.25))
        .velocity(Vector3::new(3.0, 0.0, 0.0))
        .restitution(0.0)
        .friction(0.5);
    w.add_body(b).unwrap();
    w.run(1.0, 0.1).unwrap();
    (w, 62.5)
}

#[test]
fn a_sliding_box_loses_its_kinetic_energy_in_both_modes_and_no_fast_step_adds_any() {
    let kinetic = 0.5 * 62.5 * 9.0;
    let (w, m) = sliding_box(Mode::Fast(FastSettings::new(1.0 / 240.0)));
    let r = w.report();
    println!("measured: fast mode energy change {:.6e} J, largest rise {:?} J", r.energy_change, r.energy_gain);
    // The soft contact settles the box by g / (2 pi 240 Hz)^2 = 4.3e-6 m: m g 1e-5 m (6e-3 J) covers that.
    assert!((r.energy_change + kinetic).abs() < m * G * 1e-5, "{} vs {}", r.energy_change, -kinetic);
    let gain = r.energy_gain.expect("fast mode reports its largest rise");
    assert!((0.0..m * G * 1e-5).contains(&gain), "a step added {gain} J");

    let accurate = AccurateSettings { contact_tolerance: Some(1e-6), ..Default::default() };
    let (w, m) = sliding_box(Mode::Accurate(accurate));
    let r = w.report();
    println!("measured: accurate mode energy change {:.9e} J", r.energy_change);
    // Contact steps hold positions to the 1e-6 m tolerance: m g 1e-5 m allows ten of them in height.
    assert!((r.energy_change + kinetic).abs() < m * G * 1e-5, "{} vs {}", r.energy_change, -kinetic);
}

#[test]
fn the_fast_report_energy_change_is_the_change_between_the_first_and_last_frames() {
    // Boxes dropped onto each other (restitution 0.5 and 1): the per-step sum telescopes to the frames' difference.
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
    w.add_ground(0.0, Material::new(0.5, 0.5)).unwrap();
    for k in 0..4 {
        let shape = Shape::cuboid(Vector3::new(0.3, 0.2, 0.25)).unwrap();
        let b = RigidBodyBuilder::from_shape(shape, 700.0)
            .position(Vector3::new(0.2 * (k % 3) as f64, 0.1 * (k % 2) as f64, 0.5 + 0.7 * k as f64))
            .restitution(if k % 2 == 0 { 1.0 } else { 0.3 });
        w.add_body(b).unwrap();
    }
    let run = w.run(2.0, 0.25).unwrap();
    let frames = run.energy(run.frames() - 1) - run.energy(0);
    let e0 = run.energy(0).abs();
    println!("measured: report {:.9e} J, frames {frames:.9e} J", run.report.energy_change);
    // 480 steps of rounding, each about 1e-15 of the energies summed.
    assert!((run.report.energy_change - frames).abs() < 1e-11 * e0, "{} vs {frames}", run.report.energy_change);
    assert!(run.report.energy_change < 0.0, "the drops lose energy");
}

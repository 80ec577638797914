//! Error against run time for contact. First the ball of `bouncing_ball` (dropped from 1 m, e = 0.8) in fast mode
//! at steps from 1/60 s to 1/3840 s and in accurate mode at bisection tolerances from 1e-3 s to 1e-11 s (the
//! flights are parabolas, which Dormand-Prince integrates exactly, so the collision time is accurate mode's only
//! error). The error is the largest deviation of the first three apex heights from 0.64^n m (read from a
//! mid-flight state by the ballistic formula z - r + v_z^2 / (2 g)) and, in accurate mode, of the first three
//! impact times from the closed form. Wall times are the fastest of five runs of 2.5 s.
//!
//! Then friction (`friction.rs`): a cube sliding to a stop, a cube sliding down a 35 degree incline and a sphere
//! rolling down a 30 degree one, each against its closed form, in accurate mode over contact tolerances and in fast
//! mode over steps; the table is also written to `target/contact_precision.csv` for
//! `python3 examples/plot_contact_precision.py`, which draws error against wall time.
//!
//! `cargo run --release --example contact_precision`

#[path = "contact_precision/friction.rs"]
mod friction;

use std::time::Instant;
use tumble::scenes::BouncingBall;
use tumble::{AccurateSettings, FastSettings, Mode, World, WorldError};

const G: f64 = 9.81;

/// The exact impact times and apex heights of the first `n` bounces.
fn closed_form(scene: &BouncingBall, n: usize) -> (Vec<f64>, Vec<f64>) {
    let v1 = (2.0 * G * scene.height).sqrt();
    let mut times = vec![v1 / G];
    for k in 1..n {
        times.push(times[k - 1] + 2.0 * scene.restitution.powi(k as i32) * v1 / G);
    }
    let apexes = (1..=n).map(|k| scene.height * scene.restitution.powi(2 * k as i32)).collect();
    (times, apexes)
}

/// (apex error, impact-time error or NaN, fastest wall time, steps) for a world built by `build`.
fn measure(
    scene: &BouncingBall,
    frame: f64,
    build: impl Fn() -> Result<World, WorldError>,
) -> Result<(f64, f64, f64, usize), WorldError> {
    let (times, apexes) = closed_form(scene, 3);
    let mut best = f64::INFINITY;
    let mut out = (0.0, f64::NAN, 0);
    for _ in 0..5 {
        let mut w = build()?;
        let clock = Instant::now();
        let run = w.run(2.5, frame)?;
        best = best.min(clock.elapsed().as_secs_f64());
        let mut apex_error = 0.0f64;
        for k in 0..3 {
            // the middle of flight k + 1, between impacts k and k + 1 (closed-form times)
            let mid = times[k] + scene.restitution.powi(k as i32 + 1) * (2.0 * G * scene.height).sqrt() / G;
            let f = (mid / frame).round() as usize;
            let (z, vz) = (run.body_position(f, 1).z, run.body_velocity(f, 1).z);
            apex_error = apex_error.max((z - scene.radius + vz * vz / (2.0 * G) - apexes[k]).abs());
        }
        let time_error = if run.contact_events.len() >= 3 {
            run.contact_events.iter().zip(&times).map(|(t, x)| (t - x).abs()).fold(0.0, f64::max)
        } else {
            f64::NAN
        };
        out = (apex_error, time_error, w.report().integrator.steps);
    }
    Ok((out.0, out.1, best, out.2))
}

fn main() -> Result<(), WorldError> {
    let scene = BouncingBall::default();
    println!("mode      setting      apex error (m)  impact error (s)  wall (ms)  steps");
    for k in [60.0, 120.0, 240.0, 480.0, 960.0, 1920.0, 3840.0] {
        let (apex, _, wall, steps) = measure(&scene, 1.0 / k, || {
            let (mut w, _) = scene.build()?;
            w.set_mode(Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(1.0 / k) }))?;
            Ok(w)
        })?;
        println!("fast      h = 1/{k:<6} {apex:>12.2e}  {:>16}  {:>9.3}  {steps:>5}", "-", wall * 1e3);
    }
    for tol in [1e-3, 1e-5, 1e-7, 1e-9, 1e-11] {
        let (apex, time, wall, steps) = measure(&scene, 1e-3, || {
            let (mut w, _) = scene.build()?;
            w.set_mode(Mode::Accurate(AccurateSettings { time_tolerance: tol, ..AccurateSettings::default() }))?;
            Ok(w)
        })?;
        println!("accurate  tol {tol:<8.0e} {apex:>12.2e}  {time:>16.2e}  {:>9.3}  {steps:>5}", wall * 1e3);
    }
    println!();
    friction::sweep()
}

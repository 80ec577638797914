//! Accurate mode's error against wall time on the scenes it is compared with Drake's CENIC on
//! (`tumble::scenes::Benchmark`; `benches/peers/cenic.py` runs CENIC on the same scenes): for each scene and
//! contact tolerance, one run on one thread with frames every 1/60 s, the wall time, the contact steps and the
//! error. The slide, incline and roll are measured against their closed forms over tolerances 1e-2 to 1e-9 m; the
//! pile and the dominoes over 1e-2 to 1e-5 m against the engine's own run at 1e-6 m (the largest distance of any
//! body's position from it), with the deepest penetration; "defaults" is `World::new()` as it comes. Then a settled
//! pile: 1000 s more of it.
//!
//! `cargo run --release --example accurate_scenes [-- --quick]`

use std::time::Instant;
use tumble::scenes::Benchmark;
use tumble::{AccurateSettings, Mode, World};

/// The world's bodies' positions.
fn positions(w: &World, bodies: &[tumble::BodyHandle]) -> Vec<nalgebra::Vector3<f64>> {
    bodies.iter().map(|&b| w.body(b).expect("a body of the scene").position()).collect()
}

/// One run of `scene` at `tolerance` (None: the defaults): the final positions, the wall time, the contact steps
/// and the deepest penetration.
fn run(scene: Benchmark, tolerance: Option<f64>) -> (Vec<nalgebra::Vector3<f64>>, f64, usize, f64) {
    let (mut w, bodies) = scene.build().expect("the scene builds");
    w.set_threads(1).expect("one thread");
    if let Some(tol) = tolerance {
        w.set_mode(Mode::Accurate(AccurateSettings { contact_tolerance: Some(tol), ..AccurateSettings::default() }))
            .expect("accurate mode");
    }
    let start = positions(&w, &bodies);
    let clock = Instant::now();
    let out = w.run(scene.span(), 1.0 / 60.0);
    let wall = clock.elapsed().as_secs_f64();
    let run = match out {
        Ok(run) => run,
        Err(e) => {
            println!("    failed: {e}");
            return (start, wall, 0, f64::NAN);
        }
    };
    (positions(&w, &bodies), wall, run.report.contact_steps, run.report.max_penetration)
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let closed: &[f64] = if quick { &[1e-3, 1e-5] } else { &[1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9] };
    let own: &[f64] = if quick { &[1e-3] } else { &[1e-2, 1e-3, 1e-4, 1e-5] };
    let scenes = [
        ("slide: stop distance", Benchmark::Slide),
        ("incline 35 degrees: slip", Benchmark::Incline { degrees: 35.0 }),
        ("incline 20 degrees: stick", Benchmark::Incline { degrees: 20.0 }),
        ("sphere rolling down 30 degrees", Benchmark::Roll),
        ("20-cube pile", Benchmark::CubePile),
        ("ten dominoes", Benchmark::DominoRow),
    ];
    for (name, scene) in scenes {
        println!("{name} ({} s simulated)", scene.span());
        println!("  {:<12} {:>12} {:>10} {:>8} {:>14}", "tolerance", "error (m)", "wall (s)", "steps", "penetration");
        let start = {
            let (w, bodies) = scene.build().expect("the scene builds");
            positions(&w, &bodies)
        };
        let reference = match scene.closed_form() {
            Some(_) => None,
            None => Some(run(scene, Some(1e-6)).0),
        };
        let error = |end: &[nalgebra::Vector3<f64>]| match (scene.closed_form(), &reference) {
            (Some(d), _) => ((end[0].x - start[0].x) - d).abs(),
            (None, Some(r)) => end.iter().zip(r).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max),
            _ => f64::NAN,
        };
        let tolerances = if scene.closed_form().is_some() { closed } else { own };
        for tol in tolerances.iter().copied().map(Some).chain([None]) {
            let (end, wall, steps, penetration) = run(scene, tol);
            let label = tol.map_or("defaults".to_string(), |t| format!("{t:.0e} m"));
            println!("  {label:<12} {:>12.3e} {wall:>10.4} {steps:>8} {:>12.3e} m", error(&end), penetration);
        }
    }
    // a settled pile: the defaults for 3 s, then 1000 s more
    let (mut w, _) = Benchmark::CubePile.build().expect("the pile builds");
    w.set_threads(1).expect("one thread");
    w.step(3.0).expect("the pile settles");
    let before = w.report().contact_steps;
    let clock = Instant::now();
    w.step(1000.0).expect("the pile rests");
    let r = w.report();
    println!(
        "settled pile, 1000 s more: {:.3} s of wall time, {} contact steps, {} bodies asleep",
        clock.elapsed().as_secs_f64(),
        r.contact_steps - before,
        r.sleepers
    );
}

//! Accurate mode's closed-form scenes (`tumble::scenes::Benchmark`: the slide to a stop, the incline above and
//! below its friction angle, the rolling sphere) over contact tolerances from 1e-2 to 1e-9 m and at the defaults,
//! with frames every 1/60 s: the error against the closed form is printed for each, and held within the tolerance
//! and within 1e-6 of the distance (what the defaults are chosen to keep).

use tumble::scenes::Benchmark;
use tumble::{AccurateSettings, Mode};

/// The distance body 0 of `scene` moved along x over its span at `tolerance` (None: the defaults), and the contact
/// steps it took.
fn moved(scene: Benchmark, tolerance: Option<f64>) -> (f64, usize) {
    let (mut w, bodies) = scene.build().expect("the scene builds");
    if let Some(tol) = tolerance {
        let settings = AccurateSettings { contact_tolerance: Some(tol), ..AccurateSettings::default() };
        w.set_mode(Mode::Accurate(settings)).expect("accurate mode");
    }
    let start = w.body(bodies[0]).expect("the scene's body").position().x;
    let run = w.run(scene.span(), 1.0 / 60.0).expect("the scene runs to its end");
    (w.body(bodies[0]).expect("the scene's body").position().x - start, run.report.contact_steps)
}

#[test]
fn closed_form_scenes_keep_their_error_within_the_tolerance_down_to_a_nanometre_and_at_the_defaults() {
    let scenes = [
        ("slide: stop distance", Benchmark::Slide),
        ("incline 35 degrees: slip", Benchmark::Incline { degrees: 35.0 }),
        ("incline 20 degrees: stick", Benchmark::Incline { degrees: 20.0 }),
        ("sphere rolling down 30 degrees", Benchmark::Roll),
    ];
    let tolerances = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
    for (name, scene) in scenes {
        let exact = scene.closed_form().expect("a closed-form scene");
        for tol in tolerances.iter().copied().map(Some).chain([None]) {
            let (d, steps) = moved(scene, tol);
            let error = (d - exact).abs();
            let label = tol.map_or("defaults".to_string(), |t| format!("{t:.0e} m"));
            println!("measured: {name}, tolerance {label}: error {error:.2e} m in {steps} contact steps");
            // Between events the motion is quadratic in time, which the extrapolated steps carry to the contact
            // programs' accuracy (their velocities to 1e-5 of tol / h: a position error of 1e-5 of the tolerance a
            // step); the events (a stop) are located. So the error is far inside the tolerance; 1e-6 of the
            // distance is what the defaults promise, and a sticking box (exact 0) is held to 1e-9 m or to what the
            // programs' accuracy allows over its steps.
            let programs = 1e-5 * tol.unwrap_or(0.0) * steps as f64;
            let bound = tol.unwrap_or(f64::INFINITY).min((1e-6 * exact).max(1e-9).max(programs));
            assert!(error <= bound, "{name} at {label}: error {error:e} m against {bound:e} m");
        }
    }
}

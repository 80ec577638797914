//! A regression test for the cloth drape (the command line's cloth-drape scene), which diverged once the soft step
//! spread the springs' forces over its substeps: it runs its full 3 s and lies over the ball and on the floor.

use nalgebra::Vector3;
use tumble::scenes::ClothDrape;

#[test]
fn the_cloth_drape_runs_its_3_s_and_lies_over_the_ball_and_on_the_floor() {
    // The command line's cloth-drape scene (12 x 12 particles of radius 1 cm on 60 N/m springs, fast mode at
    // 1/480 s) for its full 3 s. It diverged at t = 1.6 s once the soft step spread the springs' forces, taken
    // once a step, over its substeps (an undamped spring then gains energy at any step; this cloth's damping of
    // 0.05 N s/m was just short of the 0.055 that would have hidden it); the soft step now evaluates springs at
    // every substep.
    let scene = ClothDrape::default();
    let (mut w, ps) = scene.build().unwrap();
    let run = w.run(3.0, 0.25).unwrap_or_else(|e| panic!("the cloth drape failed: {e}"));
    let last = run.frames() - 1;
    assert!((run.times[last] - 3.0).abs() < 1e-9, "the run ended at {}", run.times[last]);
    let (radius, ball, ball_radius) = (0.01, Vector3::new(0.0, 0.0, 0.3), 0.3);
    let at: Vec<Vector3<f64>> = (0..ps.len()).map(|i| run.particle_position(last, i)).collect();
    assert!(at.iter().all(|x| x.iter().all(|v| v.is_finite())));
    let lowest = at.iter().map(|x| x.z).fold(f64::INFINITY, f64::min);
    let highest = at.iter().map(|x| x.z).fold(f64::NEG_INFINITY, f64::max);
    let inside_ball = at.iter().map(|x| ball_radius + radius - (x - ball).norm()).fold(f64::NEG_INFINITY, f64::max);
    println!(
        "measured: cloth drape at 3 s: lowest centre {lowest:.6} m, highest {highest:.6} m, deepest into the ball \
         {inside_ball:.2e} m, max penetration {:.2e} m",
        run.report.max_penetration
    );
    // The soft contacts let a resting particle sink until their springs carry its load: g / (2 pi f)^2 = 7e-8 m
    // for its own weight at f = 1,920 Hz (against a static body: twice a quarter of the 3,840 substeps a second),
    // more where the cloth presses it (the report's penetration: 6e-6 m). 1e-4 m, a hundredth of the radius, is
    // well above that and far below what a cloth falling through would show.
    let tolerance = 1e-4;
    assert!(lowest > radius - tolerance, "a particle sank into the floor: centre at {lowest} m");
    assert!(inside_ball < tolerance, "a particle sank {inside_ball} m into the ball");
    // draped onto the floor: its lowest particles rest on it (centre one radius up) ...
    assert!(lowest < radius + tolerance, "the cloth's lowest particle is {lowest} m up");
    // ... and its middle lies on the ball, whose top is 0.6 m up (the particles nearest the middle sit a little
    // off the apex, 0.60 m at their centres)
    assert!(highest > 0.55 && highest < 2.0 * ball_radius + radius + tolerance, "highest particle at {highest} m");
}

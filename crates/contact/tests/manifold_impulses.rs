//! Each manifold's impulse over a soft step (`SoftStep::manifold_impulses`), the quantity a glued object's weld
//! loads are found from: a cube resting on the ground at its four bottom corners takes its weight times the step
//! from them, about its centre no turn, and with a window each substep's impulse weighed by e^(-substep / window)
//! a later substep (a steady impulse p a substep sums to p (1 - d^n) / (1 - d)).

use nalgebra::{Matrix3, Point3, Vector3};
use tumble_contact::{soft_solve, BodyState, SoftLinks, SoftManifold, SoftPoint, SoftSettings};

const G: f64 = 9.81;
const H: f64 = 1.0 / 60.0;

/// The cube's impulses over the last of 120 steps at rest, with window `window` on its manifold.
fn resting_cube(window: f64) -> (Vector3<f64>, Vector3<f64>) {
    let m = 2.0;
    let mut cube = BodyState::rigid(m, Matrix3::identity() * (m / 6.0), Point3::new(0.0, 0.0, 0.5));
    cube.force = Vector3::new(0.0, 0.0, -m * G);
    let bodies = [BodyState::fixed(Point3::origin()), cube];
    let mut manifold = SoftManifold::new(0, 1, 0.5, 0.0);
    for (k, (x, y)) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)].into_iter().enumerate() {
        manifold.points[k] = SoftPoint { point: Point3::new(x, y, 0.0), normal: Vector3::z(), ..Default::default() };
    }
    manifold.count = 4;
    manifold.colour = 0;
    let windows = [window];
    let links = SoftLinks { manifold_windows: &windows, ..SoftLinks::default() };
    let mut last = (Vector3::zeros(), Vector3::zeros());
    for _ in 0..120 {
        // the cube is held where it rests (its motion is not carried), the manifold's impulses are
        let out = soft_solve(&bodies, &mut [&mut manifold], &links, H, &SoftSettings::default()).unwrap();
        last = out.manifold_impulses[0];
    }
    last
}

#[test]
fn a_resting_cube_takes_its_weight_over_the_step_from_its_manifold() {
    let m = 2.0;
    let (linear, angular) = resting_cube(0.0);
    // the soft contacts hold the cube to their residual (a friction impulse of 2e-5 of the weight's is left by the
    // sweeps): 1e-4 of the weight's impulse is above that and far below any load a weld is judged by
    assert!((linear - Vector3::new(0.0, 0.0, m * G * H)).norm() <= 1e-4 * m * G * H, "{linear}");
    assert!(angular.norm() <= 1e-4 * m * G * H, "{angular}");
}

#[test]
fn a_window_weighs_each_substep_s_impulse_by_its_decay() {
    let (m, window, n) = (2.0, 0.01, SoftSettings::default().substeps as f64);
    let (linear, _) = resting_cube(window);
    let d = (-H / n / window).exp();
    let expected = m * G * H / n * (1.0 - d.powf(n)) / (1.0 - d);
    // (the normal impulse alone: to the sweeps' residual, as above)
    assert!((linear.z - expected).abs() <= 1e-4 * m * G * H, "{} against {expected}", linear.z);
    // and it is not the plain sum: at this window the weights leave 0.54 of it
    assert!(linear.z < 0.6 * m * G * H);
}

#[test]
fn a_window_that_is_not_finite_is_refused_by_name() {
    let cube = BodyState::rigid(1.0, Matrix3::identity(), Point3::new(0.0, 0.0, 0.5));
    let bodies = [BodyState::fixed(Point3::origin()), cube];
    let windows = [f64::NAN];
    let links = SoftLinks { manifold_windows: &windows, ..SoftLinks::default() };
    let mut manifold = SoftManifold::new(0, 1, 0.5, 0.0);
    let error = soft_solve(&bodies, &mut [&mut manifold], &links, H, &SoftSettings::default()).unwrap_err();
    assert!(error.to_string().contains("manifold_windows"), "{error}");
}

//! Each manifold's impulse over a soft step (`SoftStep::manifold_impulses`), the quantity a glued object's weld
//! loads are found from: a cube resting on the ground at its four bottom corners takes its weight times the step
//! from them, about its centre no turn, and with a window each substep's impulse weighed by e^(-substep / window)
//! a later substep (a steady impulse p a substep sums to p (1 - d^n) / (1 - d)); and what a manifold carries into
//! the next step: a resting contact its last substep's impulse, an impact none.

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

/// A row of `n` unit cubes of 1 kg along x (no gravity, restitution 0), the first `gap` m short of the rest and
/// closing on them at `v`, the others face to face; each pair's four face corners its contacts.
fn struck_row(n: usize, v: f64, gap: f64) -> (Vec<BodyState>, Vec<SoftManifold>) {
    let inertia = Matrix3::identity() / 6.0;
    let mut bodies: Vec<BodyState> =
        (0..n).map(|i| BodyState::rigid(1.0, inertia, Point3::new(i as f64, 0.0, 0.0))).collect();
    bodies[0].position.x -= gap;
    bodies[0].velocity = Vector3::new(v, 0.0, 0.0);
    let manifolds = (0..n - 1)
        .map(|i| {
            let mut m = SoftManifold::new(i, i + 1, 0.5, 0.0);
            for (k, (y, z)) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)].into_iter().enumerate() {
                let point = Point3::new(i as f64 + 0.5, y, z);
                let gap = if i == 0 { gap } else { 0.0 };
                m.points[k] = SoftPoint { point, normal: Vector3::x(), gap, ..Default::default() };
            }
            m.count = 4;
            m.colour = (i % 2) as u32;
            m
        })
        .collect();
    (bodies, manifolds)
}

#[test]
fn an_impact_s_impulse_is_not_carried_into_the_next_step() {
    // the striker closes its gap in the step's last substep (seven substeps of travel and half of one more), so
    // the impact's impulse is in that substep: the manifold keeps it in the step's total but carries none of it,
    // nor any friction, into the next step (carried, it was 2.2 N s of the 4.0: the next step's first substep
    // pushed the striker back and the row on)
    let (n, v) = (4, 6.0);
    let settings = SoftSettings::default();
    let hs = H / settings.substeps as f64;
    let (bodies, mut manifolds) = struck_row(n, v, 7.5 * v * hs);
    soft_solve(&bodies, &mut manifolds, &SoftLinks::default(), H, &settings).unwrap();
    let struck = &manifolds[0];
    let step_total: f64 = struck.points().iter().map(|p| p.step_normal).sum();
    assert!(step_total > 0.5 * v, "{step_total}");
    assert!(struck.points().iter().all(|p| p.normal_impulse == 0.0));
    assert_eq!((struck.tangent_impulse, struck.twist_impulse), (Vector3::zeros(), 0.0));
}

#[test]
fn a_resting_contact_s_impulse_is_carried() {
    // the resting cube's manifold starts each step from its last substep's impulse, m g h / substeps (to the
    // sweeps' residual as above)
    let (m, n) = (2.0, SoftSettings::default().substeps as f64);
    let mut cube = BodyState::rigid(m, Matrix3::identity() * (m / 6.0), Point3::new(0.0, 0.0, 0.5));
    cube.force = Vector3::new(0.0, 0.0, -m * G);
    let bodies = [BodyState::fixed(Point3::origin()), cube];
    let mut manifold = SoftManifold::new(0, 1, 0.5, 0.0);
    for (k, (x, y)) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)].into_iter().enumerate() {
        manifold.points[k] = SoftPoint { point: Point3::new(x, y, 0.0), normal: Vector3::z(), ..Default::default() };
    }
    manifold.count = 4;
    manifold.colour = 0;
    for _ in 0..10 {
        soft_solve(&bodies, &mut [&mut manifold], &SoftLinks::default(), H, &SoftSettings::default()).unwrap();
    }
    let carried: f64 = manifold.points().iter().map(|p| p.normal_impulse).sum();
    assert!((carried - m * G * H / n).abs() <= 1e-4 * m * G * H / n, "{carried}");
}

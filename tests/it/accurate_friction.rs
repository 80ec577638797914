//! Coulomb friction in accurate mode against closed forms: a box sliding to a stop, a box on an incline below and
//! above its friction angle, a sphere rolling down an incline, and a spinning box thrown onto a floor. An incline
//! is the floor under gravity tilted by the incline's angle (the same equations in the incline's frame).

use crate::common;

use nalgebra::{UnitQuaternion, Vector3};
use tumble::{AccurateSettings, Material, Mode, RigidBodyBuilder, Shape, World};

const G: f64 = 9.81;

/// An accurate-mode world with contact tolerance `tol` (m), gravity tilted by `theta` about y (down the incline is
/// +x), and a floor of friction `mu` and restitution 0.
fn incline(theta: f64, mu: f64, tol: f64) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Accurate(AccurateSettings { contact_tolerance: Some(tol), ..Default::default() })).unwrap();
    w.set_gravity(Vector3::new(G * theta.sin(), 0.0, -G * theta.cos())).unwrap();
    w.add_ground(0.0, Material::new(0.0, mu)).unwrap();
    w
}

/// A 0.5 m cube of density 1000 resting on the floor, moving at `v` along x.
fn cube_on_floor(w: &mut World, mu: f64, v: f64) -> tumble::BodyHandle {
    let cube = Shape::cuboid(Vector3::repeat(0.25)).unwrap();
    w.add_body(
        RigidBodyBuilder::from_shape(cube, 1000.0)
            .position(Vector3::new(0.0, 0.0, 0.25))
            .velocity(Vector3::new(v, 0.0, 0.0))
            .restitution(0.0)
            .friction(mu),
    )
    .unwrap()
}

/// The distance a cube thrown at 2 m/s on a floor with mu = 0.5 slides, at contact tolerance `tol`.
fn stop_distance(tol: f64) -> (f64, tumble::WorldReport) {
    let (mu, v) = (0.5, 2.0);
    let mut w = incline(0.0, mu, tol);
    let cube = cube_on_floor(&mut w, mu, v);
    w.step(0.6).unwrap();
    let b = w.body(cube).unwrap();
    assert!(b.velocity().norm() < 1e-9, "stopped: {}", b.velocity());
    (b.position().x, w.report())
}

#[test]
fn a_sliding_box_stops_at_v_squared_over_two_mu_g_and_the_error_falls_with_the_tolerance() {
    // d = v^2 / (2 mu g) = 4 / 9.81 m. Friction is constant while sliding, which the extrapolated contact steps
    // carry exactly; the error is where the stop falls inside a step, which the step doubling resolves to the
    // tolerance.
    let exact = 2.0 * 2.0 / (2.0 * 0.5 * G);
    let mut errors = Vec::new();
    for tol in [1e-4, 1e-6, 1e-8] {
        let (d, report) = stop_distance(tol);
        let error = (d - exact).abs() / exact;
        println!(
            "measured: tolerance {tol:e} m: stop distance {d:.12} m, relative error {error:.2e}, {} contact steps",
            report.contact_steps
        );
        errors.push(error);
    }
    assert!(errors[2] < 1e-6, "at 1e-8 m: {:e}", errors[2]);
    assert!(errors[0] > errors[2], "the error falls with the tolerance: {errors:?}");
}

#[test]
fn a_box_on_an_incline_stays_below_its_friction_angle_and_slides_above_it() {
    let mu = 0.5;
    // below: tan 20 deg = 0.36 < 0.5; it stays put, to 1e-9 m over 10 s
    let theta = 20f64.to_radians();
    let mut w = incline(theta, mu, 1e-8);
    let cube = cube_on_floor(&mut w, mu, 0.0);
    w.step(10.0).unwrap();
    let drift = (w.body(cube).unwrap().position() - Vector3::new(0.0, 0.0, 0.25)).norm();
    println!("measured: 20 deg incline, mu 0.5: drift {drift:.2e} m in 10 s");
    assert!(drift < 1e-9, "drift {drift} m");
    // above: tan 35 deg = 0.70 > 0.5; x = 1/2 g (sin - mu cos) t^2
    let theta = 35f64.to_radians();
    let mut w = incline(theta, mu, 1e-7);
    let cube = cube_on_floor(&mut w, mu, 0.0);
    let t = 0.5;
    w.step(t).unwrap();
    let a = G * (theta.sin() - mu * theta.cos());
    let x = w.body(cube).unwrap().position().x;
    let measured = 2.0 * x / (t * t);
    println!("measured: 35 deg incline, mu 0.5: acceleration {measured:.12}, closed form {a:.12}");
    assert!((measured - a).abs() < 1e-6 * a, "{measured} against {a}");
}

#[test]
fn a_sphere_rolls_down_an_incline_at_five_sevenths_g_sin_theta_and_slides_past_its_angle() {
    // Rolling without slipping needs mu >= (2/7) tan theta; then a = (5/7) g sin theta. Above that angle it slides
    // at g (sin - mu cos) while friction spins it up.
    let theta = 30f64.to_radians();
    for (mu, rolls) in [(0.3, true), (0.1, false)] {
        let mut w = incline(theta, mu, 1e-7);
        let ball = w
            .add_body(
                RigidBodyBuilder::from_shape(Shape::sphere(0.2).unwrap(), 1000.0)
                    .position(Vector3::new(0.0, 0.0, 0.2))
                    .restitution(0.0)
                    .friction(mu),
            )
            .unwrap();
        let t = 0.5;
        w.step(t).unwrap();
        let x = w.body(ball).unwrap().position().x;
        let measured = 2.0 * x / (t * t);
        let a = if rolls { 5.0 / 7.0 * G * theta.sin() } else { G * (theta.sin() - mu * theta.cos()) };
        println!("measured: sphere, mu {mu}: acceleration {measured:.12}, closed form {a:.12}");
        assert!((measured - a).abs() < 1e-6 * a, "mu {mu}: {measured} against {a}");
    }
}

#[test]
fn a_box_thrown_spinning_onto_a_floor_settles_flat_at_rest_and_never_gains_energy() {
    let mut w = World::new();
    w.add_ground(0.0, Material::new(0.3, 0.6)).unwrap();
    let cube = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.3, 0.2, 0.1)).unwrap(), 800.0)
                .position(Vector3::new(0.0, 0.0, 1.0))
                .orientation(UnitQuaternion::from_euler_angles(0.4, 0.3, 0.2))
                .velocity(Vector3::new(2.0, 0.5, 0.0))
                .angular_velocity(Vector3::new(3.0, -2.0, 8.0))
                .restitution(0.3)
                .friction(0.6),
        )
        .unwrap();
    let energy = common::energies_by_steps(&mut w, 4.0, 1.0 / 60.0);
    let e0 = energy[0];
    // Energy may rise between calls only by what lifting sunk contacts adds: m g times the contact tolerance
    // (1e-6 of the scene's size, a few micrometres), far below 1e-6 of the starting energy.
    let rise = energy.windows(2).map(|e| e[1] - e[0]).fold(f64::MIN, f64::max);
    println!("measured: thrown box: largest energy rise between steps of 1/60 s {:.2e} of E0", rise / e0);
    assert!(rise < 1e-6 * e0, "energy rose by {rise} J");
    let b = w.body(cube).unwrap();
    let up = b.orientation() * Vector3::z();
    println!(
        "measured: thrown box ends at z = {:.9}, |v| = {:.2e}, |w| = {:.2e}",
        b.position().z,
        b.velocity().norm(),
        b.angular_velocity().norm()
    );
    assert!(b.velocity().norm() < 1e-6 && b.angular_velocity().norm() < 1e-6, "at rest");
    // flat: on its largest face (half height 0.1 m), to the tolerance
    assert!(up.z.abs() > 1.0 - 1e-9 && (b.position().z - 0.1).abs() < 1e-5, "flat: up {up}, z {}", b.position().z);
}

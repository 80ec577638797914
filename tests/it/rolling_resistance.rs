//! Rolling and torsional resistance against their closed forms, in both modes. The law: a contact resists the
//! bodies' relative turn across its normal with a torque of at most c_r N r (c_r the rolling resistance,
//! dimensionless; N the normal force; r the rolling radius, the ball's radius here), and about its normal with at
//! most c_t N r. A solid ball (I = 2/5 m R^2) rolling without slipping on a flat floor then obeys
//! m a = -f and I a / R = f R - c_r m g R, so it slows at a = 5/7 c_r g (friction supplying f = 2/7 c_r m g, within
//! mu m g), stops at t = 7 v0 / (5 c_r g) after 7 v0^2 / (10 c_r g), and stays; a ball spinning in place about the
//! normal at w0 slows at c_t m g R / I = 5 c_t g / (2 R) and stops at 2 R w0 / (5 c_t g).

use nalgebra::Vector3;
use tumble::{FastSettings, Material, MaterialChange, Mode, RigidBodyBuilder, Shape, Target, World};

const G: f64 = 9.81;
const R: f64 = 0.1;

/// A solid ball of radius R on a floor (friction 0.5 both), rolling along x at `v0` (spinning about z at `spin`),
/// with rolling and torsional resistance `c_r` and `c_t` on the ball alone (the pair takes the larger).
fn ball(mode: Mode, v0: f64, spin: f64, c_r: f64, c_t: f64) -> (World, tumble::BodyHandle) {
    let mut w = World::new();
    w.set_mode(mode).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let b = RigidBodyBuilder::from_shape(Shape::sphere(R).unwrap(), 1000.0)
        .position(Vector3::new(0.0, 0.0, R))
        .velocity(Vector3::new(v0, 0.0, 0.0))
        .angular_velocity(Vector3::new(0.0, v0 / R, spin))
        .friction(0.5)
        .rolling_resistance(c_r)
        .torsional_resistance(c_t);
    let h = w.add_body(b).unwrap();
    (w, h)
}

/// `t` to a whole number of fast mode's steps of 1/240 s (both modes are stepped by the same times).
fn steps(t: f64) -> f64 {
    (t * 240.0).round() / 240.0
}

fn modes() -> [(Mode, &'static str); 2] {
    [(Mode::default(), "accurate"), (Mode::Fast(FastSettings::new(1.0 / 240.0)), "fast")]
}

#[test]
fn a_rolling_ball_slows_at_five_sevenths_of_its_resistance_times_g_and_stops() {
    let (v0, c) = (1.0, 0.1);
    let a = 5.0 / 7.0 * c * G;
    let (stop, distance) = (v0 / a, v0 * v0 / (2.0 * a));
    for (mode, name) in modes() {
        let (mut w, h) = ball(mode, v0, 0.0, c, 0.0);
        let half = steps(0.5 * stop);
        w.step(half).unwrap();
        let b = w.body(h).unwrap();
        let v = b.velocity().x;
        // accurate mode: the contact steps hold the law to their tolerance; fast mode: its soft step at 1/240 s
        // (the resistance bound lags the normal impulse of the substep before): 1% of the speed lost
        let tol = if name == "accurate" { 1e-4 } else { 0.01 * a * half };
        assert!((v - (v0 - a * half)).abs() < tol, "{name}: {v} m/s at {half} s, closed form {}", v0 - a * half);
        // still rolling: the contact point does not slip (to the same tolerance)
        let slip = v - b.angular_velocity().y * R;
        assert!(slip.abs() < tol, "{name}: slips at {slip} m/s");
        w.step(steps(stop - half + 0.5)).unwrap();
        let b = w.body(h).unwrap();
        let x = b.position().x;
        // the distance to a millimetre in accurate mode (the stop is located to the steps' size), 2% in fast mode
        let tol = if name == "accurate" { 1e-3 } else { 0.02 * distance };
        assert!((x - distance).abs() < tol, "{name}: stopped at {x} m, closed form {distance}");
        assert!(b.velocity().norm() < 1e-3 && b.angular_velocity().norm() < 1e-2, "{name}: still moving");
    }
}

#[test]
fn a_ball_spinning_in_place_stops_by_torsional_resistance() {
    let (w0, c) = (20.0, 0.2);
    let alpha = 5.0 * c * G / (2.0 * R);
    let stop = w0 / alpha;
    for (mode, name) in modes() {
        let (mut w, h) = ball(mode, 0.0, w0, 0.0, c);
        let half = steps(0.5 * stop);
        w.step(half).unwrap();
        let spin = w.body(h).unwrap().angular_velocity().z;
        let expected = w0 - alpha * half;
        // as above: the contact steps' tolerance, or 1% of the spin lost in fast mode
        let tol = if name == "accurate" { 1e-3 } else { 0.01 * alpha * half };
        assert!((spin - expected).abs() < tol, "{name}: {spin} rad/s at half time, closed form {expected}");
        w.step(steps(stop - half + 0.3)).unwrap();
        let spin = w.body(h).unwrap().angular_velocity().z;
        assert!(spin.abs() < 1e-2, "{name}: spins at {spin} rad/s after it should have stopped");
    }
}

#[test]
fn without_resistance_the_ball_rolls_on_and_a_change_between_steps_stops_it() {
    for (mode, name) in modes() {
        let (mut w, h) = ball(mode, 1.0, 0.0, 0.0, 0.0);
        w.step(1.0).unwrap();
        // nothing resists: the speed kept to the mode's own accuracy (fast: soft contacts, a thousandth)
        let v = w.body(h).unwrap().velocity().x;
        assert!((v - 1.0).abs() < 1e-3, "{name}: a free ball rolls on, got {v}");
        let change = MaterialChange { rolling_resistance: Some(0.5), ..Default::default() };
        w.set_material(Target::Body(h), change).unwrap();
        // a = 5/7 0.5 g = 3.5 m/s^2 stops it within 0.3 s
        w.step(0.5).unwrap();
        let v = w.body(h).unwrap().velocity().norm();
        assert!(v < 1e-3, "{name}: rolling resistance given between steps stops it, still at {v}");
    }
}

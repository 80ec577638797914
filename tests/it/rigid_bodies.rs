//! Rigid bodies: a torque-free body conserves energy and angular momentum and flips about its intermediate axis;
//! torques and forces off the centre of mass give the spin and motion of the chapter's formulas.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use tumble::{Method, RigidBodyBuilder, Settings, Shape, Target, World};

fn free_body(w0: Vector3<f64>) -> World {
    let mut w = World::new();
    w.set_gravity(Vector3::zeros()).unwrap();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-12, 1e-12)).unwrap();
    let inertia = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0));
    w.add_body(RigidBodyBuilder::new(1.0, inertia).angular_velocity(w0)).unwrap();
    w
}

/// I = diag(1, 2, 3), spinning near the intermediate axis, 100 s at rtol = atol = 1e-12: energy and |L| stay within
/// a relative 1e-10 (the bound), and the body-frame angular velocity about the middle axis changes sign
/// repeatedly (the Dzhanibekov flip; theory gives a flip period of about 13 s here).
#[test]
fn torque_free_body_conserves_and_flips() {
    let mut w = free_body(Vector3::new(0.01, 1.0, 0.0));
    let run = w.run(100.0, 0.05).unwrap();
    let (e0, l0) = (run.energy(0), run.angular_momentum(0));
    let mut flips = 0;
    let mut previous = 1.0;
    for f in 0..run.frames() {
        let (e, l) = (run.energy(f), run.angular_momentum(f));
        assert!(((e - e0) / e0).abs() < 1e-10, "energy drift {:e} at t = {}", (e - e0) / e0, run.times[f]);
        assert!(((l.norm() - l0.norm()) / l0.norm()).abs() < 1e-10, "|L| drift at t = {}", run.times[f]);
        let body_w = run.body_orientation(f, 0).inverse() * run.body_angular_velocity(f, 0);
        if body_w.y * previous < 0.0 {
            flips += 1;
        }
        previous = body_w.y;
    }
    assert!(flips >= 4, "{flips} flips of the intermediate axis in 100 s");
}

/// The same body spun about its major axis (stable): no flip, the body-frame angular velocity stays within 1% of
/// its start.
#[test]
fn spin_about_the_major_axis_is_stable() {
    let mut w = free_body(Vector3::new(0.01, 0.0, 1.0));
    let run = w.run(100.0, 0.1).unwrap();
    for f in 0..run.frames() {
        let body_w = run.body_orientation(f, 0).inverse() * run.body_angular_velocity(f, 0);
        assert!((body_w.z - 1.0).abs() < 0.01, "t = {}: {body_w:?}", run.times[f]);
    }
}

fn ball(w: &mut World) -> tumble::BodyHandle {
    w.set_gravity(Vector3::zeros()).unwrap();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-12, 1e-12)).unwrap();
    w.add_body(RigidBodyBuilder::from_shape(Shape::sphere(0.5).unwrap(), 1000.0)).unwrap()
}

/// A constant torque on a ball: w(t) = tau t / I and a rotation by tau t^2 / (2 I) about the torque's axis, to 1e-9.
#[test]
fn constant_torque_spins_up_a_ball() {
    let mut w = World::new();
    let b = ball(&mut w);
    let i = w.body(b).unwrap().inertia()[(0, 0)];
    let tau = Vector3::new(0.0, 3.0, 4.0);
    w.add_torque(b, tau).unwrap();
    let run = w.run(2.0, 0.1).unwrap();
    for f in 0..run.frames() {
        let t = run.times[f];
        assert!((run.body_angular_velocity(f, 0) - tau * t / i).norm() < 1e-9, "t = {t}");
        let expected = UnitQuaternion::from_scaled_axis(tau * t * t / (2.0 * i));
        assert!(run.body_orientation(f, 0).angle_to(&expected) < 1e-9, "t = {t}");
    }
}

/// A force F fixed in world axes at a body point r: the centre of mass accelerates as F / M whatever the point
/// (P(t) = F t exactly), and at first L grows as ((r - x) x F) t. After 1 ms the ball has turned by
/// |tau| t^2 / (2 I) ~ 1e-6 rad, so the torque has changed by that fraction: the check is to 1e-5.
#[test]
fn force_off_the_centre_gives_the_chapters_torque() {
    let mut w = World::new();
    let b = ball(&mut w);
    let body = w.body(b).unwrap();
    let (mass, i) = (body.mass(), body.inertia()[(0, 0)]);
    let (force, at) = (Vector3::new(100.0, 0.0, 0.0), Vector3::new(0.0, 0.5, 0.0));
    w.add_force(Target::Body(b), force, Some(at)).unwrap();
    let t = 1e-3;
    w.step(t).unwrap();
    let body = w.body(b).unwrap();
    assert!((body.momentum() - force * t).norm() < 1e-12 * (force * t).norm());
    assert!((body.velocity() - force * t / mass).norm() < 1e-12);
    let tau = at.cross(&force);
    assert!((body.angular_momentum() - tau * t).norm() < 1e-5 * (tau * t).norm());
    assert!((body.angular_velocity() - tau * t / i).norm() < 1e-5 * (tau * t / i).norm());
}

/// The velocity of a body point is w x (r - x) + v: compared with central differences of the point's position
/// over 2 x 1e-4 s (error O(h^2) ~ 1e-7 relative).
#[test]
fn point_velocity_formula() {
    let mut w = World::new();
    let b = ball(&mut w);
    let (p0, r) = (Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.3, -0.2, 0.4));
    w.set_body_state(
        b,
        p0,
        UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
        Vector3::new(0.5, 0.0, -1.0),
        Vector3::new(2.0, -1.0, 3.0),
    )
    .unwrap();
    let h = 1e-4;
    let before = w.body(b).unwrap().world_point(r);
    w.step(h).unwrap();
    let middle = w.body(b).unwrap().clone();
    w.step(h).unwrap();
    let after = w.body(b).unwrap().world_point(r);
    let fd = (after - before) / (2.0 * h);
    let formula = middle.point_velocity(middle.world_point(r));
    assert!((fd - formula).norm() < 1e-6 * formula.norm(), "{fd:?} vs {formula:?}");
}

/// A free-falling body falls like a particle, whatever its spin.
#[test]
fn spinning_body_falls_like_a_particle() {
    let mut w = World::new();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-10, 1e-10)).unwrap();
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.1, 0.2, 0.3)).unwrap(), 500.0)
                .angular_velocity(Vector3::new(3.0, 1.0, 2.0)),
        )
        .unwrap();
    w.step(1.5).unwrap();
    let z = w.body(b).unwrap().position().z;
    assert!((z + 0.5 * 9.81 * 1.5 * 1.5).abs() < 1e-9, "z = {z}");
}

/// The built-in heavy top (spin 40 rad/s about its axis, tilted 0.3 rad, tip held by a stiff spring) precesses at
/// the steady rate of a heavy symmetric top, the slow root of I1 cos(theta) W^2 - I3 w3 W + M g l = 0 (0.6180
/// rad/s), averaged over 5 s. It starts without precession, so it nutates about that motion at about
/// I3 w3 / I1 = 80 rad/s; averaged over ~60 nutation periods the rate is within 1%.
#[test]
fn heavy_top_precesses_at_the_steady_rate() {
    let (mut w, _) = tumble::scenes::spinning_top().unwrap();
    let run = w.run(5.0, 1.0 / 120.0).unwrap();
    let azimuth = |f: usize| run.body_position(f, 0).y.atan2(run.body_position(f, 0).x);
    let mut turned = 0.0;
    for f in 1..run.frames() {
        let mut d = azimuth(f) - azimuth(f - 1);
        d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
        turned += d;
    }
    let rate = turned / 5.0;
    let (a, b, c) = (0.02 * 0.3f64.cos(), 0.04 * 40.0, 9.81 * 0.1);
    let steady = (b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    assert!((rate / steady - 1.0).abs() < 0.01, "precession {rate} rad/s, steady {steady} rad/s");
}

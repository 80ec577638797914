//! The joint scenes of the peer comparison (`benches/peers/compare.py --joints`), in tumble's fast mode (default) or
//! accurate mode (`accurate`), one markdown row each; the same definitions as the peers' (z up, g = 9.81):
//! a chain of 20 capsules (half height 0.04 m, radius 0.01 m, 1 kg) on ball joints from a fixed point at
//! (0, 0, 2.5), each link 0.1 m, with a 10 kg ball of radius 0.1 m at its end, dt 1/60: hanging at rest for 5 s
//! (its stretch, the sum of the joints' gaps, at the end) and released from the horizontal (the largest stretch in
//! 5 s); and a 1 kg ball of radius 5 cm hinged 1 m from a fixed point, released at rest from the horizontal, dt
//! 1/60, 10 s (its period, from the downward crossings of the vertical, against the physical pendulum's
//! 4 sqrt(I / (m g L)) K(sin 45 deg) with I = m (L^2 + 2 r^2 / 5)). Times are for the steps alone.
//!
//! `cargo run --release --example joint_scenes [-- accurate]`

use nalgebra::{UnitQuaternion, Vector3};
use std::time::Instant;
use tumble::{BodyHandle, FastSettings, JointBuilder, Method, Mode, RigidBodyBuilder, Settings, Shape, World};

const G: f64 = 9.81;
const K_HALF: f64 = 1.854_074_677_301_372;

fn world(accurate: bool) -> World {
    let mut w = World::new();
    if accurate {
        w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-8, 1e-10)).unwrap();
    } else {
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 60.0))).unwrap();
    }
    w
}

/// The chain, turned by `turn` about the pivot; its bodies and its joints' anchors (body, local point) in pairs.
type Anchor = (Option<BodyHandle>, Vector3<f64>);
fn chain(w: &mut World, turn: UnitQuaternion<f64>) -> Vec<(Anchor, Anchor)> {
    let pivot = Vector3::new(0.0, 0.0, 2.5);
    let link = Shape::capsule(0.04, 0.01).unwrap();
    let (top, bottom) = (Vector3::new(0.0, 0.0, 0.05), Vector3::new(0.0, 0.0, -0.05));
    let mut joints = Vec::new();
    let mut above: Anchor = (None, pivot);
    for k in 0..20 {
        let at = pivot + turn * Vector3::new(0.0, 0.0, -0.05 - 0.1 * k as f64);
        let b = w
            .add_body(RigidBodyBuilder::from_shape_with_mass(link.clone(), 1.0).position(at).orientation(turn))
            .unwrap();
        w.add_joint(JointBuilder::ball(above.0, Some(b)).anchor_a(above.1).anchor_b(top)).unwrap();
        joints.push((above, (Some(b), top)));
        above = (Some(b), bottom);
    }
    let at = pivot + turn * Vector3::new(0.0, 0.0, -2.1);
    let ball = w
        .add_body(
            RigidBodyBuilder::from_shape_with_mass(Shape::sphere(0.1).unwrap(), 10.0).position(at).orientation(turn),
        )
        .unwrap();
    w.add_joint(JointBuilder::ball(above.0, Some(ball)).anchor_a(above.1).anchor_b(Vector3::new(0.0, 0.0, 0.1)))
        .unwrap();
    joints.push((above, (Some(ball), Vector3::new(0.0, 0.0, 0.1))));
    joints
}

/// The sum of the joints' gaps (m).
fn stretch(w: &World, joints: &[(Anchor, Anchor)]) -> f64 {
    let point = |(b, p): &Anchor| match b {
        Some(b) => w.body(*b).unwrap().world_point(*p),
        None => *p,
    };
    joints.iter().map(|(a, b)| (point(a) - point(b)).norm()).sum()
}

fn main() {
    let accurate = std::env::args().any(|a| a == "accurate");
    let name = if accurate { "tumble accurate (dopri5, rtol 1e-8)" } else { "tumble fast (soft step, 8 substeps)" };
    println!("| {name} | value |\n|---|---|");
    let dt = 1.0 / 60.0;
    for (horizontal, label) in [
        (false, "chain hanging, dt 1/60: stretch after 5 s"),
        (true, "chain from horizontal, dt 1/60: largest stretch in 5 s"),
    ] {
        let mut w = world(accurate);
        let turn = if horizontal {
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -std::f64::consts::FRAC_PI_2)
        } else {
            UnitQuaternion::identity()
        };
        let joints = chain(&mut w, turn);
        let (mut spent, mut worst) = (0.0, 0.0f64);
        for _ in 0..300 {
            let clock = Instant::now();
            w.step(dt).unwrap();
            spent += clock.elapsed().as_secs_f64();
            worst = worst.max(stretch(&w, &joints));
        }
        let value = if horizontal { worst } else { stretch(&w, &joints) };
        println!("| {label} / ms a step | {value:.2e} m / {:.3} ms |", spent * 1e3 / 300.0);
    }
    let mut w = world(accurate);
    let r = 0.05;
    let bob = w
        .add_body(RigidBodyBuilder::from_shape_with_mass(Shape::sphere(r).unwrap(), 1.0).position(Vector3::x()))
        .unwrap();
    w.add_joint(JointBuilder::hinge(None, Some(bob), Vector3::y()).anchor_b(Vector3::new(-1.0, 0.0, 0.0))).unwrap();
    let (mut spent, mut crossings, mut last) = (0.0, Vec::new(), (0.0, 1.0));
    for _ in 0..600 {
        let clock = Instant::now();
        w.step(dt).unwrap();
        spent += clock.elapsed().as_secs_f64();
        let (t, x) = (w.time(), w.body(bob).unwrap().position().x);
        if last.1 > 0.0 && x <= 0.0 {
            crossings.push(last.0 + last.1 / (last.1 - x) * (t - last.0));
        }
        last = (t, x);
    }
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let exact = 4.0 * ((1.0 + 0.4 * r * r) / G).sqrt() * K_HALF;
    println!(
        "| hinged pendulum from 90 deg, dt 1/60: period error / ms a step | {:+.2e} / {:.4} ms |",
        (period - exact) / exact,
        spent * 1e3 / 600.0
    );
}

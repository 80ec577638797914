//! Jointed scenes: a pendulum released from the horizontal, a chain of links hanging with a weight, Newton's cradle
//! of hinged balls, a door its motor swings open to its limit, and a ragdoll dropped onto stairs. Each is built in
//! the mode it suits (the ragdoll and the door use limits, which only fast mode has).

use crate::body::RigidBodyBuilder;
use crate::collider::Material;
use crate::error::WorldError;
use crate::joint::JointBuilder;
use crate::mode::{FastSettings, Mode};
use crate::spring::BodyHandle;
use crate::world::World;
use nalgebra::{UnitQuaternion, Vector3};
use tumble_collide::Shape;
use tumble_integrate::{Method, Settings};

/// A pendulum: a ball of `radius` on a rigid rod of `length` from a fixed point, released at rest from the
/// horizontal (accurate mode, Dopri5 at rtol 1e-10: its period matches the elliptic integral to about 1e-10).
pub fn pendulum(length: f64, radius: f64) -> Result<(World, BodyHandle), WorldError> {
    super::within("length", length, 1e-3, 1e6)?;
    super::within("radius", radius, 1e-4, 0.5 * length)?;
    let mut w = World::new();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-10, 1e-12))?;
    let bob = w.add_body(
        RigidBodyBuilder::from_shape_with_mass(Shape::sphere(radius)?, 1.0)
            .position(Vector3::new(length, 0.0, 0.0))
            .name("bob")
            .color(super::hue(0)),
    )?;
    w.add_joint(JointBuilder::distance(None, Some(bob), None))?;
    Ok((w, bob))
}

/// A chain of `links` rods (0.1 m, 1 kg each) hanging from a fixed point by ball joints, a 10 kg weight at its
/// end (fast mode at 1/60 s, 8 substeps: the rigid rows are solved together and the chain does not stretch).
pub fn chain(links: usize) -> Result<(World, Vec<BodyHandle>), WorldError> {
    if !(1..=1000).contains(&links) {
        return Err(WorldError::invalid("links", format!("must be from 1 to 1000, got {links}")));
    }
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 60.0)))?;
    let rod = Shape::capsule(0.04, 0.01)?;
    let mut out = Vec::with_capacity(links + 1);
    for k in 0..links {
        let at = Vector3::new(0.0, 0.0, 2.5 - 0.05 - 0.1 * k as f64);
        let link = RigidBodyBuilder::from_shape_with_mass(rod.clone(), 1.0).position(at);
        let b = w.add_body(link.name(format!("link {}", k + 1)).color(super::hue(1)))?;
        let joint = match out.last() {
            None => JointBuilder::ball(None, Some(b)).anchor_a(Vector3::new(0.0, 0.0, 2.5)),
            Some(&above) => JointBuilder::ball(Some(above), Some(b)).anchor_a(Vector3::new(0.0, 0.0, -0.05)),
        };
        w.add_joint(joint.anchor_b(Vector3::new(0.0, 0.0, 0.05)))?;
        out.push(b);
    }
    let end = Vector3::new(0.0, 0.0, 2.5 - 0.1 * links as f64 - 0.1);
    let weight = RigidBodyBuilder::from_shape_with_mass(Shape::sphere(0.1)?, 10.0).position(end);
    let weight = w.add_body(weight.name("weight").color(super::hue(5)))?;
    let last = *out.last().expect("at least one link");
    w.add_joint(
        JointBuilder::ball(Some(last), Some(weight))
            .anchor_a(Vector3::new(0.0, 0.0, -0.05))
            .anchor_b(Vector3::new(0.0, 0.0, 0.1)),
    )?;
    out.push(weight);
    Ok((w, out))
}

/// Newton's cradle: `balls` steel balls (radius 0.05 m) in a row 1 mm apart, each hung by a hinge 0.5 m above it,
/// the first pulled out by `angle` and released (fast mode at 1/240 s, restitution 1, no friction). The soft step
/// resolves the row's impacts within one step together, so part of the momentum spreads along the row instead of
/// all reaching the last ball (the example prints how much does).
pub fn newtons_cradle(balls: usize, angle: f64) -> Result<(World, Vec<BodyHandle>), WorldError> {
    if !(2..=100).contains(&balls) {
        return Err(WorldError::invalid("balls", format!("must be from 2 to 100, got {balls}")));
    }
    super::within("angle", angle, 0.0, 1.5)?;
    let (r, l) = (0.05, 0.5);
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0)))?;
    let mut out = Vec::with_capacity(balls);
    for k in 0..balls {
        let pivot = Vector3::new((2.0 * r + 1e-3) * k as f64, 0.0, 1.0);
        let swing = if k == 0 { angle } else { 0.0 };
        let turn = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), swing);
        let ball = RigidBodyBuilder::from_shape(Shape::sphere(r)?, 7800.0)
            .position(pivot + turn * Vector3::new(0.0, 0.0, -l))
            .orientation(turn)
            .restitution(1.0)
            .friction(0.0)
            .name(format!("ball {}", k + 1))
            .color(super::hue(if k == 0 { 0 } else { 5 }));
        let b = w.add_body(ball)?;
        let hinge =
            JointBuilder::hinge(None, Some(b), Vector3::y()).anchor_a(pivot).anchor_b(Vector3::new(0.0, 0.0, l));
        w.add_joint(hinge)?;
        out.push(b);
    }
    Ok((w, out))
}

/// A door (1 m x 2 m x 4 cm, 20 kg) on a vertical hinge, its motor turning it at 1 rad/s with at most 20 N m until
/// its limit at 1.5 rad holds it (fast mode at 1/60 s).
pub fn door() -> Result<(World, BodyHandle), WorldError> {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 60.0)))?;
    w.add_ground(0.0, Material::new(0.0, 0.5))?;
    let panel = Shape::cuboid(Vector3::new(0.5, 0.02, 1.0))?;
    let d = RigidBodyBuilder::from_shape_with_mass(panel, 20.0).position(Vector3::new(0.5, 0.0, 1.01));
    let d = w.add_body(d.name("door").color(super::hue(2)))?;
    let hinge = JointBuilder::hinge(None, Some(d), Vector3::z())
        .anchor_a(Vector3::new(0.0, 0.0, 1.01))
        .anchor_b(Vector3::new(-0.5, 0.0, 0.0))
        .limits(0.0, 1.5)
        .motor(1.0, 20.0);
    w.add_joint(hinge)?;
    Ok((w, d))
}

/// A ragdoll of 10 parts (torso, head, upper and lower arms and legs; 70 kg) dropped onto a flight of stairs:
/// ball joints at the neck, shoulders and hips, hinges with limits at the elbows and knees (fast mode at 1/60 s).
pub fn ragdoll() -> Result<(World, Vec<BodyHandle>), WorldError> {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 60.0)))?;
    let stone = Material::new(0.0, 0.5);
    w.add_ground(0.0, stone)?;
    // stairs going down along +x: steps 0.3 m deep and 0.2 m high
    for k in 0..6 {
        let height = 0.2 * (6 - k) as f64;
        let step = RigidBodyBuilder::fixed(Some(Shape::cuboid(Vector3::new(0.15, 1.0, 0.5 * height))?))
            .position(Vector3::new(0.3 * k as f64, 0.0, 0.5 * height))
            .friction(stone.friction)
            .restitution(0.0)
            .name(format!("step {}", k + 1))
            .color(super::hue(5));
        w.add_body(step)?;
    }
    let top = 1.2 + 0.05;
    let part = |w: &mut World, shape: Shape, mass: f64, at: Vector3<f64>, name: &str| {
        let b = RigidBodyBuilder::from_shape_with_mass(shape, mass).position(at).friction(0.6).restitution(0.0);
        w.add_body(b.name(name).color(super::hue(2)))
    };
    // lying face down across the top step, head towards the stairs, 0.3 m above it, pushed off towards them
    let z = top + 0.3;
    let torso = part(&mut w, Shape::cuboid(Vector3::new(0.3, 0.17, 0.1))?, 35.0, Vector3::new(0.0, 0.0, z), "torso")?;
    let head = part(&mut w, Shape::sphere(0.11)?, 5.0, Vector3::new(0.43, 0.0, z), "head")?;
    let limb = |r: f64, half: f64| Shape::capsule(half, r);
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let mut limbs = Vec::new();
    for side in [-1.0, 1.0] {
        let named = |b: RigidBodyBuilder, part: &str| {
            b.name(format!("{} {part}", if side < 0.0 { "right" } else { "left" })).color(super::hue(1))
        };
        // arms reach forward past the head, legs back
        let upper_arm = RigidBodyBuilder::from_shape_with_mass(limb(0.045, 0.1)?, 2.5)
            .position(Vector3::new(0.42, side * 0.24, z))
            .orientation(along_x)
            .friction(0.6);
        let upper_arm = w.add_body(named(upper_arm, "upper arm"))?;
        let forearm = RigidBodyBuilder::from_shape_with_mass(limb(0.04, 0.1)?, 1.5)
            .position(Vector3::new(0.72, side * 0.24, z))
            .orientation(along_x)
            .friction(0.6);
        let forearm = w.add_body(named(forearm, "forearm"))?;
        let thigh = RigidBodyBuilder::from_shape_with_mass(limb(0.07, 0.15)?, 7.0)
            .position(Vector3::new(-0.52, side * 0.1, z))
            .orientation(along_x)
            .friction(0.6);
        let thigh = w.add_body(named(thigh, "thigh"))?;
        let shin = RigidBodyBuilder::from_shape_with_mass(limb(0.05, 0.15)?, 4.0)
            .position(Vector3::new(-0.96, side * 0.1, z))
            .orientation(along_x)
            .friction(0.6);
        let shin = w.add_body(named(shin, "shin"))?;
        // joints at the ends of the limbs (each limb's local z runs along +x: the capsules were turned so)
        let shoulder = JointBuilder::ball(Some(torso), Some(upper_arm))
            .anchor_a(Vector3::new(0.27, side * 0.24, 0.0))
            .anchor_b(Vector3::new(0.0, 0.0, -0.15));
        w.add_joint(shoulder)?;
        let elbow = JointBuilder::hinge(Some(upper_arm), Some(forearm), Vector3::y())
            .anchor_a(Vector3::new(0.0, 0.0, 0.15))
            .anchor_b(Vector3::new(0.0, 0.0, -0.15))
            .limits(-2.5, 0.0);
        w.add_joint(elbow)?;
        let hip = JointBuilder::ball(Some(torso), Some(thigh))
            .anchor_a(Vector3::new(-0.3, side * 0.1, 0.0))
            .anchor_b(Vector3::new(0.0, 0.0, 0.22));
        w.add_joint(hip)?;
        let knee = JointBuilder::hinge(Some(thigh), Some(shin), Vector3::y())
            .anchor_a(Vector3::new(0.0, 0.0, -0.22))
            .anchor_b(Vector3::new(0.0, 0.0, 0.22))
            .limits(0.0, 2.5);
        w.add_joint(knee)?;
        limbs.extend([upper_arm, forearm, thigh, shin]);
    }
    w.add_joint(
        JointBuilder::ball(Some(torso), Some(head))
            .anchor_a(Vector3::new(0.3, 0.0, 0.0))
            .anchor_b(Vector3::new(-0.13, 0.0, 0.0)),
    )?;
    let mut parts = vec![torso, head];
    parts.extend(limbs);
    for &h in &parts {
        let b = w.body(h).expect("just added");
        let (x, q) = (b.position(), b.orientation());
        w.set_body_state(h, x, q, Vector3::new(3.0, 0.0, 0.0), Vector3::new(0.0, 1.0, 0.0))?;
    }
    Ok((w, parts))
}

//! A world written into the scene file: every object with its state and start, exactly (momenta, mass and inertia
//! as they are, colliders about the centre of mass), and the world's settings.

use super::file::*;
use crate::error::WorldError;
use crate::joint::JointKind;
use crate::load::{Load, Target};
use crate::spring::Attachment;
use crate::world::World;
use nalgebra::{UnitQuaternion, Vector3};
use std::collections::BTreeMap;
use tumble_collide::Shape;

fn v3(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn q4(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

pub(crate) fn shape_file(s: &Shape) -> ShapeFile {
    let points = |ps: Vec<nalgebra::Point3<f64>>| ps.iter().map(|p| [p.x, p.y, p.z]).collect();
    match s {
        Shape::Sphere { radius } => ShapeFile::Sphere { radius: *radius },
        Shape::Cuboid { half_extents } => ShapeFile::Box { half_extents: v3(half_extents) },
        Shape::Capsule { half_height, radius } => ShapeFile::Capsule { half_height: *half_height, radius: *radius },
        Shape::Cylinder { half_height, radius } => ShapeFile::Cylinder { half_height: *half_height, radius: *radius },
        Shape::ConvexHull(h) => ShapeFile::ConvexHull {
            points: points(h.source_points().to_vec()),
            faces: h.source_faces().map(<[[u32; 3]]>::to_vec),
        },
        Shape::TriMesh(m) => ShapeFile::TriMesh { vertices: points(m.vertices()), triangles: m.triangles() },
        Shape::Mesh(m) => ShapeFile::Mesh {
            vertices: points(m.vertices().to_vec()),
            triangles: m.triangles().to_vec(),
            name: m.name().to_string(),
            decomposition: None,
        },
        Shape::Decomposed(d) => ShapeFile::DecomposedMesh {
            vertices: points(d.mesh().vertices().to_vec()),
            triangles: d.mesh().triangles().to_vec(),
            name: d.mesh().name().to_string(),
            decomposition: *d.params(),
            pieces: d.pieces().iter().map(|h| points(h.source_points().to_vec())).collect(),
            seconds: d.seconds(),
        },
        Shape::HalfSpace { normal } => ShapeFile::HalfSpace { normal: v3(normal) },
    }
}

/// The scene file of the world as it is. A world with force callbacks cannot be written (they are code): the
/// error names `loads`.
pub(crate) fn scene_file(w: &World) -> Result<SceneFile, WorldError> {
    let particle_places: BTreeMap<u32, usize> = w.particles.iter().zip(0..).map(|((h, _), k)| (h.index(), k)).collect();
    let body_places: BTreeMap<u32, usize> = w.bodies.iter().zip(0..).map(|((h, _), k)| (h.index(), k)).collect();
    let particles = w
        .particles
        .iter()
        .map(|(h, p)| ParticleFile {
            mass: p.mass,
            position: v3(&p.position),
            velocity: v3(&p.velocity),
            damping: p.damping,
            stiffness: p.stiffness,
            anchor: v3(&p.anchor),
            radius: p.radius,
            restitution: p.material.restitution,
            friction: p.material.friction,
            rolling_resistance: p.material.rolling_resistance,
            torsional_resistance: p.material.torsional_resistance,
            friction_combine: p.material.friction_combine,
            restitution_combine: p.material.restitution_combine,
            start: w.starts.particle(h.index()).map(|(x, v)| [v3(&x), v3(&v)]),
        })
        .collect();
    let bodies = w
        .bodies
        .iter()
        .map(|(h, b)| (h, b, !b.is_static && !b.is_kinematic()))
        .map(|(h, b, movable)| BodyFile {
            is_static: b.is_static,
            colliders: b
                .colliders
                .iter()
                .map(|c| ColliderFile {
                    shape: shape_file(&c.shape),
                    position: v3(&c.offset.translation.vector),
                    orientation: q4(&c.offset.rotation),
                })
                .collect(),
            mass: movable.then_some(b.mass),
            inertia: movable.then(|| {
                let i = b.inertia;
                [
                    [i[(0, 0)], i[(0, 1)], i[(0, 2)]],
                    [i[(1, 0)], i[(1, 1)], i[(1, 2)]],
                    [i[(2, 0)], i[(2, 1)], i[(2, 2)]],
                ]
            }),
            density: None,
            position: v3(&b.position),
            orientation: q4(&b.orientation),
            velocity: None,
            momentum: movable.then(|| v3(&b.momentum)),
            angular_velocity: None,
            angular_momentum: movable.then(|| v3(&b.angular_momentum)),
            linear_damping: b.linear_damping,
            angular_damping: b.angular_damping,
            restitution: b.material.restitution,
            friction: b.material.friction,
            rolling_resistance: b.material.rolling_resistance,
            torsional_resistance: b.material.torsional_resistance,
            friction_combine: b.material.friction_combine,
            restitution_combine: b.material.restitution_combine,
            start: w.starts.body(h.index()).map(|(x, q, p, l)| (v3(&x), q4(&q), v3(&p), v3(&l))),
            origin: (b.origin != Vector3::zeros()).then(|| v3(&b.origin)),
            collision_groups: (b.groups != crate::body::ALL_GROUPS).then_some(b.groups),
            name: b.look.name.clone(),
            color: b.look.color,
            keyframes: b.keyframes().map(|k| KeyframesFile {
                times: k.times().to_vec(),
                positions: k.positions().iter().map(v3).collect(),
                orientations: k.orientations().iter().map(q4).collect(),
            }),
        })
        .collect();
    let end = |a: &Attachment| match a {
        Attachment::Particle(h) => AttachmentFile::Particle(particle_places[&h.index()]),
        Attachment::Body(h, anchor) => AttachmentFile::Body { body: body_places[&h.index()], anchor: v3(anchor) },
        Attachment::Point(p) => AttachmentFile::Point(v3(p)),
    };
    let springs = w
        .springs
        .iter()
        .map(|(_, s)| SpringFile {
            a: end(&s.a),
            b: end(&s.b),
            stiffness: s.stiffness,
            damping: s.damping,
            rest_length: Some(s.rest_length),
        })
        .collect();
    let target = |t: &Target| match t {
        Target::Particle(h) => TargetFile::Particle(particle_places[&h.index()]),
        Target::Body(h) => TargetFile::Body(body_places[&h.index()]),
    };
    let loads = w
        .loads
        .iter()
        .map(|(_, l)| match l {
            Load::Force { target: t, force, at } => {
                Ok(LoadFile::Force { target: target(t), force: v3(force), at: at.as_ref().map(v3) })
            }
            Load::Torque { body, torque } => {
                Ok(LoadFile::Torque { body: body_places[&body.index()], torque: v3(torque) })
            }
            Load::Callback { .. } => Err(WorldError::invalid(
                "loads",
                "a world with a force callback cannot be saved (a callback is code); remove it first",
            )),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let place = |h: Option<crate::spring::BodyHandle>| h.map(|h| body_places[&h.index()]);
    let joints = w
        .joints
        .iter()
        .map(|(_, j)| {
            let s = &j.spec;
            let kind = match s.kind {
                JointKind::Distance { rope, .. } => JointKind::Distance { length: Some(j.length), rope },
                other => other,
            };
            JointFile {
                kind,
                a: place(s.a),
                b: place(s.b),
                anchor_a: v3(&s.anchor_a),
                anchor_b: v3(&s.anchor_b),
                axis: v3(&s.axis),
                limits: s.limits.map(|(lo, hi)| [lo, hi]),
                turn_limits: s.turn_limits.map(|(lo, hi)| [lo, hi]),
                motor: s.motor,
                spring: s.spring,
                softness: s.softness.map(|(h, z)| [h, z]),
                reference: Some(q4(&j.reference)),
                axis_b: Some(v3(&j.axis_b)),
                breaking_force: s.breaking.map(|b| b.force).filter(|f| f.is_finite()),
                breaking_torque: s.breaking.map(|b| b.torque).filter(|t| t.is_finite()),
                broken: j.broken,
                collide: s.collide,
                breaking_window: s.breaking.map_or(0.0, |b| b.window),
                cluster: s.cluster,
            }
        })
        .collect();
    Ok(SceneFile {
        format: FORMAT.into(),
        version: VERSION,
        time: w.time,
        gravity: v3(&w.gravity),
        combine: w.combine,
        mode: w.mode,
        integrator: Some(w.settings.clone()),
        threads: w.threads,
        divergence_factor: Some(w.divergence_factor),
        spring_jacobian: w.spring_jacobian,
        particles,
        bodies,
        springs,
        loads,
        joints,
        memory: None,
    })
}

//! A world built from a scene file, through the same builders and checks as one built by hand, each error said
//! with the field's path (`bodies[3].mass: ...`); states, masses and inertias as written are kept to the bit.

use super::file::*;
use crate::body::RigidBodyBuilder;
use crate::error::{check_finite, WorldError};
use crate::joint::{JointBuilder, JointKind};
use crate::keyframes::Keyframes;
use crate::limits;
use crate::load::{Load, Target};
use crate::mode::Mode;
use crate::particle::ParticleBuilder;
use crate::spring::{Attachment, BodyHandle, ParticleHandle, SpringBuilder};
use crate::world::World;
use nalgebra::{Isometry3, Matrix3, Point3, Quaternion, Translation3, Unit, UnitQuaternion, Vector3};
use tumble_collide::{Decomposed, Mesh, Shape};

/// An error of the list `list` (a field name the error carries), said with the item's path.
fn at(list: &'static str, path: String) -> impl Fn(WorldError) -> WorldError {
    move |e| match e {
        WorldError::InvalidArgument { name, reason } => WorldError::invalid(list, format!("{path}.{name}: {reason}")),
        WorldError::UnknownHandle { name, .. } => WorldError::invalid(list, format!("{path}.{name}: no such place")),
        other => other,
    }
}

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::from(a)
}

/// A quaternion (w, x, y, z) as written: kept to the bit when its norm is 1 within 1e-12 (as saved), else
/// normalised (as a person writes it); not finite or zero is an error.
fn quaternion(name: &'static str, q: [f64; 4]) -> Result<UnitQuaternion<f64>, WorldError> {
    let q = Quaternion::new(q[0], q[1], q[2], q[3]);
    let n = q.norm();
    if !(n.is_finite() && n > 0.0) {
        return Err(WorldError::invalid(name, format!("must be a finite nonzero quaternion, got {q:?}")));
    }
    Ok(if (n - 1.0).abs() <= 1e-12 { UnitQuaternion::new_unchecked(q) } else { UnitQuaternion::new_normalize(q) })
}

pub(crate) fn shape(s: &ShapeFile) -> Result<Shape, WorldError> {
    let points = |ps: &[[f64; 3]]| ps.iter().map(|&p| Point3::from(p)).collect::<Vec<_>>();
    Ok(match s {
        ShapeFile::Sphere { radius } => Shape::sphere(*radius)?,
        ShapeFile::Box { half_extents } => Shape::cuboid(v3(*half_extents))?,
        ShapeFile::Capsule { half_height, radius } => Shape::capsule(*half_height, *radius)?,
        ShapeFile::Cylinder { half_height, radius } => Shape::cylinder(*half_height, *radius)?,
        ShapeFile::ConvexHull { points: p, faces: None } => Shape::convex_hull(&points(p))?,
        ShapeFile::ConvexHull { points: p, faces: Some(f) } => Shape::convex_mesh(&points(p), f)?,
        ShapeFile::TriMesh { vertices, triangles } => Shape::trimesh(&points(vertices), triangles)?,
        ShapeFile::Mesh { vertices, triangles, name, decomposition } => {
            let mesh = Mesh::new(&points(vertices), triangles, name)?;
            match decomposition {
                Some(params) => Shape::decomposed(&mesh, params)?,
                None => Shape::mesh(mesh),
            }
        }
        ShapeFile::DecomposedMesh { vertices, triangles, name, decomposition, pieces, seconds } => {
            let mesh = Mesh::new(&points(vertices), triangles, name)?;
            let pieces: Vec<Vec<Point3<f64>>> = pieces.iter().map(|p| points(p)).collect();
            if !(seconds.is_finite() && *seconds >= 0.0) {
                return Err(WorldError::invalid("seconds", format!("must be finite and >= 0, got {seconds}")));
            }
            Shape::Decomposed(Decomposed::from_pieces(&mesh, decomposition, &pieces, *seconds)?)
        }
        ShapeFile::HalfSpace { normal } => {
            let n = v3(*normal);
            if n.iter().all(|c| c.is_finite()) && (n.norm() - 1.0).abs() <= 1e-12 {
                Shape::HalfSpace { normal: Unit::new_unchecked(n) }
            } else {
                Shape::half_space(n)?
            }
        }
    })
}

fn collider(c: &ColliderFile) -> Result<(Shape, Isometry3<f64>), WorldError> {
    let rotation = quaternion("orientation", c.orientation)?;
    limits::vector("position", &v3(c.position), limits::COORDINATE, "m")?;
    Ok((shape(&c.shape)?, Isometry3::from_parts(Translation3::from(v3(c.position)), rotation)))
}

fn body_builder(b: &BodyFile) -> Result<RigidBodyBuilder, WorldError> {
    let colliders =
        b.colliders.iter().enumerate().map(|(k, c)| collider(c).map_err(at("colliders", format!("colliders[{k}]"))));
    let colliders = colliders.collect::<Result<Vec<_>, _>>()?;
    if let Some(k) = &b.keyframes {
        return kinematic_builder(b, k, colliders);
    }
    let mut builder = match (b.is_static, b.mass, b.inertia, b.density) {
        (true, None, None, None) => RigidBodyBuilder::fixed(None),
        (true, ..) => return Err(WorldError::invalid("static", "a static body has no mass, inertia or density")),
        (false, Some(m), Some(i), None) => RigidBodyBuilder::new(m, Matrix3::from_fn(|r, c| i[r][c])),
        (false, m, None, d) => {
            let Some((first, pose)) = colliders.first() else {
                return Err(WorldError::invalid("colliders", "a body without mass and inertia needs a shape"));
            };
            if *pose != Isometry3::identity() {
                return Err(WorldError::invalid(
                    "colliders",
                    "with a density or a mass alone, the first collider sits at the body's origin (no position or orientation)",
                ));
            }
            match (m, d) {
                (Some(m), None) => RigidBodyBuilder::from_shape_with_mass(first.clone(), m),
                (None, Some(d)) => RigidBodyBuilder::from_shape(first.clone(), d),
                _ => return Err(WorldError::invalid("density", "give a density, or a mass (with or without inertia)")),
            }
        }
        (false, _, Some(_), _) => return Err(WorldError::invalid("inertia", "an inertia needs a mass and no density")),
    };
    let skip = usize::from(!b.is_static && b.inertia.is_none());
    for (s, pose) in colliders.into_iter().skip(skip) {
        builder = builder.collider(s, pose);
    }
    let both = |name: &'static str, x: bool, y: bool| {
        if x && y {
            Err(WorldError::invalid(name, "give it or its momentum, not both"))
        } else {
            Ok(())
        }
    };
    both("velocity", b.velocity.is_some(), b.momentum.is_some())?;
    both("angular_velocity", b.angular_velocity.is_some(), b.angular_momentum.is_some())?;
    if let Some(o) = b.origin {
        limits::vector("origin", &v3(o), limits::COORDINATE, "m")?;
        builder = builder.origin_offset(v3(o));
    }
    // the position is put in exactly by `exact_fields`, within the bound of states a file may hold
    Ok(surface(builder, b)
        .orientation(quaternion("orientation", b.orientation)?)
        .velocity(v3(b.velocity.unwrap_or_default()))
        .angular_velocity(v3(b.angular_velocity.unwrap_or_default()))
        .linear_damping(b.linear_damping)
        .angular_damping(b.angular_damping))
}

/// A body's collision groups, look and material from its file.
fn surface(mut builder: RigidBodyBuilder, b: &BodyFile) -> RigidBodyBuilder {
    if let Some(groups) = b.collision_groups {
        builder = builder.collision_groups(groups);
    }
    if let Some(name) = &b.name {
        builder = builder.name(name.clone());
    }
    if let Some(rgba) = b.color {
        builder = builder.color(rgba);
    }
    builder.material(b.material())
}

/// A kinematic body from its file: its path, colliders, look and material (its pose follows from the path).
fn kinematic_builder(
    b: &BodyFile,
    k: &KeyframesFile,
    colliders: Vec<(Shape, Isometry3<f64>)>,
) -> Result<RigidBodyBuilder, WorldError> {
    if b.is_static {
        return Err(WorldError::invalid("keyframes", "a static body has no keyframes"));
    }
    let orientations = k.orientations.iter().map(|q| quaternion("keyframes", *q)).collect::<Result<Vec<_>, _>>()?;
    let path = Keyframes::new(k.times.clone(), k.positions.iter().map(|p| v3(*p)).collect(), Some(orientations))?;
    let mut builder = RigidBodyBuilder::kinematic(None, path);
    for (s, pose) in colliders {
        builder = builder.collider(s, pose);
    }
    Ok(surface(builder, b))
}

/// The bound on positions and velocities a file may hold: beyond what a user may set (1e12 m, 1e12 m/s), since a
/// world's own steps can carry it further before its divergence limit stops them, and a world must load what it
/// saved; within it, energies and momenta stay finite.
const STATE: f64 = 1e100;

/// A world from a scene file.
pub(crate) fn world_from(f: &SceneFile) -> Result<World, WorldError> {
    if f.format != FORMAT {
        return Err(WorldError::invalid("format", format!("expected \"{FORMAT}\", got \"{}\"", f.format)));
    }
    if f.version != VERSION {
        return Err(WorldError::invalid(
            "version",
            format!("this tumble reads version {VERSION} of the scene format, the file is version {}", f.version),
        ));
    }
    let mut w = World::new();
    w.set_gravity(v3(f.gravity))?;
    w.set_combine_rules(f.combine);
    w.set_threads(f.threads)?;
    if let Some(factor) = f.divergence_factor {
        w.set_divergence_factor(factor)?;
    }
    w.set_spring_jacobian(f.spring_jacobian);
    let mut particles: Vec<ParticleHandle> = Vec::new();
    for (k, p) in f.particles.iter().enumerate() {
        let builder = ParticleBuilder::new(p.mass)
            .damping(p.damping)
            .stiffness(p.stiffness)
            .anchor(v3(p.anchor))
            .radius(p.radius)
            .material(p.material());
        let h = w.add_particle(builder).map_err(at("particles", format!("particles[{k}]")))?;
        let (x, v) = (v3(p.position), v3(p.velocity));
        limits::vector("position", &x, STATE, "m").map_err(at("particles", format!("particles[{k}]")))?;
        limits::vector("velocity", &v, STATE, "m/s").map_err(at("particles", format!("particles[{k}]")))?;
        if let Some(particle) = w.particles.get_mut(h) {
            (particle.position, particle.velocity) = (x, v);
        }
        w.record_particle_start(h);
        if let Some([x, v]) = p.start {
            let (x, v) = (v3(x), v3(v));
            limits::vector("start", &x, limits::COORDINATE, "m").map_err(at("particles", format!("particles[{k}]")))?;
            limits::vector("start", &v, limits::SPEED, "m/s").map_err(at("particles", format!("particles[{k}]")))?;
            w.starts.set_particle(h.index(), (x, v));
        }
        particles.push(h);
    }
    let mut bodies: Vec<BodyHandle> = Vec::new();
    for (k, b) in f.bodies.iter().enumerate() {
        let path = format!("bodies[{k}]");
        let h = body_builder(b).and_then(|builder| w.add_body(builder)).map_err(at("bodies", path.clone()))?;
        exact_fields(&mut w, h, b).map_err(at("bodies", path))?;
        bodies.push(h);
    }
    let particle = |list: &'static str, path: &str, i: usize| {
        particles.get(i).copied().ok_or_else(|| WorldError::invalid(list, format!("{path}: no particle at place {i}")))
    };
    let body = |list: &'static str, path: &str, i: usize| {
        bodies.get(i).copied().ok_or_else(|| WorldError::invalid(list, format!("{path}: no body at place {i}")))
    };
    for (k, s) in f.springs.iter().enumerate() {
        let end = |e: &AttachmentFile, side: &str| -> Result<Attachment, WorldError> {
            let path = format!("springs[{k}].{side}");
            Ok(match e {
                AttachmentFile::Particle(i) => Attachment::Particle(particle("springs", &path, *i)?),
                AttachmentFile::Body { body: i, anchor } => Attachment::Body(body("springs", &path, *i)?, v3(*anchor)),
                AttachmentFile::Point(p) => Attachment::Point(v3(*p)),
            })
        };
        let mut builder =
            SpringBuilder::new(end(&s.a, "a")?, end(&s.b, "b")?).stiffness(s.stiffness).damping(s.damping);
        if let Some(l) = s.rest_length {
            builder = builder.rest_length(l);
        }
        w.add_spring(builder).map_err(at("springs", format!("springs[{k}]")))?;
    }
    for (k, l) in f.loads.iter().enumerate() {
        let path = format!("loads[{k}]");
        let load = match l {
            LoadFile::Force { target, force, at: point } => {
                let target = match target {
                    TargetFile::Particle(i) => Target::Particle(particle("loads", &path, *i)?),
                    TargetFile::Body(i) => Target::Body(body("loads", &path, *i)?),
                };
                Load::Force { target, force: v3(*force), at: point.map(v3) }
            }
            LoadFile::Torque { body: i, torque } => {
                Load::Torque { body: body("loads", &path, *i)?, torque: v3(*torque) }
            }
        };
        w.add_load(load).map_err(at("loads", path))?;
    }
    // the mode before the joints, which must fit it (a soft joint only in fast mode)
    w.set_mode(f.mode)?;
    for (k, j) in f.joints.iter().enumerate() {
        let path = format!("joints[{k}]");
        let end = |i: Option<usize>| i.map(|i| body("joints", &path, i)).transpose();
        let (a, b) = (end(j.a)?, end(j.b)?);
        let mut builder = match j.kind {
            JointKind::Ball => JointBuilder::ball(a, b),
            JointKind::Hinge => JointBuilder::hinge(a, b, v3(j.axis)),
            JointKind::Slider => JointBuilder::slider(a, b, v3(j.axis)),
            JointKind::Weld => JointBuilder::weld(a, b),
            JointKind::Piston => JointBuilder::piston(a, b, v3(j.axis)),
            JointKind::Drive { linear: false } => JointBuilder::spin_drive(a, b, v3(j.axis)),
            JointKind::Drive { linear: true } => JointBuilder::slide_drive(a, b, v3(j.axis)),
            JointKind::Distance { length, rope: false } => JointBuilder::distance(a, b, length),
            JointKind::Distance { length, rope: true } => JointBuilder::rope(a, b, length),
        };
        builder = builder.anchor_a(v3(j.anchor_a)).anchor_b(v3(j.anchor_b)).axis(v3(j.axis));
        if let Some([lo, hi]) = j.limits {
            builder = builder.limits(lo, hi);
        }
        if let Some([lo, hi]) = j.turn_limits {
            builder = builder.turn_limits(lo, hi);
        }
        if let Some(m) = j.motor {
            builder = builder.motor(m.speed, m.max_force);
        }
        if let Some(sp) = j.spring {
            builder = builder.spring(sp.stiffness, sp.damping, sp.target);
        }
        if let Some([hz, zeta]) = j.softness {
            builder = builder.softness(hz, zeta);
        }
        builder = builder.collide(j.collide).cluster(j.cluster);
        if j.breaking_force.is_some() || j.breaking_torque.is_some() {
            let bound = |b: Option<f64>| b.unwrap_or(f64::INFINITY);
            builder = builder.breaking_averaged(bound(j.breaking_force), bound(j.breaking_torque), j.breaking_window);
        }
        let h = w.add_joint(builder).map_err(at("joints", path.clone()))?;
        // the joint's zero as it was made, to the bit
        let joint = w.joints.get_mut(h).expect("just added");
        joint.broken = j.broken;
        if let Some(q) = j.reference {
            joint.reference = quaternion("reference", q).map_err(at("joints", path.clone()))?;
        }
        if let Some(axis) = j.axis_b {
            let axis = v3(axis);
            if !(axis.iter().all(|c| c.is_finite()) && (axis.norm() - 1.0).abs() < 1e-9) {
                return Err(WorldError::invalid("joints", format!("{path}.axis_b: must be a unit vector")));
            }
            joint.axis_b = axis;
        }
    }
    if let Some(settings) = &f.integrator {
        match f.mode {
            Mode::Accurate(_) => w.set_integrator(settings.clone()).map_err(at("integrator", "integrator".into()))?,
            Mode::Fast(_) => w.settings = settings.clone(),
        }
    }
    w.time = limits::in_range("time", f.time, -limits::TIME, limits::TIME, "s")?;
    let t = w.time;
    w.bodies.iter_mut().for_each(|(_, b)| b.follow(t));
    w.stepped = f.particles.iter().any(|p| p.start.is_some()) || f.bodies.iter().any(|b| b.start.is_some());
    Ok(w)
}

/// Puts a body's momenta, collider placements (given its mass and inertia) and start as written, to the bit.
fn exact_fields(w: &mut World, h: BodyHandle, f: &BodyFile) -> Result<(), WorldError> {
    let b = w.bodies.get_mut(h).ok_or_else(|| WorldError::invalid("bodies", "lost"))?;
    if f.is_static || f.inertia.is_some() {
        for (c, written) in b.colliders.iter_mut().zip(&f.colliders) {
            c.offset.translation.vector = v3(written.position);
        }
    }
    if b.is_kinematic() {
        // its pose is its path's at the world's time, put in once the time is read
        return Ok(());
    }
    limits::vector("position", &v3(f.position), STATE, "m")?;
    b.position = v3(f.position);
    if !b.is_static {
        if let Some(p) = f.momentum {
            limits::vector("momentum", &(v3(p) / b.mass), STATE, "m/s (p / m)")?;
            b.momentum = v3(p);
        }
        if let Some(l) = f.angular_momentum {
            check_finite("angular_momentum", l.iter())?;
            b.angular_momentum = v3(l);
        }
    }
    if let Some((x, q, p, l)) = f.start {
        limits::vector("start", &v3(x), limits::COORDINATE, "m")?;
        check_finite("start", p.iter().chain(l.iter()))?;
        let start = (v3(x), quaternion("start", q)?, v3(p), v3(l));
        w.starts.set_body(h.index(), start);
    } else {
        w.record_body_start(h);
    }
    Ok(())
}

//! Mesh scenes, every mesh built in code: a ball dropped into a cup, a ring tossed onto a peg, a chair of one
//! non-convex mesh on its four legs, a torus rolling, and a pile of mixed meshes. Each takes the mode to run in.

use crate::body::RigidBodyBuilder;
use crate::collider::Material;
use crate::error::WorldError;
use crate::mesh_shape::MeshShape;
use crate::mode::Mode;
use crate::spring::BodyHandle;
use crate::world::World;
use nalgebra::{UnitQuaternion, Vector3};
use tumble_collide::{Mesh, Shape};

/// Floor and surfaces: no bounce, friction 0.5.
const MATERIAL: Material = Material::new(0.0, 0.5);

/// The cup of `ball_in_cup`: 5 cm outer radius, 8 cm tall, 5 mm walls, 48 segments around.
pub fn cup() -> Result<Mesh, WorldError> {
    Ok(Mesh::cup_mesh(0.05, 0.08, 0.005, 48)?)
}

/// A world in `mode` with the ground at z = 0.
fn world(mode: Mode) -> Result<World, WorldError> {
    let mut w = World::new();
    w.set_mode(mode)?;
    w.add_ground(0.0, MATERIAL)?;
    Ok(w)
}

/// A body of a mesh at `density`, turned by `turn`, its modelled origin above (x, y) and its lowest point `gap`
/// above z = `floor` (a mesh body is placed by its modelled frame).
fn dropped(
    shape: Shape,
    density: f64,
    turn: UnitQuaternion<f64>,
    (x, y): (f64, f64),
    floor: f64,
    gap: f64,
) -> Result<RigidBodyBuilder, WorldError> {
    let low = shape.aabb(&nalgebra::Isometry3::from_parts(nalgebra::Translation3::identity(), turn))?.min.z;
    Ok(RigidBodyBuilder::from_shape(shape, density)
        .position(Vector3::new(x, y, floor + gap - low))
        .orientation(turn)
        .restitution(0.0)
        .friction(0.5))
}

/// A ceramic cup (2400 kg/m^3) standing on the floor and a 3 cm rubber ball (1100 kg/m^3, restitution 0.3) dropped
/// into it from 7 cm above its rim, 1 cm off its axis; `as_hull` gives the cup its convex hull instead of its
/// decomposition (the ball then lands on the hull's lid). Returns the world, the cup and the ball.
pub fn ball_in_cup(mode: Mode, as_hull: bool) -> Result<(World, BodyHandle, BodyHandle), WorldError> {
    let mut w = world(mode)?;
    let mut c = dropped(Shape::mesh(cup()?), 2400.0, UnitQuaternion::identity(), (0.0, 0.0), 0.0, 1e-4)?;
    if as_hull {
        c = c.mesh_shape(MeshShape::Hull);
    }
    let cup = w.add_body(c.name("cup").color(super::hue(1)))?;
    let ball = w.add_body(
        RigidBodyBuilder::from_shape(Shape::sphere(0.015)?, 1100.0)
            .position(Vector3::new(0.01, 0.0, 0.08 + 0.07))
            .restitution(0.3)
            .friction(0.5)
            .name("ball")
            .color(super::hue(0)),
    )?;
    Ok((w, cup, ball))
}

/// A static peg (a cylinder mesh, 1.2 cm radius, 12 cm tall) and a wooden ring (a torus of 3 cm radius, 6 mm tube,
/// 700 kg/m^3) tossed onto it: 5 cm above its top, tilted 8 degrees, moving 0.05 m/s sideways. Returns the world,
/// the peg and the ring.
pub fn ring_on_peg(mode: Mode) -> Result<(World, BodyHandle, BodyHandle), WorldError> {
    let mut w = world(mode)?;
    let peg_mesh = Mesh::cylinder_mesh(0.06, 0.012, 32)?;
    let peg = w.add_body(
        RigidBodyBuilder::fixed(Some(Shape::mesh(peg_mesh)))
            .position(Vector3::new(0.0, 0.0, 0.06))
            .name("peg")
            .color(super::hue(5)),
    )?;
    let torus = Shape::mesh(Mesh::torus_mesh(0.03, 0.006, 32)?);
    let ring = w.add_body(
        RigidBodyBuilder::from_shape(torus, 700.0)
            .position(Vector3::new(-0.004, 0.0, 0.17))
            .orientation(UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 8f64.to_radians()))
            .velocity(Vector3::new(0.05, 0.0, 0.0))
            .restitution(0.0)
            .friction(0.4)
            .name("ring")
            .color(super::hue(2)),
    )?;
    Ok((w, peg, ring))
}

/// The chair's grid cells (5 cm): a 9 x 9 seat one cell thick on four 1 x 1 legs nine cells tall, and a back of 9 x
/// 1 cells ten tall along one edge.
fn chair_cells() -> Vec<[i32; 3]> {
    let mut cells = Vec::new();
    for x in 0..9 {
        for y in 0..9 {
            cells.push([x, y, 9]);
        }
        for z in 10..20 {
            cells.push([x, 8, z]);
        }
    }
    for (x, y) in [(0, 0), (8, 0), (0, 8), (8, 8)] {
        for z in 0..9 {
            cells.push([x, y, z]);
        }
    }
    cells
}

/// A wooden chair (600 kg/m^3) of one non-convex mesh, set down 1 mm above the floor on its four legs.
pub fn chair(mode: Mode) -> Result<(World, BodyHandle), WorldError> {
    let mut w = world(mode)?;
    let mesh = Mesh::from_cells(&chair_cells(), 0.05, "chair")?;
    let chair = dropped(Shape::mesh(mesh), 600.0, UnitQuaternion::identity(), (0.0, 0.0), 0.0, 1e-3)?;
    let c = w.add_body(chair.name("chair").color(super::hue(2)))?;
    Ok((w, c))
}

/// A rubber torus (10 cm radius, 3 cm tube, 1100 kg/m^3) standing on edge, rolling at 1 m/s along x.
pub fn torus_roll(mode: Mode) -> Result<(World, BodyHandle), WorldError> {
    let mut w = world(mode)?;
    let (major, minor) = (0.1, 0.03);
    let torus = Shape::mesh(Mesh::torus_mesh(major, minor, 48)?);
    let speed = 1.0;
    let radius = major + minor;
    let t = w.add_body(
        RigidBodyBuilder::from_shape(torus, 1100.0)
            .position(Vector3::new(0.0, 0.0, radius + 1e-4))
            .orientation(UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2))
            .velocity(Vector3::new(speed, 0.0, 0.0))
            .angular_velocity(Vector3::new(0.0, speed / radius, 0.0))
            .restitution(0.0)
            .friction(0.8)
            .name("torus")
            .color(super::hue(3)),
    )?;
    Ok((w, t))
}

/// `count` meshes of five kinds (cup, ring, chair-like stool, pebble, peg), each about 10 cm, dropped in a loose
/// column onto the floor; `as_hull` gives each its convex hull instead of its decomposition. Returns the world and
/// the bodies.
pub fn mesh_pile(mode: Mode, count: usize, as_hull: bool) -> Result<(World, Vec<BodyHandle>), WorldError> {
    let mut w = world(mode)?;
    let kinds = pile_meshes()?;
    let mut bodies = Vec::with_capacity(count);
    for k in 0..count {
        // 16 a layer on a 20 cm grid, layers 20 cm apart: no two overlap however they are turned (17 cm at most)
        let (layer, slot) = (k / 16, k % 16);
        let xy = (0.2 * (slot % 4) as f64 - 0.3, 0.2 * (slot / 4) as f64 - 0.3);
        let turn = UnitQuaternion::from_euler_angles(0.3 * k as f64, 0.7 * k as f64, 1.1 * k as f64);
        // the same five meshes, turned: each is decomposed once
        let mesh = kinds[k % kinds.len()].clone();
        let name = format!("{} {}", if mesh.name().is_empty() { "mesh" } else { mesh.name() }, k + 1);
        let mut b =
            dropped(Shape::mesh(mesh), 800.0, turn, xy, 0.2 * layer as f64, 0.01)?.name(name).color(super::hue(k));
        if as_hull {
            b = b.mesh_shape(MeshShape::Hull);
        }
        bodies.push(w.add_body(b)?);
    }
    Ok((w, bodies))
}

/// The pile's five meshes.
fn pile_meshes() -> Result<Vec<Mesh>, WorldError> {
    let stool: Vec<[i32; 3]> = (0..4)
        .flat_map(|x| (0..4).map(move |y| [x, y, 3]))
        .chain([(0, 0), (3, 0), (0, 3), (3, 3)].into_iter().flat_map(|(x, y)| (0..3).map(move |z| [x, y, z])))
        .collect();
    let pebble = Mesh::sphere_mesh(0.04, 16)?;
    let squash: Vec<_> = pebble.vertices().iter().map(|p| nalgebra::Point3::new(p.x * 1.3, p.y, p.z * 0.6)).collect();
    Ok(vec![
        Mesh::cup_mesh(0.04, 0.07, 0.006, 24)?,
        Mesh::torus_mesh(0.035, 0.01, 20)?,
        Mesh::from_cells(&stool, 0.025, "stool")?,
        Mesh::new(&squash, pebble.triangles(), "pebble")?,
        Mesh::cylinder_mesh(0.04, 0.015, 16)?,
    ])
}

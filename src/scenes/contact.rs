//! Contact scenes: a ball bouncing with e = 0.8 (accurate mode), a box thrown tumbling onto the floor, a row of
//! dominoes, a pyramid of boxes, a pile of boxes dropped together and a cloth of particles draping over a sphere
//! (fast mode).

use crate::body::RigidBodyBuilder;
use crate::collider::Material;
use crate::error::WorldError;
use crate::mode::{FastSettings, Mode};
use crate::particle::ParticleBuilder;
use crate::spring::{BodyHandle, ParticleHandle};
use crate::world::World;
use nalgebra::{UnitQuaternion, Vector3};
use tumble_collide::Shape;
use tumble_integrate::{Method, Settings};

/// A ball dropped onto the floor, bouncing with coefficient of restitution e (accurate mode: every bounce located
/// by bisection, the n-th apex at e^(2n) times the drop height).
#[derive(Clone, Debug, PartialEq)]
pub struct BouncingBall {
    /// Coefficient of restitution of ball and floor.
    pub restitution: f64,
    /// Ball radius (m).
    pub radius: f64,
    /// Height of the ball's lowest point above the floor at the start (m).
    pub height: f64,
}

impl Default for BouncingBall {
    fn default() -> Self {
        BouncingBall { restitution: 0.8, radius: 0.1, height: 1.0 }
    }
}

impl BouncingBall {
    /// Checks every parameter by name: restitution 0..=1, radius 1e-6..=1e6 m, height 0..=1e9 m.
    pub fn check(&self) -> Result<(), WorldError> {
        super::within("restitution", self.restitution, 0.0, 1.0)?;
        super::within("radius", self.radius, 1e-6, 1e6)?;
        super::within("height", self.height, 0.0, 1e9)?;
        Ok(())
    }

    /// The world (Dormand-Prince at rtol 1e-10, atol 1e-12; frictionless) and the ball.
    pub fn build(&self) -> Result<(World, BodyHandle), WorldError> {
        self.check()?;
        let mut w = World::new();
        w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-10, 1e-12))?;
        w.add_ground(0.0, Material::new(self.restitution, 0.0))?;
        let ball = w.add_body(
            RigidBodyBuilder::from_shape(Shape::sphere(self.radius)?, 1000.0)
                .position(Vector3::new(0.0, 0.0, self.height + self.radius))
                .restitution(self.restitution)
                .friction(0.0)
                .name("ball")
                .color(super::hue(1)),
        )?;
        Ok((w, ball))
    }
}

/// A box thrown spinning onto the floor, where friction and restitution 0.3 bring it to rest (fast mode, 1/240 s).
pub fn tumbling_box() -> Result<(World, BodyHandle), WorldError> {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0)))?;
    w.add_ground(0.0, Material::new(0.3, 0.6))?;
    let b = w.add_body(
        RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.3, 0.2, 0.15))?, 600.0)
            .position(Vector3::new(-1.5, 0.0, 1.5))
            .orientation(UnitQuaternion::from_euler_angles(0.4, 0.3, 0.2))
            .velocity(Vector3::new(2.0, 0.3, 1.0))
            .angular_velocity(Vector3::new(4.0, 6.0, 2.0))
            .restitution(0.3)
            .friction(0.6)
            .name("box")
            .color(super::hue(2)),
    )?;
    Ok((w, b))
}

/// A row of dominoes on the floor; the first is tipped toward the others (fast mode, 1/240 s).
#[derive(Clone, Debug, PartialEq)]
pub struct Dominoes {
    /// How many.
    pub count: usize,
    /// Distance between neighbours (m); each is 0.08 x 0.4 x 0.8 m.
    pub spacing: f64,
}

impl Default for Dominoes {
    fn default() -> Self {
        Dominoes { count: 20, spacing: 0.5 }
    }
}

impl Dominoes {
    /// Checks every parameter by name: count 1..=1000, spacing 1e-3..=1e6 m.
    pub fn check(&self) -> Result<(), WorldError> {
        if !(1..=1000).contains(&self.count) {
            return Err(WorldError::invalid("count", format!("must be from 1 to 1000 dominoes, got {}", self.count)));
        }
        super::within("spacing", self.spacing, 1e-3, 1e6)?;
        Ok(())
    }

    /// The world and the dominoes in order.
    pub fn build(&self) -> Result<(World, Vec<BodyHandle>), WorldError> {
        self.check()?;
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0)))?;
        w.add_ground(0.0, Material::new(0.1, 0.6))?;
        let half = Vector3::new(0.04, 0.2, 0.4);
        let mut row = Vec::with_capacity(self.count);
        for k in 0..self.count {
            let mut b = RigidBodyBuilder::from_shape(Shape::cuboid(half)?, 700.0)
                .position(Vector3::new(k as f64 * self.spacing, 0.0, half.z))
                .restitution(0.1)
                .friction(0.4)
                .name(format!("domino {}", k + 1))
                .color(super::hue(k % 2));
            if k == 0 {
                b = b.angular_velocity(Vector3::new(0.0, 2.0, 0.0));
            }
            row.push(w.add_body(b)?);
        }
        Ok((w, row))
    }
}

/// A 2D pyramid of cubes (edge 0.5 m), `layers` high, each cube resting on two below (fast mode, 1/240 s).
#[derive(Clone, Debug, PartialEq)]
pub struct Pyramid {
    /// Number of layers (the bottom one has as many cubes).
    pub layers: usize,
}

impl Default for Pyramid {
    fn default() -> Self {
        Pyramid { layers: 10 }
    }
}

impl Pyramid {
    /// Checks the number of layers: 1..=1000.
    pub fn check(&self) -> Result<(), WorldError> {
        if !(1..=1000).contains(&self.layers) {
            return Err(WorldError::invalid("layers", format!("must be from 1 to 1000, got {}", self.layers)));
        }
        Ok(())
    }

    /// The world and the cubes, bottom layer first.
    pub fn build(&self) -> Result<(World, Vec<BodyHandle>), WorldError> {
        self.check()?;
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0)))?;
        w.add_ground(0.0, Material::new(0.0, 0.6))?;
        let mut cubes = Vec::new();
        for layer in 0..self.layers {
            for k in 0..self.layers - layer {
                let x = (k as f64 + 0.5 * layer as f64) * 0.5;
                cubes.push(
                    w.add_body(
                        RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.25))?, 500.0)
                            .position(Vector3::new(x, 0.0, 0.25 + 0.5 * layer as f64))
                            .restitution(0.0)
                            .friction(0.6)
                            .name(format!("cube {} of layer {}", k + 1, layer + 1))
                            .color(super::hue(layer)),
                    )?,
                );
            }
        }
        Ok((w, cubes))
    }
}

/// A pile: cubes of edge 0.5 m (500 kg/m^3, restitution 0.2, friction 0.6) on a `side` x `side` grid 0.6 m apart
/// in `layers` layers 0.6 m apart, each slightly tilted, dropped together onto the floor (fast mode, 1/240 s).
#[derive(Clone, Debug, PartialEq)]
pub struct Pile {
    /// Cubes along each side of a layer.
    pub side: usize,
    /// Layers.
    pub layers: usize,
}

impl Default for Pile {
    fn default() -> Self {
        Pile { side: 10, layers: 1 }
    }
}

impl Pile {
    /// Checks the sizes by name: side and layers from 1, at most 100,000 cubes in all.
    pub fn check(&self) -> Result<(), WorldError> {
        if self.side == 0 || self.side > 1000 {
            return Err(WorldError::invalid("side", format!("must be from 1 to 1000, got {}", self.side)));
        }
        if self.layers == 0 || self.side.saturating_mul(self.side).saturating_mul(self.layers) > 100_000 {
            return Err(WorldError::invalid(
                "layers",
                format!(
                    "{} layers of {} x {} cubes: from 1 layer to 100,000 cubes in all",
                    self.layers, self.side, self.side
                ),
            ));
        }
        Ok(())
    }

    /// The world and the cubes, layer by layer.
    pub fn build(&self) -> Result<(World, Vec<BodyHandle>), WorldError> {
        self.check()?;
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0)))?;
        w.add_ground(0.0, Material::new(0.2, 0.6))?;
        let cube = Shape::cuboid(Vector3::repeat(0.25))?;
        let mut cubes = Vec::new();
        let mut n = 0u32;
        for layer in 0..self.layers {
            for i in 0..self.side {
                for j in 0..self.side {
                    n += 1;
                    let tilt = 0.05 * ((n * 7919 % 13) as f64 / 13.0 - 0.5);
                    cubes.push(
                        w.add_body(
                            RigidBodyBuilder::from_shape(cube.clone(), 500.0)
                                .position(Vector3::new(0.6 * i as f64, 0.6 * j as f64, 0.3 + 0.6 * layer as f64))
                                .orientation(UnitQuaternion::from_euler_angles(tilt, -tilt, 2.0 * tilt))
                                .restitution(0.2)
                                .friction(0.6)
                                .name(format!("cube {n}"))
                                .color(super::hue(n as usize)),
                        )?,
                    );
                }
            }
        }
        Ok((w, cubes))
    }
}

/// A square cloth of n x n particles (each a 1 cm sphere) dropped over a ball of radius 0.3 m resting on the floor
/// (fast mode, 1/480 s: the springs are explicit there, and 1/480 s keeps them stable).
#[derive(Clone, Debug, PartialEq)]
pub struct ClothDrape {
    /// Particles along a side.
    pub n: usize,
    /// Side length (m).
    pub size: f64,
}

impl Default for ClothDrape {
    fn default() -> Self {
        ClothDrape { n: 12, size: 1.2 }
    }
}

impl ClothDrape {
    /// Checks every parameter by name: n 2..=1000, size 1e-3..=1e3 m.
    pub fn check(&self) -> Result<(), WorldError> {
        super::side_count("n", self.n)?;
        super::within("size", self.size, 1e-3, 1e3)?;
        Ok(())
    }

    /// The world and the particles, row by row.
    pub fn build(&self) -> Result<(World, Vec<ParticleHandle>), WorldError> {
        self.check()?;
        let n = self.n;
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(1.0 / 480.0) }))?;
        w.add_ground(0.0, Material::new(0.0, 0.5))?;
        w.add_body(
            RigidBodyBuilder::fixed(Some(Shape::sphere(0.3)?))
                .position(Vector3::new(0.0, 0.0, 0.3))
                .restitution(0.0)
                .friction(0.5)
                .name("ball")
                .color(super::hue(1)),
        )?;
        let spacing = self.size / (n - 1) as f64;
        let m = 0.3 / (n * n) as f64;
        let mut ps = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let x = Vector3::new(i as f64 * spacing - 0.5 * self.size, j as f64 * spacing - 0.5 * self.size, 0.9);
                let p = ParticleBuilder::new(m).position(x).radius(0.01).material(Material::new(0.0, 0.5));
                ps.push(w.add_particle(p)?);
            }
        }
        super::weave(&mut w, &ps, n, 60.0, 0.05)?;
        Ok((w, ps))
    }
}

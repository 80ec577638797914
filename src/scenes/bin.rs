//! A bin filled as an animator fills one: `count` bodies of random sizes (masses up to about 16 times each other),
//! dropped in layers onto a 4 x 4 m floor walled on four sides 4 m high; boxes only, or a mix of boxes, balls, capsules and
//! convex hulls. Seeded: the same bodies every time. Fast mode at 1/60 s.

use crate::body::RigidBodyBuilder;
use crate::error::WorldError;
use crate::mode::{FastSettings, Mode};
use crate::spring::BodyHandle;
use crate::world::World;
use nalgebra::{Point3, UnitQuaternion, Vector3};
use tumble_collide::Shape;

/// What fills the bin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fill {
    /// Boxes of one size (half extent 0.15 m).
    EqualBoxes,
    /// Boxes of random sizes (half extents 0.1 to 0.25 m each way).
    MixedBoxes,
    /// Boxes, balls, capsules and convex hulls of random sizes.
    MixedShapes,
}

/// A walled bin and what fills it.
#[derive(Clone, Debug, PartialEq)]
pub struct Bin {
    pub count: usize,
    pub fill: Fill,
    pub seed: u64,
}

impl Default for Bin {
    fn default() -> Self {
        Bin { count: 500, fill: Fill::MixedBoxes, seed: 1 }
    }
}

/// Side of the bin's square floor (m) and its walls' height.
const SIDE: f64 = 4.0;
const WALL: f64 = 2.0;
/// Density of every body (kg/m^3).
const DENSITY: f64 = 500.0;

/// A seeded generator.
struct Lcg(u64);

impl Lcg {
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

impl Bin {
    /// The world and the bodies that fill the bin.
    pub fn build(&self) -> Result<(World, Vec<BodyHandle>), WorldError> {
        if !(1..=100_000).contains(&self.count) {
            return Err(WorldError::invalid("count", format!("must be from 1 to 100000, got {}", self.count)));
        }
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 60.0)))?;
        let floor = Shape::cuboid(Vector3::new(0.5 * SIDE + 0.1, 0.5 * SIDE + 0.1, 0.1))?;
        w.add_body(RigidBodyBuilder::fixed(Some(floor)).position(Vector3::new(0.0, 0.0, -0.1)).friction(0.6))?;
        for (x, y, along_x) in [(0.5, 0.0, false), (-0.5, 0.0, false), (0.0, 0.5, true), (0.0, -0.5, true)] {
            let half =
                if along_x { Vector3::new(0.5 * SIDE, 0.05, WALL) } else { Vector3::new(0.05, 0.5 * SIDE, WALL) };
            let at = Vector3::new(x * (SIDE + 0.1), y * (SIDE + 0.1), WALL);
            w.add_body(RigidBodyBuilder::fixed(Some(Shape::cuboid(half)?)).position(at).friction(0.6))?;
        }
        let mut rng = Lcg(self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x5DEE_CE66);
        // a grid of 7 x 7 a layer within the walls, 0.55 m apart (room for the largest body turned any way), layers
        // 0.55 m apart
        let mut bodies = Vec::with_capacity(self.count);
        for k in 0..self.count {
            let (layer, i, j) = (k / 49, (k % 49) / 7, k % 7);
            let at = Vector3::new(-1.65 + 0.55 * i as f64, -1.65 + 0.55 * j as f64, 0.5 + 0.55 * layer as f64);
            let shape = match self.fill {
                Fill::EqualBoxes => Shape::cuboid(Vector3::repeat(0.15))?,
                Fill::MixedBoxes => Shape::cuboid(self.half(&mut rng))?,
                Fill::MixedShapes => match k % 4 {
                    0 => Shape::cuboid(self.half(&mut rng))?,
                    1 => Shape::sphere(rng.range(0.1, 0.25))?,
                    2 => Shape::capsule(rng.range(0.05, 0.15), rng.range(0.07, 0.18))?,
                    _ => {
                        let h = self.half(&mut rng);
                        let corners = (0..10)
                            .map(|_| Point3::new(rng.range(-h.x, h.x), rng.range(-h.y, h.y), rng.range(-h.z, h.z)));
                        Shape::convex_hull(&corners.collect::<Vec<_>>())?
                    }
                },
            };
            let turn = Vector3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-3.0, 3.0));
            let b = RigidBodyBuilder::from_shape(shape, DENSITY)
                .position(at)
                .orientation(UnitQuaternion::from_scaled_axis(turn))
                .restitution(0.1)
                .friction(0.6);
            bodies.push(w.add_body(b)?);
        }
        Ok((w, bodies))
    }

    /// Half extents of a random box: 0.1 to 0.25 m each way (volumes up to 15.6 times each other).
    fn half(&self, rng: &mut Lcg) -> Vector3<f64> {
        Vector3::new(rng.range(0.1, 0.25), rng.range(0.1, 0.25), rng.range(0.1, 0.25))
    }
}

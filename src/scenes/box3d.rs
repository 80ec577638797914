//! Box3D's benchmark walls of cubes (its `benchmarks.c`, erincatto/box3d on GitHub), built in tumble's axes (z up; Box3D's
//! y is tumble's z and its z tumble's -y): a large pyramid of unit cubes stacked exactly touching, and many small
//! ones spread over a wide ground. Fast mode at 1/60 s with sleeping off, as Box3D runs them; the solver's
//! substeps and sweeps are the caller's.

use crate::body::RigidBodyBuilder;
use crate::error::WorldError;
use crate::mode::{FastSettings, Mode};
use crate::spring::BodyHandle;
use crate::world::World;
use nalgebra::Vector3;
use tumble_collide::Shape;

/// Half extent of a cube (m).
const HALF: f64 = 0.5;
/// Density of a cube (kg/m^3) and friction of every shape (Box3D's default).
const DENSITY: f64 = 100.0;
const FRICTION: f64 = 0.6;

/// A world in fast mode at 1/60 s without sleeping, with a static slab of half extents `half` x `half` x 1 m whose
/// top is z = 0 (Box3D's ground box).
fn ground(half: f64) -> Result<World, WorldError> {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(1.0 / 60.0) }))?;
    let slab = Shape::cuboid(Vector3::new(half, half, 1.0))?;
    w.add_body(
        RigidBodyBuilder::fixed(Some(slab)).position(Vector3::new(0.0, 0.0, -1.0)).restitution(0.0).friction(FRICTION),
    )?;
    Ok(w)
}

/// A wall of cubes `base` wide at the bottom, each row one shorter and half a cube over, every cube touching those
/// below and beside it; the bottom row's left cube's centre at x = `left`, in the plane y = `y`. Bottom row first.
fn wall(w: &mut World, base: usize, left: f64, y: f64) -> Result<Vec<BodyHandle>, WorldError> {
    let cube = Shape::cuboid(Vector3::repeat(HALF))?;
    let mut cubes = Vec::with_capacity(base * (base + 1) / 2);
    for row in 0..base {
        let z = (2 * row + 1) as f64 * HALF;
        for k in row..base {
            let x = left + row as f64 * HALF + 2.0 * (k - row) as f64 * HALF;
            let b = RigidBodyBuilder::from_shape(cube.clone(), DENSITY)
                .position(Vector3::new(x, y, z))
                .restitution(0.0)
                .friction(FRICTION);
            cubes.push(w.add_body(b)?);
        }
    }
    Ok(cubes)
}

/// Box3D's `large_pyramid`: a wall of unit cubes (density 100, friction 0.6) with `base` cubes at the bottom (100:
/// 5,050 cubes), centred on x = 0, on a 800 x 800 m slab.
#[derive(Clone, Debug, PartialEq)]
pub struct LargePyramid {
    pub base: usize,
}

impl Default for LargePyramid {
    fn default() -> Self {
        LargePyramid { base: 100 }
    }
}

impl LargePyramid {
    /// The world and the cubes, bottom row first (the last is the top).
    pub fn build(&self) -> Result<(World, Vec<BodyHandle>), WorldError> {
        check_base(self.base)?;
        let mut w = ground(400.0)?;
        let cubes = wall(&mut w, self.base, HALF - HALF * self.base as f64, 0.0)?;
        Ok((w, cubes))
    }
}

/// Box3D's `many_pyramids`: `rows` x `columns` walls of unit cubes `base` wide (14 x 14 of 10: 196 walls of 55,
/// 10,780 cubes) spread over a square slab, each wall's plane across the rows.
#[derive(Clone, Debug, PartialEq)]
pub struct ManyPyramids {
    pub rows: usize,
    pub columns: usize,
    pub base: usize,
}

impl Default for ManyPyramids {
    fn default() -> Self {
        ManyPyramids { rows: 14, columns: 14, base: 10 }
    }
}

impl ManyPyramids {
    /// The world and each wall's cubes, bottom row first (the last of each is its top).
    pub fn build(&self) -> Result<(World, Vec<Vec<BodyHandle>>), WorldError> {
        check_base(self.base)?;
        for (name, n) in [("rows", self.rows), ("columns", self.columns)] {
            if !(2..=100).contains(&n) {
                return Err(WorldError::invalid(name, format!("must be from 2 to 100, got {n}")));
            }
        }
        let extent = HALF * self.columns as f64 * (self.base as f64 + 1.0);
        let mut w = ground(extent)?;
        let width = 2.0 * HALF * self.base as f64;
        let spacing = 2.0 * (extent - 2.0 * HALF) / (self.rows as f64 - 1.0);
        let mut walls = Vec::with_capacity(self.rows * self.columns);
        for i in 0..self.rows {
            // Box3D's z of row i, which is tumble's -y
            let y = -(-extent + 2.0 * HALF + spacing * i as f64);
            for j in 0..self.columns {
                let centre = -extent + j as f64 * (width + 2.0 * HALF) + 2.0 * HALF;
                walls.push(wall(&mut w, self.base, HALF + centre - 0.5, y)?);
            }
        }
        Ok((w, walls))
    }
}

fn check_base(base: usize) -> Result<(), WorldError> {
    if !(1..=1000).contains(&base) {
        return Err(WorldError::invalid("base", format!("must be from 1 to 1000, got {base}")));
    }
    Ok(())
}

//! Built-in scenes: a cloth pinned at two corners, and a heavy top spinning on a pivot; with contact (in
//! `contact.rs`) a bouncing ball, a tumbling box, a row of dominoes, a pyramid of boxes and a cloth draping over a
//! sphere; and (in `meshes.rs`) meshes built in code: a ball in a cup, a ring on a peg, a chair, a rolling torus, a
//! pile of meshes; and (in `fracture.rs`) a glued wall a wrecking ball smashes. Examples, benchmarks, tests and the Python module's default job start from them.

mod benchmark;
mod bin;
mod box3d;
mod contact;
mod fracture;
pub mod joints;
pub mod meshes;
mod registry;
pub use benchmark::Benchmark;
pub use bin::{Bin, Fill};
pub use box3d::{LargePyramid, ManyPyramids};
pub use contact::{tumbling_box, BouncingBall, ClothDrape, Dominoes, Pile, Pyramid};
pub use fracture::{running_bond_wall, WreckingBall};
pub use registry::{build, check, NAMES};

use crate::body::RigidBodyBuilder;
use crate::error::WorldError;
use crate::particle::ParticleBuilder;
use crate::spring::{Attachment, BodyHandle, ParticleHandle, SpringBuilder};
use crate::world::World;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use tumble_integrate::{Method, Settings};

/// A square cloth of n x n particles.
#[derive(Clone, Debug, PartialEq)]
pub struct Cloth {
    /// Particles along a side.
    pub n: usize,
    /// Side length (m).
    pub size: f64,
    /// Total mass (kg).
    pub mass: f64,
    /// Stiffness of structural and shear springs (N/m).
    pub stiffness: f64,
    /// Damping of every spring (N s/m).
    pub damping: f64,
    /// Stiffness of the springs pinning two corners to their starting points (N/m).
    pub pin_stiffness: f64,
}

impl Default for Cloth {
    fn default() -> Self {
        Cloth { n: 16, size: 1.0, mass: 0.5, stiffness: 1e3, damping: 0.5, pin_stiffness: 1e4 }
    }
}

/// Checks a scene parameter: finite and within `lo ..= hi`, or an error naming it with its range.
pub(crate) fn within(name: &'static str, v: f64, lo: f64, hi: f64) -> Result<f64, WorldError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(WorldError::invalid(name, format!("must be from {lo:e} to {hi:e}, got {v}")))
    }
}

/// Checks a count of particles a side: 2 ..= 1000.
pub(crate) fn side_count(name: &'static str, n: usize) -> Result<usize, WorldError> {
    if (2..=1000).contains(&n) {
        Ok(n)
    } else {
        Err(WorldError::invalid(name, format!("a cloth needs from 2 to 1000 particles a side, got {n}")))
    }
}

/// Springs of an n x n grid of particles (row by row): structural ones between neighbours and shear ones across
/// both diagonals of every cell.
pub(crate) fn weave(
    w: &mut World,
    ps: &[ParticleHandle],
    n: usize,
    stiffness: f64,
    damping: f64,
) -> Result<(), WorldError> {
    let at = |i: usize, j: usize| ps[j * n + i];
    let spring = |a, b| {
        SpringBuilder::new(Attachment::Particle(a), Attachment::Particle(b)).stiffness(stiffness).damping(damping)
    };
    for j in 0..n {
        for i in 0..n {
            if i + 1 < n {
                w.add_spring(spring(at(i, j), at(i + 1, j)))?;
            }
            if j + 1 < n {
                w.add_spring(spring(at(i, j), at(i, j + 1)))?;
            }
            if i + 1 < n && j + 1 < n {
                w.add_spring(spring(at(i, j), at(i + 1, j + 1)))?;
                w.add_spring(spring(at(i + 1, j), at(i, j + 1)))?;
            }
        }
    }
    Ok(())
}

impl Cloth {
    /// Checks every parameter by name: n 2..=1000, size 1e-6..=1e6 m, mass 1e-20..=1e20 kg, stiffnesses and
    /// damping 0..=1e12 (so every particle's mass, position and spring stays within `tumble::limit`).
    pub fn check(&self) -> Result<(), WorldError> {
        side_count("n", self.n)?;
        within("size", self.size, 1e-6, 1e6)?;
        within("mass", self.mass, 1e-20, 1e20)?;
        within("stiffness", self.stiffness, 0.0, 1e12)?;
        within("damping", self.damping, 0.0, 1e12)?;
        within("pin_stiffness", self.pin_stiffness, 0.0, 1e12)?;
        Ok(())
    }

    /// Builds the cloth horizontally at height 1 m, corners (0, 0) and (size, 0) pinned, with structural springs
    /// between neighbours and shear springs across every cell, stepped by implicit Euler at 1/240 s.
    pub fn build(&self) -> Result<(World, Vec<ParticleHandle>), WorldError> {
        self.check()?;
        let n = self.n;
        let mut w = World::new();
        w.set_integrator(Settings::fixed(Method::ImplicitEuler, 1.0 / 240.0))?;
        let spacing = self.size / (n - 1) as f64;
        let m = self.mass / (n * n) as f64;
        let mut ps = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let x = Vector3::new(i as f64 * spacing, j as f64 * spacing, 1.0);
                ps.push(w.add_particle(ParticleBuilder::new(m).position(x))?);
            }
        }
        let at = |i: usize, j: usize| ps[j * n + i];
        weave(&mut w, &ps, n, self.stiffness, self.damping)?;
        for corner in [at(0, 0), at(n - 1, 0)] {
            let x = w.particle(corner)?.position();
            w.add_spring(
                SpringBuilder::new(Attachment::Particle(corner), Attachment::Point(x))
                    .stiffness(self.pin_stiffness)
                    .damping(self.damping)
                    .rest_length(0.0),
            )?;
        }
        Ok((w, ps))
    }
}

/// A heavy symmetric top: mass 1 kg, moments I1 = I2 = 0.02 and I3 = 0.04 kg m^2, centre of mass 0.1 m from its
/// tip, which a stiff damped spring (zero rest length) holds at the origin. Tilted 0.3 rad, spinning at 40 rad/s
/// about its axis; gravity makes it precess at about 0.618 rad/s (the slow root of
/// I1 cos(theta) W^2 - I3 w3 W + M g l = 0). Stepped by Radau5 at 1e-8.
pub fn spinning_top() -> Result<(World, BodyHandle), WorldError> {
    let (mass, i1, i3, arm, spin, tilt): (f64, f64, f64, f64, f64, f64) = (1.0, 0.02, 0.04, 0.1, 40.0, 0.3);
    let mut w = World::new();
    w.set_integrator(Settings::tolerances(Method::Radau5, 1e-8, 1e-8))?;
    // Written out as the Python scene (and the bindings) build it, so both give the same numbers bit for bit.
    let q = UnitQuaternion::new_normalize(Quaternion::new((tilt / 2.0).cos(), (tilt / 2.0).sin(), 0.0, 0.0));
    let axis = Vector3::new(0.0, -tilt.sin(), tilt.cos());
    let top = w.add_body(
        RigidBodyBuilder::new(mass, Matrix3::from_diagonal(&Vector3::new(i1, i1, i3)))
            .position(axis * arm)
            .orientation(q)
            .angular_velocity(axis * spin),
    )?;
    w.add_spring(
        SpringBuilder::new(Attachment::Body(top, Vector3::new(0.0, 0.0, -arm)), Attachment::Point(Vector3::zeros()))
            .stiffness(1e5)
            .damping(50.0)
            .rest_length(0.0),
    )?;
    Ok((w, top))
}

/// The built-in scenes' colours (linear RGB, opaque): the bodies of a scene take them in turn.
const PALETTE: [[f64; 4]; 6] = [
    [0.80, 0.18, 0.12, 1.0],
    [0.10, 0.35, 0.75, 1.0],
    [0.90, 0.62, 0.10, 1.0],
    [0.15, 0.55, 0.25, 1.0],
    [0.55, 0.25, 0.65, 1.0],
    [0.65, 0.65, 0.62, 1.0],
];

/// The k-th colour of the built-in scenes' palette.
pub(crate) fn hue(k: usize) -> [f64; 4] {
    PALETTE[k % PALETTE.len()]
}

//! Shared test helpers: a seeded generator (SplitMix64) and random poses, shapes and closed blobs drawn from it.
#![allow(dead_code)]

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use tumble_collide::{Mesh, Shape, SplitMix};

/// SplitMix64: small, seeded, reproducible.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        let mut g = SplitMix(self.0);
        let bits = g.next_u64();
        self.0 = g.0;
        bits
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Uniform integer in [0, n).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    pub fn vector(&mut self, half: f64) -> Vector3<f64> {
        Vector3::new(self.range(-half, half), self.range(-half, half), self.range(-half, half))
    }

    /// A rotation uniform over SO(3) (Shoemake).
    pub fn rotation(&mut self) -> UnitQuaternion<f64> {
        let (u1, u2, u3) = (self.uniform(), self.uniform(), self.uniform());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            b * (tau * u3).cos(),
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
        ))
    }

    pub fn pose(&mut self, half: f64) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.vector(half)), self.rotation())
    }

    /// A random box or convex hull of 4 to 24 points, about 1 across.
    pub fn polyhedral_shape(&mut self) -> Shape {
        if self.below(3) == 0 {
            Shape::cuboid(Vector3::new(self.range(0.05, 0.8), self.range(0.05, 0.8), self.range(0.05, 0.8))).unwrap()
        } else {
            loop {
                let n = 4 + self.below(21) as usize;
                let scale = Vector3::new(self.range(0.2, 1.0), self.range(0.2, 1.0), self.range(0.2, 1.0));
                let pts: Vec<Point3<f64>> =
                    (0..n).map(|_| Point3::from(self.vector(1.0).component_mul(&scale))).collect();
                if let Ok(s) = Shape::convex_hull(&pts) {
                    return s;
                }
            }
        }
    }
}

/// A random star-shaped blob: a sphere mesh of `segments` whose vertices are pushed out by a smooth random radius
/// (four sine terms of up to `amplitude`), then scaled and placed by what `place` draws; closed and outward by
/// construction.
pub fn blob(
    rng: &mut Rng,
    segments: u32,
    amplitude: f64,
    place: impl FnOnce(&mut Rng) -> (f64, Isometry3<f64>),
) -> Mesh {
    let sphere = Mesh::sphere_mesh(1.0, segments).unwrap();
    let k: Vec<(Vector3<f64>, f64)> = (0..4).map(|_| (rng.vector(3.0), rng.range(-amplitude, amplitude))).collect();
    let (scale, pose) = place(rng);
    let vertices: Vec<Point3<f64>> = sphere
        .vertices()
        .iter()
        .map(|p| {
            let r = 1.0 + k.iter().map(|(f, a)| a * f.dot(&p.coords).sin()).sum::<f64>();
            pose * Point3::from(p.coords * r * scale)
        })
        .collect();
    Mesh::new(&vertices, sphere.triangles(), "blob").unwrap()
}

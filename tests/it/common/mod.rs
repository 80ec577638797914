//! Helpers shared by the integration tests.

use nalgebra::{Point3, UnitQuaternion, Vector3};
use tumble::{Material, RigidBodyBuilder, Shape, World};

/// Every number of a world's state, its time and its object counts, as bits (for bit-for-bit comparisons).
#[allow(dead_code)] // not every test file compares states
pub fn state_bits(w: &World) -> Vec<u64> {
    let mut out = vec![w.time().to_bits(), w.particle_count() as u64, w.body_count() as u64];
    for (_, p) in w.particles() {
        out.extend(p.position().iter().chain(p.velocity().iter()).map(|v| v.to_bits()));
    }
    for (_, b) in w.bodies() {
        let q = b.orientation();
        out.extend(
            b.position().iter().chain(b.velocity().iter()).chain(b.angular_velocity().iter()).map(|v| v.to_bits()),
        );
        out.extend([q.w, q.i, q.j, q.k].iter().map(|v| v.to_bits()));
    }
    out
}

/// A seeded linear congruential generator: the same numbers on every machine, for random scenes.
#[allow(dead_code)] // not every test file draws random scenes
pub struct Lcg(pub u64);

#[allow(dead_code)]
impl Lcg {
    /// The next number in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next number in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// A random shape of every kind a body can have: sphere, cuboid, capsule, cylinder, convex hull (0.05 to 0.3 m).
#[allow(dead_code)]
pub fn random_shape(rng: &mut Lcg) -> Shape {
    let kind = (rng.next() * 5.0) as usize;
    match kind {
        0 => Shape::sphere(rng.range(0.05, 0.3)).unwrap(),
        1 => Shape::cuboid(Vector3::new(rng.range(0.05, 0.3), rng.range(0.05, 0.3), rng.range(0.05, 0.3))).unwrap(),
        2 => Shape::capsule(rng.range(0.05, 0.3), rng.range(0.05, 0.3)).unwrap(),
        3 => Shape::cylinder(rng.range(0.05, 0.3), rng.range(0.05, 0.3)).unwrap(),
        _ => {
            let points: Vec<Point3<f64>> = (0..8)
                .map(|_| Point3::new(rng.range(-0.25, 0.25), rng.range(-0.25, 0.25), rng.range(-0.25, 0.25)))
                .collect();
            Shape::convex_hull(&points).unwrap()
        }
    }
}

/// A seeded random drop onto a ground (accurate mode): one to five random shapes one above another, random
/// orientations, spins, densities (100 to 3000 kg/m^3), friction (0 to 1) and restitution (0 to 0.6).
#[allow(dead_code)]
pub fn random_drop(seed: u64) -> World {
    let mut rng = Lcg(seed.wrapping_mul(7919).wrapping_add(17));
    let mut w = World::new();
    w.add_ground(0.0, Material::new(rng.range(0.0, 0.6), rng.range(0.0, 1.0))).unwrap();
    let count = 1 + (rng.next() * 5.0) as usize;
    for k in 0..count {
        let shape = random_shape(&mut rng);
        let q = UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        w.add_body(
            RigidBodyBuilder::from_shape(shape, rng.range(100.0, 3000.0))
                .position(Vector3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 0.6 + 0.7 * k as f64))
                .orientation(q)
                .angular_velocity(Vector3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)))
                .restitution(rng.range(0.0, 0.6))
                .friction(rng.range(0.0, 1.0)),
        )
        .unwrap();
    }
    w
}

/// The world's mechanical energy (kinetic and potential) at its start and after each of `span / dt` calls of
/// `step(dt)`: states at the ends of calls are the engine's own, never interpolated (frames between an engine's
/// steps are interpolated, and an interpolation through a bounce dips in kinetic energy and rises again).
#[allow(dead_code)]
pub fn energies_by_steps(w: &mut World, span: f64, dt: f64) -> Vec<f64> {
    let energy = |w: &World| w.kinetic_energy() + w.potential_energy();
    let mut out = vec![energy(w)];
    for _ in 0..(span / dt).round() as usize {
        w.step(dt).unwrap_or_else(|e| panic!("at t = {}: {e}", w.time()));
        out.push(energy(w));
    }
    out
}

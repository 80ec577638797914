//! The scenes accurate mode is measured on against Drake's CENIC (`benches/peers/cenic.py`,
//! `examples/accurate_scenes.rs`), each with its closed form where it has one. z up, g = 9.81, restitution 0,
//! the same friction on both surfaces; inclines by tilting gravity. All in accurate mode at its defaults.

use crate::body::RigidBodyBuilder;
use crate::collider::Material;
use crate::error::WorldError;
use crate::spring::BodyHandle;
use crate::world::World;
use nalgebra::{UnitQuaternion, Vector3};
use tumble_collide::Shape;

const G: f64 = 9.81;

/// One of the measured scenes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Benchmark {
    /// A cube of half extent 0.2 m, density 500, sliding at 2 m/s on mu 0.5; it stops at v^2 / (2 mu g).
    Slide,
    /// A 0.1 m cube (half extent 0.05 m), density 500, on mu 0.5 tilted by `degrees`; down the slope it moves
    /// g (sin - mu cos) t^2 / 2 when tan > mu, and not at all otherwise.
    Incline { degrees: f64 },
    /// A sphere of radius 0.1 m, density 1000, on mu 0.3 tilted 30 degrees: it rolls (5/7) g sin t^2 / 2.
    Roll,
    /// 20 cubes of half extent 0.1 m, density 500, mu 0.5, dropped in three loose layers 0.3 m apart, each layer
    /// offset to land on the one below, every third cube tilted.
    CubePile,
    /// Ten dominoes 0.04 x 0.2 x 0.4 m, density 700, mu 0.5, 0.25 m apart; the first set pivoting on its front
    /// edge at 2 rad/s.
    DominoRow,
}

impl Benchmark {
    /// The scene's world and its bodies.
    pub fn build(&self) -> Result<(World, Vec<BodyHandle>), WorldError> {
        let mut w = World::new();
        let (mu, tilt) = match *self {
            Benchmark::Slide | Benchmark::CubePile | Benchmark::DominoRow => (0.5, 0.0),
            Benchmark::Incline { degrees } => (0.5, degrees.to_radians()),
            Benchmark::Roll => (0.3, 30f64.to_radians()),
        };
        // tilted gravity: downhill is +x
        w.set_gravity(Vector3::new(G * tilt.sin(), 0.0, -G * tilt.cos()))?;
        let floor = Material::new(0.0, mu);
        w.add_ground(0.0, floor)?;
        let body = |shape: Shape, density: f64, at: Vector3<f64>| {
            RigidBodyBuilder::from_shape(shape, density).position(at).restitution(0.0).friction(mu)
        };
        let mut bodies = Vec::new();
        match *self {
            Benchmark::Slide => {
                let half = 0.2;
                let b = body(Shape::cuboid(Vector3::repeat(half))?, 500.0, Vector3::new(0.0, 0.0, half));
                bodies.push(w.add_body(b.velocity(Vector3::new(2.0, 0.0, 0.0)))?);
            }
            Benchmark::Incline { .. } => {
                let half = 0.05;
                bodies.push(w.add_body(body(
                    Shape::cuboid(Vector3::repeat(half))?,
                    500.0,
                    Vector3::new(0.0, 0.0, half),
                ))?);
            }
            Benchmark::Roll => {
                let r = 0.1;
                bodies.push(w.add_body(body(Shape::sphere(r)?, 1000.0, Vector3::new(0.0, 0.0, r)))?);
            }
            Benchmark::CubePile => {
                let half = 0.1;
                let layers = [7usize, 7, 6];
                let mut n = 0;
                for (layer, &count) in layers.iter().enumerate() {
                    let offset = 0.12 * layer as f64;
                    for k in 0..count {
                        let (i, j) = ((k % 3) as f64, (k / 3) as f64);
                        let at = Vector3::new(0.26 * i + offset, 0.26 * j + offset, half + 0.05 + 0.3 * layer as f64);
                        let turn = if n % 3 == 2 { 0.3 } else { 0.0 };
                        let b = body(Shape::cuboid(Vector3::repeat(half))?, 500.0, at)
                            .orientation(UnitQuaternion::from_euler_angles(turn, 0.5 * turn, 0.2 * turn));
                        bodies.push(w.add_body(b)?);
                        n += 1;
                    }
                }
            }
            Benchmark::DominoRow => {
                let half = Vector3::new(0.02, 0.1, 0.2);
                for k in 0..10 {
                    let at = Vector3::new(0.25 * k as f64, 0.0, half.z);
                    let mut b = body(Shape::cuboid(half)?, 700.0, at);
                    if k == 0 {
                        // turning about its front bottom edge (x + half.x, z = 0) at 2 rad/s: v = w x (c - edge)
                        let w_y = Vector3::new(0.0, 2.0, 0.0);
                        let lever = Vector3::new(-half.x, 0.0, half.z);
                        b = b.angular_velocity(w_y).velocity(w_y.cross(&lever));
                    }
                    bodies.push(w.add_body(b)?);
                }
            }
        }
        Ok((w, bodies))
    }

    /// The simulated span the comparison runs (s).
    pub fn span(&self) -> f64 {
        match *self {
            Benchmark::Slide | Benchmark::Roll => 1.0,
            Benchmark::Incline { degrees } => {
                if degrees.to_radians().tan() > 0.5 {
                    1.0
                } else {
                    2.0
                }
            }
            Benchmark::CubePile => 3.0,
            Benchmark::DominoRow => 4.0,
        }
    }

    /// The closed form of the measured distance after `span()`, where the scene has one (m): the slide's stop
    /// distance, the incline's and the roll's distance down the slope.
    pub fn closed_form(&self) -> Option<f64> {
        let t = self.span();
        match *self {
            Benchmark::Slide => Some(2.0 * 2.0 / (2.0 * 0.5 * G)),
            Benchmark::Incline { degrees } => {
                let a = degrees.to_radians();
                Some((G * (a.sin() - 0.5 * a.cos())).max(0.0) * t * t / 2.0)
            }
            Benchmark::Roll => Some(5.0 / 7.0 * G * 30f64.to_radians().sin() * t * t / 2.0),
            _ => None,
        }
    }
}

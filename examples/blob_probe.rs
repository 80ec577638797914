use nalgebra::{Point3, UnitQuaternion, Vector3};
use tumble::{FastSettings, Material, Mesh, Mode, RigidBodyBuilder, Shape, World};
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}
fn blob(rng: &mut Lcg) -> Mesh {
    let sphere = Mesh::sphere_mesh(1.0, 20).unwrap();
    let k: Vec<(Vector3<f64>, f64)> = (0..4)
        .map(|_| (Vector3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)), rng.range(-0.3, 0.3)))
        .collect();
    let scale = rng.range(0.03, 0.15);
    let v: Vec<Point3<f64>> = sphere
        .vertices()
        .iter()
        .map(|p| {
            Point3::from(p.coords * scale * (1.0 + k.iter().map(|(f, a)| a * f.dot(&p.coords).sin()).sum::<f64>()))
        })
        .collect();
    Mesh::new(&v, sphere.triangles(), "blob").unwrap()
}
fn main() {
    let seed: u64 = std::env::args().nth(1).unwrap().parse().unwrap();
    let fast = std::env::args().any(|a| a == "fast");
    let mode = if fast { Mode::Fast(FastSettings::new(1.0 / 240.0)) } else { Mode::default() };
    let mut rng = Lcg(seed * 7 + 3);
    let mut w = World::new();
    w.set_mode(mode).unwrap();
    w.add_ground(0.0, Material { restitution: rng.range(0.0, 0.5), friction: rng.range(0.2, 1.0) }).unwrap();
    for k in 0..3 {
        let q = UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        let m = blob(&mut rng);
        let b = RigidBodyBuilder::from_shape(Shape::mesh(m), rng.range(200.0, 3000.0))
            .position(Vector3::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1), 0.3 + 0.35 * k as f64))
            .orientation(q)
            .restitution(rng.range(0.0, 0.5))
            .friction(rng.range(0.2, 1.0));
        w.add_body(b).unwrap();
    }
    for _ in 0..60 {
        w.step(1.0 / 30.0).unwrap();
    }
    println!("pen {:.3e} tol {:?}", w.report().max_penetration, w.report().contact_tolerance);
}

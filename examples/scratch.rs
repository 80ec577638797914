use nalgebra::Vector3;
use tumble::{Material, Mode, RigidBodyBuilder, Shape, World};
fn main() {
    let mut w = World::new();
    w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
    w.add_ground(0.0, Material { restitution: 0.0, friction: 0.5 }).unwrap();
    let b = w.add_body(RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.5, 0.5, 0.5)).unwrap(), 1000.0).position(Vector3::new(0.0, 0.0, 2.0)).restitution(0.0)).unwrap();
    for k in 0..20 {
        w.step(0.1).unwrap();
        let body = w.body(b).unwrap();
        println!("t={:.2} z={:.6} v={:.4e} ", w.time(), body.position().z, body.velocity().norm());
        let _ = k;
    }
    println!("{}", w.report());
}

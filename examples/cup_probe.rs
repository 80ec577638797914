use nalgebra::Vector3;
use tumble::{Material, Mesh, MeshShape, Mode, RigidBodyBuilder, Shape, World};
fn main() {
    let fast = std::env::args().any(|a| a == "fast");
    let hull = std::env::args().any(|a| a == "hull");
    let cup = Mesh::cup_mesh(0.05, 0.08, 0.005, 48).unwrap();
    let t = std::time::Instant::now();
    let d = tumble::collide::Decomposed::new(&cup, &Default::default()).unwrap();
    println!("pieces {} in {:.3}s (measured {:.3})", d.pieces().len(), d.seconds(), t.elapsed().as_secs_f64());
    let mut w = World::new();
    if fast {
        w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
    }
    w.add_ground(0.0, Material { restitution: 0.0, friction: 0.5 }).unwrap();
    let cp = Shape::mesh(cup.clone()).mass_properties(1.0).unwrap().local_com;
    let mut b = RigidBodyBuilder::from_shape(Shape::mesh(cup), 1000.0).position(Vector3::new(0.0, 0.0, 1e-4 + cp.z));
    if hull {
        b = b.mesh_shape(MeshShape::Hull);
    }
    let c = w.add_body(b).unwrap();
    let ball = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::sphere(0.015).unwrap(), 1000.0)
                .position(Vector3::new(0.01, 0.0, 0.15))
                .restitution(0.3),
        )
        .unwrap();
    let t = std::time::Instant::now();
    for k in 0..50 {
        w.step(0.1).unwrap();
        if k % 10 == 9 {
            let (bp, cp) = (w.body(ball).unwrap().position(), w.body(c).unwrap().position());
            println!("t {:.1} ball {:.4?} cup {:.4?}", w.time(), bp.as_slice(), cp.as_slice());
        }
    }
    println!("wall {:.2}s report: {}", t.elapsed().as_secs_f64(), w.report());
}

//! One fast-mode scene run for profiling: `rest` (one box on the ground, dt 1/240), `stack` (ten cubes) or `pile N`
//! (the peer comparison's pile, dt 1/60), on one thread without sleeping, printing the time a step:
//! `cargo run --release --example fast_once -- pile 1000 600 [--substeps S] [--iterations K]`
use nalgebra::Vector3;
use tumble::{FastSettings, FastSolver, Material, Mode, RigidBodyBuilder, Shape, SoftSolver, World};
fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut soft = SoftSolver::default();
    for (flag, field) in [("--substeps", &mut soft.substeps), ("--iterations", &mut soft.iterations)] {
        if let Some(k) = args.iter().position(|a| a == flag) {
            *field = args[k + 1].parse().expect("a whole number");
            args.drain(k..k + 2);
        }
    }
    let which = args.first().map(String::as_str).unwrap_or("rest");
    let number = |k: usize, default: usize| args.get(k).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (dt, mut w) = (if which == "pile" { 1.0 / 60.0 } else { 1.0 / 240.0 }, World::new());
    w.set_mode(Mode::Fast(FastSettings { sleep: false, solver: FastSolver::Soft(soft), ..FastSettings::new(dt) }))
        .unwrap();
    w.set_threads(1).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let cube = |w: &mut World, half: f64, at: Vector3<f64>| {
        let shape = Shape::cuboid(Vector3::repeat(half)).unwrap();
        w.add_body(RigidBodyBuilder::from_shape(shape, 1000.0).position(at).restitution(0.0).friction(0.5)).unwrap();
    };
    let steps = match which {
        "pile" => {
            for k in 0..number(1, 1000) {
                let (layer, i, j) = (k / 100, (k % 100) / 10, k % 10);
                cube(&mut w, 0.5, Vector3::new(1.2 * i as f64, 1.2 * j as f64, 2.5 + 1.2 * layer as f64));
            }
            number(2, 600)
        }
        "stack" => {
            (0..10).for_each(|k| cube(&mut w, 0.25, Vector3::new(0.0, 0.0, 0.25 + 0.5 * k as f64)));
            number(1, 20000)
        }
        _ => {
            cube(&mut w, 0.5, Vector3::new(0.0, 0.0, 0.5));
            number(1, 50000)
        }
    };
    let clock = std::time::Instant::now();
    for _ in 0..steps {
        w.step(dt).unwrap();
    }
    println!("{which}: {:.2} us a step", clock.elapsed().as_secs_f64() * 1e6 / steps as f64);
    let r = w.report();
    println!(
        "narrow-phase tests {:.1} a step, pushing contacts {:.1} a step, penetration {:.3} mm",
        r.collision_checks as f64 / steps as f64,
        r.impulses as f64 / steps as f64,
        r.max_penetration * 1e3
    );
}

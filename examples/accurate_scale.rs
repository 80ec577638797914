//! Accurate mode on scenes of many bodies, one thread, frames every 1/60 s: N spinning boxes dropped 2 m apart (each
//! its own island) with islands on their own clocks and on one; 200 dominoes on an S-curve (half extents 4 x 12 x
//! 24 mm, 33 mm apart, the first tipped) in fast mode for 10 s and in accurate mode for its first seconds; the
//! 20-cube pile's landing second. Prints markdown tables.
//!
//! `cargo run --release --example accurate_scale [-- --dominoes SECONDS]`

use nalgebra::{UnitQuaternion, Vector3};
use std::time::Instant;
use tumble::scenes::Benchmark;
use tumble::{AccurateSettings, Material, Mode, RigidBodyBuilder, Shape, World};

/// `n` boxes (half extent 0.1 m) 2 m apart on a square grid, dropped from 0.5 to 0.56 m with a spin.
fn boxes(n: usize) -> World {
    let mut w = World::new();
    w.add_ground(0.0, Material::new(0.3, 0.5)).unwrap();
    let side = (n as f64).sqrt().ceil() as usize;
    for k in 0..n {
        let at = Vector3::new(2.0 * (k % side) as f64, 2.0 * (k / side) as f64, 0.5 + 0.01 * (k % 7) as f64);
        let b = RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.1)).unwrap(), 500.0)
            .position(at)
            .angular_velocity(Vector3::new(0.3 * (k % 5) as f64, 0.2, 0.1));
        w.add_body(b).unwrap();
    }
    w
}

/// `n` dominoes along an S-curve, the first tipped about its front bottom edge at 5 rad/s.
fn dominoes(n: usize) -> World {
    let mut w = World::new();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let half = Vector3::new(0.004, 0.012, 0.024);
    let (mut x, mut y, mut heading) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..n {
        let q = UnitQuaternion::from_euler_angles(0.0, 0.0, heading);
        let mut b = RigidBodyBuilder::from_shape(Shape::cuboid(half).unwrap(), 700.0)
            .position(Vector3::new(x, y, half.z))
            .orientation(q);
        if k == 0 {
            let spin = q * Vector3::new(0.0, 5.0, 0.0);
            b = b.angular_velocity(spin).velocity(spin.cross(&(q * Vector3::new(-half.x, 0.0, half.z))));
        }
        w.add_body(b).unwrap();
        (x, y) = (x + 0.033 * heading.cos(), y + 0.033 * heading.sin());
        heading += if k < n / 2 { 0.02 } else { -0.02 };
    }
    w
}

/// Wall seconds of a run of `span` (frames every 1/60 s) on one thread.
fn timed(mut w: World, span: f64) -> (f64, World) {
    w.set_threads(1).unwrap();
    let clock = Instant::now();
    w.run(span, 1.0 / 60.0).expect("the run");
    (clock.elapsed().as_secs_f64(), w)
}

fn fallen(w: &World) -> usize {
    w.bodies().filter(|(_, b)| b.position().z > 0.0 && b.position().z < 0.6 * 0.024).count()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let domino_span: f64 =
        args.iter().position(|a| a == "--dominoes").and_then(|k| args.get(k + 1)).map_or(2.0, |s| s.parse().unwrap());
    println!("| boxes apart, 2 s | own clocks (s) | one clock (s) | own / one box |");
    println!("|---|---|---|---|");
    let mut one_box = 0.0;
    for n in [1usize, 10, 100, 1000] {
        let mut w = boxes(n);
        let (own, _) = timed(w.clone(), 2.0);
        w.set_mode(Mode::Accurate(AccurateSettings { island_clocks: false, ..AccurateSettings::default() })).unwrap();
        let (one, _) = timed(w, 2.0);
        if n == 1 {
            one_box = own;
        }
        println!("| {n} | {own:.4} | {one:.4} | {:.1} |", own / one_box);
    }
    let (fast_wall, fast_world) = {
        let mut w = dominoes(200);
        w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
        timed(w, 10.0)
    };
    let (acc_wall, acc_world) = timed(dominoes(200), domino_span);
    println!();
    println!("| 200 dominoes | simulated (s) | wall (s) | fallen |");
    println!("|---|---|---|---|");
    println!("| fast mode, dt 1/240 s | 10 | {fast_wall:.3} | {} |", fallen(&fast_world));
    println!("| accurate mode, defaults | {domino_span} | {acc_wall:.3} | {} |", fallen(&acc_world));
    let (pile, _) = timed(Benchmark::CubePile.build().unwrap().0, 1.0);
    println!();
    println!("20-cube pile, its landing second at the defaults: {pile:.3} s");
}

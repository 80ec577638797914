//! Saving and loading a 1,000-body world: the pile of the peer comparison (1,000 cubes on a ground, fast mode) after
//! 300 steps, written and read as JSON and as the binary format, each with the engine's memory, and as the scene
//! alone (JSON without the memory); then the same cubes in accurate mode 0.2 s into their fall (the memory holds
//! the integration: Dopri5's stages and points); least time of five, sizes.
//!
//! cargo run --release --example save_load

use nalgebra::Vector3;
use std::time::Instant;
use tumble::{FastSettings, Material, Mode, RigidBodyBuilder, Shape, World};

fn least<T>(f: impl Fn() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = f();
    for _ in 0..5 {
        let clock = Instant::now();
        out = f();
        best = best.min(clock.elapsed().as_secs_f64());
    }
    (best * 1e3, out)
}

fn cubes(fast: bool) -> World {
    let mut w = World::new();
    if fast {
        w.set_mode(Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(1.0 / 60.0) })).unwrap();
    }
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    for k in 0..1000 {
        let (layer, i, j) = (k / 100, (k % 100) / 10, k % 10);
        let at = Vector3::new(1.2 * i as f64, 1.2 * j as f64, 2.5 + 1.2 * layer as f64);
        let shape = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
        w.add_body(RigidBodyBuilder::from_shape(shape, 1000.0).position(at).restitution(0.0).friction(0.5)).unwrap();
    }
    w
}

fn measure(w: &World, memory: &str) {
    let row = |name: &str, size: usize, write: f64, read: f64| {
        println!("| {name} | {:.0} kB | {write:.1} ms | {read:.1} ms |", size as f64 / 1e3)
    };
    let (write, scene) = least(|| w.to_json_scene().unwrap());
    let (read, _) = least(|| World::from_json(&scene).unwrap());
    row("JSON, the scene alone", scene.len(), write, read);
    let (write, json) = least(|| w.to_json().unwrap());
    let (read, _) = least(|| World::from_json(&json).unwrap());
    row(&format!("JSON with {memory}"), json.len(), write, read);
    let (write, bytes) = least(|| w.to_bytes().unwrap());
    let (read, _) = least(|| World::from_bytes(&bytes).unwrap());
    row(&format!("binary with {memory}"), bytes.len(), write, read);
}

fn main() {
    println!("| format | size | write | read |\n|---|---|---|---|");
    let mut fast = cubes(true);
    fast.step(300.0 / 60.0).unwrap();
    measure(&fast, "fast mode's memory");
    let mut accurate = cubes(false);
    accurate.step(0.2).unwrap();
    measure(&accurate, "accurate mode's memory");
}

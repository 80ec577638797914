//! Fast mode at scale (issue 15): a rain of N cubes (half extent 0.5 m, on a square grid at 1.2 m pitch, 2 m up)
//! dropped on a ground and stepped at 1/60 s until they rest; prints a markdown row per N: time to build, ms a step
//! while falling and after landing (finding contacts and solving them), contacts and islands a step, and the
//! process's peak memory.
//!
//! cargo run --release --example scale -- [N ...] [--steps S] [--threads T]

use nalgebra::Vector3;
use std::time::Instant;
use tumble::{FastSettings, Material, Mode, RigidBodyBuilder, Shape, World};

/// The process's peak resident memory (MB), from /proc (0 where there is none).
fn peak_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = status.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1));
    kb.and_then(|k| k.parse::<f64>().ok()).unwrap_or(0.0) / 1024.0
}

fn rain(n: usize, threads: usize) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(1.0 / 60.0) })).unwrap();
    w.set_threads(threads).unwrap();
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let side = (n as f64).sqrt().ceil() as usize;
    let shape = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    for k in 0..n {
        let at = Vector3::new(1.2 * (k % side) as f64, 1.2 * (k / side) as f64, 2.5);
        w.add_body(RigidBodyBuilder::from_shape(shape.clone(), 1000.0).position(at).friction(0.5).restitution(0.0))
            .unwrap();
    }
    w
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str, default: usize| {
        args.iter().position(|a| a == name).map_or(default, |k| args[k + 1].parse().expect("a whole number"))
    };
    let (steps, threads) = (flag("--steps", 60), flag("--threads", 0));
    let sizes: Vec<usize> = args
        .iter()
        .enumerate()
        .filter(|(k, a)| !a.starts_with("--") && (*k == 0 || !args[k - 1].starts_with("--")))
        .map(|(_, a)| a.parse().expect("a body count"))
        .collect();
    println!("| cubes | build (s) | ms a step, falling | ms a step, landed (contacts + solve) | contacts a step | islands a step | peak memory (MB) |");
    println!("|---|---|---|---|---|---|---|");
    for n in if sizes.is_empty() { vec![1000, 10000, 100000] } else { sizes } {
        let clock = Instant::now();
        let mut w = rain(n, threads);
        w.step(1.0 / 60.0).unwrap(); // the first step compiles the world and builds its broad phase
        let build = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        w.step(20.0 / 60.0).unwrap(); // still falling: 0.35 s of the 0.64 s the fall takes
        let falling = clock.elapsed().as_secs_f64() * 1e3 / 20.0;
        w.step(40.0 / 60.0).unwrap(); // landed and settling
        let before = w.report();
        let clock = Instant::now();
        w.step(steps as f64 / 60.0).unwrap();
        let landed = clock.elapsed().as_secs_f64() * 1e3 / steps as f64;
        let r = w.report();
        let per = |a: f64, b: f64| (a - b) * 1e3 / steps as f64;
        println!(
            "| {n} | {build:.2} | {falling:.2} | {landed:.1} ({:.1} + {:.1}) | {:.0} | {:.0} | {:.0} |",
            per(r.collision_seconds, before.collision_seconds),
            per(r.contact_seconds, before.contact_seconds),
            (r.impulses - before.impulses) as f64 / steps as f64,
            (r.islands - before.islands) as f64 / steps as f64,
            peak_mb()
        );
    }
}

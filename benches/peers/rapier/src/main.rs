//! The peer comparison's scenes in Rapier 0.36 (f64, its defaults, one thread), one markdown row each; the same
//! scene definitions as tumble's `examples/fast_scenes.rs` (z up, g = 9.81):
//! a pile of N cubes of half extent 0.5 m, density 1000, on a 10 x 10 grid at 1.2 m pitch in N / 100 layers 1.2 m
//! apart, the lowest bottoms 2 m up, friction 0.5, dt 1/60, 600 steps, without and with sleeping (ms a step over
//! all 600, the steps alone timed; penetration the largest over the last 100); a stack of 10 cubes of half extent 0.25 m, density 500, friction
//! 0.6, dt 1/240, 10 s (largest displacement); a slide (half extent 0.2 m, density 500, 2 m/s, mu 0.5, dt 1/240,
//! 2 s; stop distance against v^2 / (2 mu g)); a resting cube of half extent 0.5 m for 10 s; a bullet (5 cm sphere
//! at 1000 m/s against a 1 cm static wall, dt 1/60); the stack's and the resting cube's time a step (the fixed cost
//! of a step). `meshes`: the 50-mesh pile (`meshes.rs`). `pyramids`: Box3D's two benchmark walls of cubes instead.
//! `--substeps N`: Rapier's solver iterations (its substeps; 4 by default). `--only-piles`: the piles alone.
//! Penetration is the deepest overlap recomputed from the poses (`../overlap.rs`), as for every engine.

use rapier3d_f64::prelude::*;
use std::time::Instant;

mod meshes;
#[path = "../../overlap.rs"]
mod overlap;

/// Solver iterations (Rapier's substeps) of every world, `--substeps N` (4, Rapier's default, if not given).
static SUBSTEPS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(4);

const G: f64 = 9.81;

fn world(dt: f64) -> PhysicsWorld {
    let mut w = PhysicsWorld::default();
    w.gravity = Vector::new(0.0, 0.0, -G);
    w.integration_parameters.dt = dt;
    w.integration_parameters.num_solver_iterations = SUBSTEPS.load(std::sync::atomic::Ordering::Relaxed);
    w
}

/// The floor: a fixed slab whose top is z = 0.
fn ground(w: &mut PhysicsWorld, mu: f64) {
    let floor = w.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -1.0)));
    w.insert_collider(ColliderBuilder::cuboid(1000.0, 1000.0, 1.0).friction(mu).restitution(0.0), Some(floor));
}

fn cube(w: &mut PhysicsWorld, half: f64, density: f64, at: Vector, mu: f64, sleep: bool) -> RigidBodyHandle {
    let (b, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(at).can_sleep(sleep),
        ColliderBuilder::cuboid(half, half, half).density(density).friction(mu).restitution(0.0),
    );
    b
}

/// The cubes of half extent `half` as boxes posed where the world has them (nalgebra, for `overlap.rs`).
fn boxes(w: &PhysicsWorld, cubes: &[RigidBodyHandle], half: f64) -> Vec<overlap::Boxed> {
    cubes
        .iter()
        .map(|&b| {
            let p = w.bodies[b].position();
            let (t, r) = (p.translation, p.rotation);
            let rotation = nalgebra::UnitQuaternion::new_normalize(nalgebra::Quaternion::new(r.w, r.x, r.y, r.z));
            let pose = nalgebra::Isometry3::from_parts(nalgebra::Translation3::new(t.x, t.y, t.z), rotation);
            (nalgebra::Vector3::repeat(half), pose)
        })
        .collect()
}

/// The pile: (ms a step, the deepest overlap over the last 100 steps, recomputed from the poses).
fn pile(n: usize, sleep: bool) -> (f64, f64) {
    let mut w = world(1.0 / 60.0);
    ground(&mut w, 0.5);
    let cubes: Vec<RigidBodyHandle> = (0..n)
        .map(|k| {
            let (layer, i, j) = (k / 100, (k % 100) / 10, k % 10);
            let at = Vector::new(1.2 * i as f64, 1.2 * j as f64, 2.5 + 1.2 * layer as f64);
            cube(&mut w, 0.5, 1000.0, at, 0.5, sleep)
        })
        .collect();
    let (mut spent, mut worst) = (0.0, 0.0f64);
    for step in 0..600 {
        let clock = Instant::now();
        w.step();
        spent += clock.elapsed().as_secs_f64();
        if step >= 500 {
            worst = worst.max(overlap::deepest(&boxes(&w, &cubes, 0.5)));
        }
    }
    (spent * 1e3 / 600.0, worst)
}

/// Box3D's benchmark walls (`tumble::scenes::LargePyramid`, `ManyPyramids`; the same cubes, poses, density and
/// friction, z up), at 1/60 s with sleeping off: a wall of `base` unit cubes with its bottom left cube's centre at
/// x = `left`, in the plane y = `y`; bottom row first.
fn wall(w: &mut PhysicsWorld, base: usize, left: f64, y: f64) -> Vec<RigidBodyHandle> {
    let mut out = Vec::new();
    for row in 0..base {
        let z = (2 * row + 1) as f64 * 0.5;
        for k in row..base {
            let x = left + row as f64 * 0.5 + (k - row) as f64;
            let (b, _) = w.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(x, y, z)).can_sleep(false),
                ColliderBuilder::cuboid(0.5, 0.5, 0.5).density(100.0).friction(0.6).restitution(0.0),
            );
            out.push(b);
        }
    }
    out
}

/// Steps a world of walls `steps` times (the first untimed): (ms a step, the largest sink of a top cube, the
/// deepest overlap at the end).
fn walls(mut w: PhysicsWorld, walls: Vec<Vec<RigidBodyHandle>>, steps: usize) -> (f64, f64, f64) {
    let tops: Vec<RigidBodyHandle> = walls.iter().map(|c| *c.last().unwrap()).collect();
    let start: Vec<f64> = tops.iter().map(|&b| w.bodies[b].translation().z).collect();
    w.step();
    let clock = Instant::now();
    for _ in 1..steps {
        w.step();
    }
    let ms = clock.elapsed().as_secs_f64() * 1e3 / (steps - 1) as f64;
    let sink = tops.iter().zip(&start).map(|(&b, z)| z - w.bodies[b].translation().z).fold(0.0, f64::max);
    let all: Vec<RigidBodyHandle> = walls.into_iter().flatten().collect();
    (ms, sink, overlap::deepest(&boxes(&w, &all, 0.5)))
}

/// A world at 1/60 s over a fixed slab of half extents `half` x `half` x 1 whose top is z = 0 (friction 0.6).
fn slab_world(half: f64) -> PhysicsWorld {
    let mut w = world(1.0 / 60.0);
    let floor = w.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -1.0)));
    w.insert_collider(ColliderBuilder::cuboid(half, half, 1.0).friction(0.6).restitution(0.0), Some(floor));
    w
}

fn pyramids() {
    let mut w = slab_world(400.0);
    let cubes = wall(&mut w, 100, 0.5 - 50.0, 0.0);
    let (ms, sink, deepest) = walls(w, vec![cubes], 200);
    println!(
        "| large pyramid (5,050 cubes), 200 steps: ms a step / top's sink / overlap | {ms:.1} ms / {:.1} mm / {:.2} mm |",
        sink * 1e3,
        deepest * 1e3
    );
    let (rows, columns, base) = (14, 14, 10);
    let extent = 0.5 * columns as f64 * (base as f64 + 1.0);
    let mut w = slab_world(extent);
    let spacing = 2.0 * (extent - 1.0) / (rows as f64 - 1.0);
    let mut all = Vec::new();
    for i in 0..rows {
        let y = -(-extent + 1.0 + spacing * i as f64);
        for j in 0..columns {
            let centre = -extent + j as f64 * (base as f64 + 1.0) + 1.0;
            all.push(wall(&mut w, base, 0.5 + centre - 0.5, y));
        }
    }
    let (ms, sink, deepest) = walls(w, all, 100);
    println!(
        "| many pyramids (10,780 cubes), 100 steps: ms a step / largest top's sink / overlap | {ms:.1} ms / {:.2} mm / {:.2} mm |",
        sink * 1e3,
        deepest * 1e3
    );
}

/// Largest displacement of any of `bodies` over `steps`, and the time of a step (us; the steps alone timed).
fn displacement(w: &mut PhysicsWorld, bodies: &[RigidBodyHandle], steps: usize) -> (f64, f64) {
    let start: Vec<Vector> = bodies.iter().map(|&b| w.bodies[b].translation()).collect();
    let (mut worst, mut spent) = (0.0f64, 0.0);
    for _ in 0..steps {
        let clock = Instant::now();
        w.step();
        spent += clock.elapsed().as_secs_f64();
        for (&b, s) in bodies.iter().zip(&start) {
            worst = worst.max((w.bodies[b].translation() - *s).length());
        }
    }
    (worst, spent * 1e6 / steps as f64)
}

/// The joint scenes (`examples/joint_scenes.rs` in tumble has their definitions), with impulse joints or multibody
/// joints; contacts between jointed bodies disabled, as tumble's are.
mod joints {
    use super::*;

    /// Either joint set, by kind.
    fn join(
        w: &mut PhysicsWorld,
        multibody: bool,
        a: RigidBodyHandle,
        b: RigidBodyHandle,
        joint: impl Into<GenericJoint>,
    ) {
        if multibody {
            w.multibody_joints.insert(a, b, joint, true).expect("a tree");
        } else {
            w.impulse_joints.insert(a, b, joint, true);
        }
    }

    type Anchor = (RigidBodyHandle, Vector);

    /// The chain, turned about the pivot when `horizontal`; its joints' anchors in pairs.
    fn chain(w: &mut PhysicsWorld, multibody: bool, horizontal: bool) -> Vec<(Anchor, Anchor)> {
        let pivot = Vector::new(0.0, 0.0, 2.5);
        let turn = if horizontal { Vector::new(0.0, -std::f64::consts::FRAC_PI_2, 0.0) } else { Vector::ZERO };
        let place = |v: Vector| if horizontal { Vector::new(-v.z, v.y, v.x) } else { v };
        let fixed = w.insert_body(RigidBodyBuilder::fixed());
        let (top, bottom) = (Vector::new(0.0, 0.0, 0.05), Vector::new(0.0, 0.0, -0.05));
        let mut above: Anchor = (fixed, pivot);
        let mut out = Vec::new();
        for k in 0..20 {
            let at = pivot + place(Vector::new(0.0, 0.0, -0.05 - 0.1 * k as f64));
            let (b, _) = w.insert(
                RigidBodyBuilder::dynamic().translation(at).rotation(turn).can_sleep(false),
                ColliderBuilder::capsule_z(0.04, 0.01).mass(1.0),
            );
            let joint = SphericalJointBuilder::new().local_anchor1(above.1).local_anchor2(top).contacts_enabled(false);
            join(w, multibody, above.0, b, joint);
            out.push((above, (b, top)));
            above = (b, bottom);
        }
        let at = pivot + place(Vector::new(0.0, 0.0, -2.1));
        let (ball, _) = w.insert(
            RigidBodyBuilder::dynamic().translation(at).rotation(turn).can_sleep(false),
            ColliderBuilder::ball(0.1).mass(10.0),
        );
        let anchor = Vector::new(0.0, 0.0, 0.1);
        let joint = SphericalJointBuilder::new().local_anchor1(above.1).local_anchor2(anchor).contacts_enabled(false);
        join(w, multibody, above.0, ball, joint);
        out.push((above, (ball, anchor)));
        out
    }

    fn stretch(w: &PhysicsWorld, joints: &[(Anchor, Anchor)]) -> f64 {
        let point = |(b, p): &Anchor| w.bodies[*b].position().transform_point(*p);
        joints.iter().map(|(a, b)| (point(a) - point(b)).length()).sum()
    }

    pub fn table(multibody: bool) {
        let kind = if multibody { "multibody" } else { "impulse" };
        println!("| Rapier 0.36.1 (f64, {kind} joints, defaults) | value |\n|---|---|");
        let dt = 1.0 / 60.0;
        for (horizontal, label) in [
            (false, "chain hanging, dt 1/60: stretch after 5 s"),
            (true, "chain from horizontal, dt 1/60: largest stretch in 5 s"),
        ] {
            let mut w = world(dt);
            let joints = chain(&mut w, multibody, horizontal);
            let (mut spent, mut worst) = (0.0, 0.0f64);
            for _ in 0..300 {
                let clock = Instant::now();
                w.step();
                spent += clock.elapsed().as_secs_f64();
                worst = worst.max(stretch(&w, &joints));
            }
            let value = if horizontal { worst } else { stretch(&w, &joints) };
            println!("| {label} / ms a step | {value:.2e} m / {:.3} ms |", spent * 1e3 / 300.0);
        }
        let mut w = world(dt);
        let fixed = w.insert_body(RigidBodyBuilder::fixed());
        let r = 0.05;
        let (bob, _) = w.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(1.0, 0.0, 0.0)).can_sleep(false),
            ColliderBuilder::ball(r).mass(1.0),
        );
        let hinge = RevoluteJointBuilder::new(Vector::Y)
            .local_anchor1(Vector::ZERO)
            .local_anchor2(Vector::new(-1.0, 0.0, 0.0))
            .contacts_enabled(false);
        join(&mut w, multibody, fixed, bob, hinge);
        let (mut spent, mut crossings, mut last) = (0.0, Vec::new(), (0.0, 1.0));
        for k in 0..600 {
            let clock = Instant::now();
            w.step();
            spent += clock.elapsed().as_secs_f64();
            let (t, x) = ((k + 1) as f64 * dt, w.bodies[bob].translation().x);
            if last.1 > 0.0 && x <= 0.0 {
                crossings.push(last.0 + last.1 / (last.1 - x) * (t - last.0));
            }
            last = (t, x);
        }
        let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        let exact = 4.0 * ((1.0 + 0.4 * r * r) / G).sqrt() * 1.854_074_677_301_372;
        println!(
            "| hinged pendulum from 90 deg, dt 1/60: period error / ms a step | {:+.2e} / {:.4} ms |",
            (period - exact) / exact,
            spent * 1e3 / 600.0
        );
    }
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(k) = args.iter().position(|a| a == "--substeps") {
        let n: usize = args[k + 1].parse().expect("a whole number of substeps");
        SUBSTEPS.store(n, std::sync::atomic::Ordering::Relaxed);
        args.drain(k..k + 2);
    }
    let substeps = SUBSTEPS.load(std::sync::atomic::Ordering::Relaxed);
    if args.iter().any(|a| a == "pyramids") {
        println!("| Rapier 0.36.1 (f64, {substeps} substeps) | value |\n|---|---|");
        pyramids();
        return;
    }
    if args.iter().any(|a| a == "meshes") {
        meshes::table();
        return;
    }
    if args.iter().any(|a| a == "joints") {
        joints::table(args.iter().any(|a| a == "multibody"));
        return;
    }
    let sizes: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    println!("| Rapier 0.36.1 (f64, {substeps} substeps) | value |\n|---|---|");
    for &n in if sizes.is_empty() { &[100usize, 1000][..] } else { &sizes[..] } {
        for (sleep, label) in [(false, "no sleep"), (true, "sleeping")] {
            let (ms, pen) = pile(n, sleep);
            println!(
                "| pile {n}, {label}: ms a step / penetration (last 100 steps) | {ms:.3} ms / {:.3} mm |",
                pen * 1e3
            );
        }
    }
    if args.iter().any(|a| a == "--only-piles") {
        return;
    }
    let dt = 1.0 / 240.0;
    let mut w = world(dt);
    ground(&mut w, 0.6);
    let stack: Vec<_> =
        (0..10).map(|k| cube(&mut w, 0.25, 500.0, Vector::new(0.0, 0.0, 0.25 + 0.5 * k as f64), 0.6, false)).collect();
    let (moved, us) = displacement(&mut w, &stack, 2400);
    println!("| stack of 10: largest displacement in 10 s | {:.3} mm |", moved * 1e3);
    println!("| stack of 10: us a step | {us:.2} us |");
    let mut w = world(dt);
    ground(&mut w, 0.5);
    let (b, _) = w.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.0, 0.2))
            .linvel(Vector::new(2.0, 0.0, 0.0))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.2, 0.2, 0.2).density(500.0).friction(0.5).restitution(0.0),
    );
    for _ in 0..480 {
        w.step();
    }
    let exact = 4.0 / (2.0 * 0.5 * G);
    println!("| slide: stop distance error | {:+.3}% |", (w.bodies[b].translation().x - exact) / exact * 100.0);
    let mut w = world(dt);
    ground(&mut w, 0.5);
    let b = cube(&mut w, 0.5, 1000.0, Vector::new(0.0, 0.0, 0.5), 0.5, false);
    let (moved, us) = displacement(&mut w, &[b], 2400);
    println!("| rest: largest displacement in 10 s | {moved:.2e} m |");
    println!("| rest: us a step | {us:.2} us |");
    let mut w = world(1.0 / 60.0);
    ground(&mut w, 0.5);
    let wall = w.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(5.0, 0.0, 2.0)));
    w.insert_collider(ColliderBuilder::cuboid(0.005, 2.0, 2.0), Some(wall));
    let (ball, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, 2.0)).linvel(Vector::new(1000.0, 0.0, 0.0)),
        ColliderBuilder::ball(0.05).density(1000.0),
    );
    for _ in 0..30 {
        w.step();
    }
    let x = w.bodies[ball].translation().x;
    println!(
        "| bullet: ball ends at x (wall at 5 m) | {x:.3} m ({}) |",
        if x < 5.0 { "held by the wall" } else { "TUNNELLED" }
    );
}

//! Bit-for-bit fingerprints of seeded scenes in every mode, for checking that a change of the engine's code
//! leaves the physics alone: random drops in accurate and fast mode (both solvers), a 300-box pile, the jointed
//! scenes, the cloth and its drape, and springs with every integrator, each on 1 and 2 threads. For each it
//! prints a hash of every state it passed through (positions, orientations, momenta, to the bit) and a hash of
//! the report's counters. Run it before and after a change and compare the two outputs:
//!
//! ```text
//! cargo run --release --example state_hashes > before.txt
//! ```
//!
//! Only the public API is used, so the same file runs on any version that has it. `--quick` leaves out the
//! slowest scenes; a scene's name as an argument runs only the scenes whose names hold it; `--dump` also prints
//! every body's pose after each step in full, to measure how far apart two builds whose hashes differ have moved.

#[path = "../tests/it/common/mod.rs"]
mod common;

use common::Lcg;
use nalgebra::Vector3;
use tumble::{
    scenes, Attachment, FastFriction, FastSettings, FastSolver, IntegratorOptions, Material, Mode, ParticleBuilder,
    Persistent, RigidBodyBuilder, Shape, SpringBuilder, Target, World, WorldOptions,
};

/// FNV-1a over 64-bit words.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn word(&mut self, w: u64) {
        for b in w.to_le_bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn float(&mut self, x: f64) {
        self.word(x.to_bits());
    }
}

/// Every number of the world's state, to the bit.
fn hash_state(h: &mut Fnv, w: &World) {
    h.float(w.time());
    for (_, p) in w.particles() {
        p.position().iter().chain(p.velocity().iter()).for_each(|v| h.float(*v));
    }
    for (_, b) in w.bodies() {
        let q = b.orientation();
        b.position().iter().chain(b.momentum().iter()).chain(b.angular_momentum().iter()).for_each(|v| h.float(*v));
        [q.w, q.i, q.j, q.k].iter().for_each(|v| h.float(*v));
    }
}

/// The report's counters (no wall times).
fn hash_report(h: &mut Fnv, w: &World) {
    let r = w.report();
    let i = &r.integrator;
    for n in [
        i.steps,
        i.rejected,
        i.rhs_evals,
        i.jacobians,
        i.factorizations,
        i.linear_solves,
        i.newton_iterations,
        r.qp_solves,
        r.collisions,
        r.impulses,
        r.bisection_steps,
        r.collision_checks,
        r.islands,
        r.sleepers,
        r.contact_steps,
        r.contact_rejected,
        r.joint_rows,
        r.forces.evaluations,
        r.forces.spring_evaluations,
        r.forces.load_evaluations,
        r.forces.callback_calls,
        r.forces.projections,
    ] {
        h.word(n as u64);
    }
    for x in [r.max_penetration, r.contact_residual, r.energy_change, r.contact_error, r.joint_error] {
        h.float(x);
    }
    h.float(r.step_error.unwrap_or(-1.0));
    h.float(r.energy_gain.unwrap_or(-1.0));
    h.float(i.error_estimate.unwrap_or(-1.0));
}

/// The tests' seeded random drop (one to five random shapes over a ground, `tests/it/common`) in `mode`, with a
/// particle of a radius thrown at it.
fn random_drop(seed: u64, mode: Mode) -> World {
    let mut w = common::random_drop(seed);
    w.set_mode(mode).unwrap();
    let mut rng = Lcg(seed.wrapping_add(1));
    let particle = ParticleBuilder::new(rng.range(0.1, 2.0))
        .radius(0.05)
        .position(Vector3::new(0.8, 0.0, 0.5))
        .velocity(Vector3::new(-1.0, 0.0, 0.0))
        .material(Material::new(rng.range(0.0, 0.6), rng.range(0.0, 1.0)));
    w.add_particle(particle).unwrap();
    w
}

/// Two particles and a body joined by damped springs, one hung from a fixed point, with a constant force, a torque,
/// damping and a particle's restoring term: every force term of the equations of motion.
fn springs() -> World {
    let mut w = World::new();
    let p = w
        .add_particle(
            ParticleBuilder::new(0.5)
                .position(Vector3::new(0.0, 0.0, 1.0))
                .velocity(Vector3::new(0.3, 0.0, 0.0))
                .damping(0.1),
        )
        .unwrap();
    let q = w
        .add_particle(
            ParticleBuilder::new(0.8)
                .position(Vector3::new(0.5, 0.2, 1.2))
                .stiffness(20.0)
                .anchor(Vector3::new(0.5, 0.0, 1.0)),
        )
        .unwrap();
    let b = w
        .add_body(
            RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::new(0.2, 0.1, 0.05)).unwrap(), 500.0)
                .position(Vector3::new(0.2, -0.3, 0.6))
                .angular_velocity(Vector3::new(0.5, 2.0, -1.0))
                .linear_damping(0.05),
        )
        .unwrap();
    let spring = |a, b, k| SpringBuilder::new(a, b).stiffness(k).damping(0.5);
    w.add_spring(spring(Attachment::Particle(p), Attachment::Point(Vector3::new(0.0, 0.0, 2.0)), 200.0)).unwrap();
    w.add_spring(spring(Attachment::Particle(p), Attachment::Particle(q), 150.0)).unwrap();
    w.add_spring(spring(Attachment::Particle(q), Attachment::Body(b, Vector3::new(0.2, 0.1, 0.0)), 300.0)).unwrap();
    w.add_spring(spring(
        Attachment::Body(b, Vector3::new(-0.2, 0.0, 0.05)),
        Attachment::Point(Vector3::new(0.0, -0.5, 1.5)),
        400.0,
    ))
    .unwrap();
    w.add_force(Target::Body(b), Vector3::new(0.5, 0.0, 0.0), Some(Vector3::new(0.0, 0.1, 0.0))).unwrap();
    w.add_torque(b, Vector3::new(0.0, 0.0, 0.02)).unwrap();
    w.add_force(Target::Particle(q), Vector3::new(0.0, 0.1, 0.0), None).unwrap();
    w
}

/// The same springs under the integrator the options name.
fn springs_with(integrator: IntegratorOptions) -> World {
    let template = WorldOptions { integrator, ..Default::default() }.build().unwrap();
    let mut w = springs();
    w.set_integrator(template.settings().clone()).unwrap();
    w
}

fn integrator(name: &str, dt: Option<f64>, rtol: Option<f64>) -> IntegratorOptions {
    IntegratorOptions { integrator: Some(name.into()), dt, rtol, atol: rtol.map(|r| r * 1e-3), ..Default::default() }
}

type Build = Box<dyn Fn() -> World>;

/// A scene: its name, how to build it, and the steps to take (each of `step` seconds, `count` times).
struct Scene {
    name: String,
    build: Build,
    step: f64,
    count: usize,
    slow: bool,
}

fn scene(name: impl Into<String>, step: f64, count: usize, build: impl Fn() -> World + 'static) -> Scene {
    Scene { name: name.into(), build: Box::new(build), step, count, slow: false }
}

fn all_scenes() -> Vec<Scene> {
    let fast = |solver: FastSolver| Mode::Fast(FastSettings { solver, ..FastSettings::new(1.0 / 240.0) });
    let exact_cone = FastSolver::Exact { erp: 0.2, friction: FastFriction::Cone };
    let mut out = Vec::new();
    for seed in 0..8u64 {
        out.push(scene(format!("accurate-drop-{seed}"), 1.0 / 60.0, 90, move || random_drop(seed, Mode::default())));
        out.push(scene(format!("fast-soft-drop-{seed}"), 1.0 / 60.0, 120, move || {
            random_drop(seed, fast(FastSolver::default()))
        }));
        out.push(scene(format!("fast-exact-drop-{seed}"), 1.0 / 60.0, 60, move || {
            random_drop(seed, fast(FastSolver::exact()))
        }));
    }
    out.push(scene("fast-exact-cone-drop", 1.0 / 60.0, 60, move || random_drop(5, fast(exact_cone))));
    out.push(scene("fast-step-doubling-drop", 1.0 / 60.0, 30, move || {
        random_drop(6, Mode::Fast(FastSettings { step_doubling: true, ..FastSettings::new(1.0 / 240.0) }))
    }));
    out.push(scene("fast-no-sleep-drop", 1.0 / 60.0, 60, move || {
        random_drop(7, Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(1.0 / 240.0) }))
    }));
    out.push(scene("accurate-resting-forces", 1.0 / 60.0, 60, || {
        let mut w = World::new();
        let mode = tumble::AccurateSettings { persistent: Persistent::RestingForces, ..Default::default() };
        w.set_mode(Mode::Accurate(mode)).unwrap();
        w.add_ground(0.0, Material::new(0.5, 0.0)).unwrap();
        let ball = RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0)
            .position(Vector3::new(0.0, 0.0, 0.5))
            .restitution(0.5)
            .friction(0.0);
        w.add_body(ball).unwrap();
        w
    }));
    out.push(scene("accurate-bouncing-ball", 1.0 / 30.0, 60, || scenes::BouncingBall::default().build().unwrap().0));
    out.push(scene("accurate-tumbling-box", 1.0 / 30.0, 45, || scenes::tumbling_box().unwrap().0));
    let mut pile = scene("fast-pile-300", 1.0 / 60.0, 120, || scenes::Pile { side: 10, layers: 3 }.build().unwrap().0);
    pile.slow = true;
    out.push(pile);
    out.push(scene("fast-exact-pile-16", 1.0 / 60.0, 30, || {
        let (mut w, _) = scenes::Pile { side: 4, layers: 1 }.build().unwrap();
        w.set_mode(Mode::Fast(FastSettings { solver: FastSolver::exact(), ..FastSettings::new(1.0 / 240.0) })).unwrap();
        w
    }));
    out.push(scene("dominoes", 1.0 / 60.0, 60, || scenes::Dominoes::default().build().unwrap().0));
    out.push(scene("pyramid", 1.0 / 60.0, 60, || scenes::Pyramid::default().build().unwrap().0));
    for (name, count) in [("pendulum", 60), ("chain", 60), ("newtons_cradle", 60), ("door", 60), ("ragdoll", 60)] {
        out.push(scene(format!("joints-{name}"), 1.0 / 60.0, count, move || scenes::build(name, &[]).unwrap()));
        let mut accurate = scene(format!("joints-{name}-accurate"), 1.0 / 60.0, 60, move || {
            let mut w = scenes::build(name, &[]).unwrap();
            if w.mode() != Mode::default() {
                w.set_mode(Mode::default()).unwrap();
            }
            w
        });
        accurate.slow = name == "chain" || name == "ragdoll";
        out.push(accurate);
    }
    out.push(scene("cloth", 1.0 / 60.0, 30, || scenes::build("cloth", &[]).unwrap()));
    out.push(scene("cloth-drape", 1.0 / 60.0, 60, || scenes::build("cloth_drape", &[]).unwrap()));
    out.push(scene("spinning-top", 1.0 / 30.0, 30, || scenes::build("spinning_top", &[]).unwrap()));
    out.push(scene("springs-fast", 1.0 / 60.0, 60, || {
        let mut w = springs();
        w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
        w
    }));
    for name in ["euler", "midpoint", "rk4", "ab4", "am4", "implicit-euler", "symplectic-euler", "verlet"] {
        out.push(scene(format!("springs-{name}-fixed"), 0.05, 20, move || {
            springs_with(integrator(name, Some(1e-3), None))
        }));
    }
    for name in ["dopri5", "rodas4", "radau5", "dop853"] {
        out.push(scene(format!("springs-{name}-adaptive"), 0.05, 20, move || {
            springs_with(integrator(name, None, Some(1e-8)))
        }));
    }
    out.push(scene("springs-euler-variable", 0.05, 10, || {
        springs_with(IntegratorOptions {
            integrator: Some("euler-variable".into()),
            tolerance: Some(1e-5),
            ..Default::default()
        })
    }));
    out.push(scene("springs-step-doubling-rk4", 0.05, 20, || {
        springs_with(IntegratorOptions {
            integrator: Some("rk4".into()),
            step_doubling: true,
            tolerance: Some(1e-7),
            ..Default::default()
        })
    }));
    out.push(scene("springs-implicit-euler-newton", 0.05, 20, || {
        springs_with(IntegratorOptions {
            integrator: Some("implicit-euler".into()),
            dt: Some(2e-3),
            newton: true,
            ..Default::default()
        })
    }));
    out.push(scene("springs-callback", 0.05, 20, || {
        let mut w = springs();
        let (p, _) = w.particles().next().unwrap();
        w.add_force_callback(Target::Particle(p), |t, s| {
            Ok(tumble::Wrench { force: -s.velocity * 0.2 + Vector3::new(t.sin(), 0.0, 0.0), torque: Vector3::zeros() })
        })
        .unwrap();
        w
    }));
    out.push(scene("springs-on-ground-rodas4", 1.0 / 60.0, 30, || {
        let mut w = springs_with(integrator("rodas4", None, Some(1e-7)));
        w.add_ground(0.0, Material::new(0.3, 0.4)).unwrap();
        w
    }));
    out
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let dump = std::env::args().any(|a| a == "--dump");
    let only: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with("--"));
    for s in all_scenes() {
        if (quick && s.slow) || only.as_ref().is_some_and(|o| !s.name.contains(o.as_str())) {
            continue;
        }
        for threads in [1usize, 2] {
            let mut w = (s.build)();
            w.set_threads(threads).unwrap();
            let (mut state, mut counters) = (Fnv::new(), Fnv::new());
            let mut outcome = "ok".to_string();
            for _ in 0..s.count {
                if let Err(e) = w.step(s.step) {
                    outcome = format!("error: {e}");
                    break;
                }
                hash_state(&mut state, &w);
                if dump {
                    // every body's pose in full after each step, to measure how far apart two builds whose hashes
                    // differ have moved, and from when
                    for (_, b) in w.bodies() {
                        let (x, q) = (b.position(), b.orientation());
                        let pose = [x.x, x.y, x.z, q.w, q.i, q.j, q.k].map(|v| format!("{v:.17e}")).join(" ");
                        println!("  pose t {:.6} {pose}", w.time());
                    }
                }
            }
            hash_report(&mut counters, &w);
            println!(
                "{:<34} threads {threads}  state {:016x}  counters {:016x}  {outcome}",
                s.name, state.0, counters.0
            );
        }
    }
}

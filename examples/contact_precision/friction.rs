//! The friction half of `contact_precision`: three problems with closed forms, accurate mode over contact
//! tolerances and fast mode over steps (its soft step and its exact cone program), error against the fastest wall
//! time of three runs.

use nalgebra::Vector3;
use std::io::Write;
use std::time::Instant;
use tumble::{AccurateSettings, FastSettings, FastSolver, Material, Mode, RigidBodyBuilder, Shape, World, WorldError};

const G: f64 = 9.81;

/// A problem: its name, how long it runs, the world for a mode, and the relative error of a finished world.
struct Problem {
    name: &'static str,
    seconds: f64,
    theta: f64,
    mu: f64,
    body: fn(f64) -> RigidBodyBuilder,
    error: fn(&World, f64, f64) -> f64,
}

fn cube(mu: f64) -> RigidBodyBuilder {
    RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.25)).unwrap(), 1000.0)
        .position(Vector3::new(0.0, 0.0, 0.25))
        .restitution(0.0)
        .friction(mu)
}

/// How far the one moving body went along x.
fn travelled(w: &World) -> f64 {
    w.bodies().find(|(_, b)| !b.is_static()).map_or(f64::NAN, |(_, b)| b.position().x)
}

fn problems() -> Vec<Problem> {
    vec![
        Problem {
            name: "sliding box: stop distance (v 2 m/s, mu 0.5)",
            seconds: 0.6,
            theta: 0.0,
            mu: 0.5,
            body: |mu| cube(mu).velocity(Vector3::new(2.0, 0.0, 0.0)),
            error: |w, _, mu| {
                let exact = 4.0 / (2.0 * mu * G);
                (travelled(w) - exact).abs() / exact
            },
        },
        Problem {
            name: "box on a 35 deg incline: distance in 0.5 s (mu 0.5)",
            seconds: 0.5,
            theta: 35f64.to_radians(),
            mu: 0.5,
            body: cube,
            error: |w, theta, mu| {
                let exact = 0.5 * G * (theta.sin() - mu * theta.cos()) * 0.25;
                (travelled(w) - exact).abs() / exact
            },
        },
        Problem {
            name: "sphere rolling down 30 deg: distance in 0.5 s (mu 0.3)",
            seconds: 0.5,
            theta: 30f64.to_radians(),
            mu: 0.3,
            body: |mu| {
                RigidBodyBuilder::from_shape(Shape::sphere(0.2).unwrap(), 1000.0)
                    .position(Vector3::new(0.0, 0.0, 0.2))
                    .restitution(0.0)
                    .friction(mu)
            },
            error: |w, theta, _| {
                let exact = 0.5 * 5.0 / 7.0 * G * theta.sin() * 0.25;
                (travelled(w) - exact).abs() / exact
            },
        },
    ]
}

/// The problem's world in `mode`, the incline as gravity tilted about y.
fn world(p: &Problem, mode: Mode) -> Result<World, WorldError> {
    let mut w = World::new();
    w.set_mode(mode)?;
    w.set_gravity(Vector3::new(G * p.theta.sin(), 0.0, -G * p.theta.cos()))?;
    w.add_ground(0.0, Material::new(0.0, p.mu))?;
    w.add_body((p.body)(p.mu))?;
    Ok(w)
}

/// (relative error, fastest wall time of three runs in s, steps).
fn measure(p: &Problem, mode: Mode) -> Result<(f64, f64, usize), WorldError> {
    let mut best = f64::INFINITY;
    let mut out = (f64::NAN, 0);
    for _ in 0..3 {
        let mut w = world(p, mode)?;
        let clock = Instant::now();
        w.step(p.seconds)?;
        best = best.min(clock.elapsed().as_secs_f64());
        let r = w.report();
        out = ((p.error)(&w, p.theta, p.mu), r.contact_steps.max(r.integrator.steps));
    }
    Ok((out.0, best, out.1))
}

/// Prints the sweep and writes it as CSV.
pub fn sweep() -> Result<(), WorldError> {
    let mut csv = String::from("problem,mode,setting,relative_error,wall_seconds,steps\n");
    for p in problems() {
        println!("{}", p.name);
        println!("  mode      setting            relative error  wall (ms)   steps");
        for (name, solver) in [("fast soft", FastSolver::default()), ("fast exact", FastSolver::exact())] {
            for k in [60.0, 240.0, 960.0, 3840.0] {
                let mode = Mode::Fast(FastSettings { sleep: false, solver, ..FastSettings::new(1.0 / k) });
                match measure(&p, mode) {
                    Ok((e, wall, steps)) => {
                        println!("  {name:<11}h = 1/{k:<11} {e:>14.2e}  {:>9.3}  {steps:>6}", wall * 1e3);
                        csv += &format!("\"{}\",{name},{},{e:e},{wall:e},{steps}\n", p.name, 1.0 / k);
                    }
                    Err(e) => println!("  {name:<11}h = 1/{k:<11} failed: {e}"),
                }
            }
        }
        for tol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let mode = Mode::Accurate(AccurateSettings { contact_tolerance: Some(tol), ..AccurateSettings::default() });
            match measure(&p, mode) {
                Ok((e, wall, steps)) => {
                    println!("  accurate  tolerance {tol:<8.0e} {e:>14.2e}  {:>9.3}  {steps:>6}", wall * 1e3);
                    csv += &format!("\"{}\",accurate,{tol},{e:e},{wall:e},{steps}\n", p.name);
                }
                Err(e) => println!("  accurate  tolerance {tol:<8.0e} failed: {e}"),
            }
        }
    }
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/contact_precision.csv");
    if let Ok(mut f) = std::fs::File::create(&path) {
        let _ = f.write_all(csv.as_bytes());
        println!("\nwritten to {}", path.display());
    }
    Ok(())
}

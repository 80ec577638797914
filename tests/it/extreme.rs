//! The extreme battery: stiff springs to 1e10 with every method, mass ratios to 1e6, speeds to 1e4 m/s, steps from
//! 1e-9 s to 1 s, bodies from 1 mm to 1 km, overlapping starts and fast spins, in both contact modes. Each scene
//! must end finite or fail with a clean error that leaves the world as it was: never a NaN, a panic or a hang.
//! `-- --nocapture` prints how each ended.

use crate::common;
use common::state_bits;
use nalgebra::{UnitQuaternion, Vector3};
use tumble::{
    Attachment, FastSettings, Material, Method, Mode, ParticleBuilder, RigidBodyBuilder, Settings, Shape,
    SpringBuilder, World, WorldError,
};

/// Runs `seconds` in steps of `chunk` (stopping at the first failure) and checks the outcome: finite if it ran,
/// unchanged by the failed call if it failed, and the failure a simulation error. Returns how it ended.
fn outcome(name: &str, w: &mut World, seconds: f64, chunk: f64) -> Result<(), WorldError> {
    let steps = (seconds / chunk).round() as usize;
    for _ in 0..steps {
        let before = state_bits(w);
        if let Err(e) = w.step(chunk) {
            assert_eq!(state_bits(w), before, "{name}: the failed step ({e}) changed the world");
            assert!(
                matches!(e, WorldError::Simulation(_)),
                "{name}: a scene that was accepted fails as a simulation: {e}"
            );
            println!("{name}: clean error at t = {}: {e}", w.time());
            return Err(e);
        }
        assert!(
            state_bits(w).iter().all(|b| f64::from_bits(*b).is_finite()),
            "{name}: non-finite state at t = {}",
            w.time()
        );
    }
    println!("{name}: ran to t = {}", w.time());
    Ok(())
}

fn cube(half: f64, density: f64, at: Vector3<f64>) -> RigidBodyBuilder {
    RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(half)).unwrap(), density).position(at)
}

#[test]
fn stiff_springs_with_every_method() {
    for k in [1e4, 1e6, 1e8, 1e10] {
        for method in Method::ALL {
            let mut w = World::new();
            let settings = if method.has_error_estimate() && method != Method::Am4 {
                Settings::tolerances(method, 1e-6, 1e-9)
            } else if method == Method::EulerVariable {
                Settings::euler_variable(1e-6)
            } else {
                Settings::fixed(method, 1e-3)
            };
            w.set_integrator(settings.max_steps(200_000)).unwrap();
            let p = w.add_particle(ParticleBuilder::new(1.0).position(Vector3::new(0.0, 0.0, -0.1))).unwrap();
            w.add_spring(
                SpringBuilder::new(Attachment::Particle(p), Attachment::Point(Vector3::zeros()))
                    .stiffness(k)
                    .damping(1.0)
                    .rest_length(0.0),
            )
            .unwrap();
            let _ = outcome(&format!("k = {k:e}, {}", method.name()), &mut w, 0.05, 0.05);
        }
    }
}

#[test]
fn mass_ratios_to_a_million_in_both_modes() {
    for ratio in [1e3, 1e6] {
        for (below, above) in [(1.0, ratio), (ratio, 1.0)] {
            for fast in [false, true] {
                let mut w = World::new();
                if fast {
                    w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
                }
                w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
                w.add_body(cube(0.5, below, Vector3::new(0.0, 0.0, 0.5))).unwrap();
                w.add_body(cube(0.5, above, Vector3::new(0.0, 0.0, 1.5))).unwrap();
                let name = format!("density {below:e} under {above:e}, {}", if fast { "fast" } else { "accurate" });
                let _ = outcome(&name, &mut w, 0.05, 0.025);
            }
        }
    }
}

#[test]
fn speeds_to_1e4_m_per_s_and_fast_spins() {
    for fast in [false, true] {
        for speed in [1e2, 1e4] {
            let mut w = World::new();
            if fast {
                w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
            }
            w.add_body(RigidBodyBuilder::fixed(Some(Shape::cuboid(Vector3::new(0.005, 1.0, 1.0)).unwrap()))).unwrap();
            w.add_body(
                RigidBodyBuilder::from_shape(Shape::sphere(0.05).unwrap(), 1000.0)
                    .position(Vector3::new(-1.0, 0.0, 0.0))
                    .velocity(Vector3::new(speed, 0.0, 0.0)),
            )
            .unwrap();
            w.set_gravity(Vector3::zeros()).unwrap();
            let name = format!("sphere at {speed:e} m/s into a 1 cm wall, {}", if fast { "fast" } else { "accurate" });
            if outcome(&name, &mut w, 0.05, 0.05).is_ok() {
                let x = w.bodies().nth(1).unwrap().1.position().x;
                assert!(x < 0.0, "{name}: passed through the wall to x = {x}");
            }
        }
        let mut w = World::new();
        if fast {
            w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
        }
        w.add_ground(0.0, Material::default()).unwrap();
        w.add_body(cube(0.2, 500.0, Vector3::new(0.0, 0.0, 0.5)).angular_velocity(Vector3::new(1e4, 3e3, -2e3)))
            .unwrap();
        let _ = outcome(&format!("box spinning at 1e4 rad/s, fast = {fast}"), &mut w, 0.1, 0.05);
    }
}

#[test]
fn steps_from_a_nanosecond_to_a_second_in_fast_mode() {
    for dt in [1e-9, 1e-6, 1e-3, 1.0 / 30.0, 0.1, 1.0] {
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings::new(dt))).unwrap();
        w.add_ground(0.0, Material::default()).unwrap();
        w.add_body(cube(0.25, 500.0, Vector3::new(0.0, 0.0, 0.3))).unwrap();
        w.add_body(
            cube(0.25, 500.0, Vector3::new(0.1, 0.0, 0.9))
                .orientation(UnitQuaternion::from_euler_angles(0.3, 0.2, 0.1)),
        )
        .unwrap();
        let span = (1000.0 * dt).min(2.0);
        let _ = outcome(&format!("fast dt = {dt:e}"), &mut w, span, span);
    }
}

#[test]
fn bodies_from_a_millimetre_to_a_kilometre_and_overlapping_starts() {
    for fast in [false, true] {
        let mode = if fast { "fast" } else { "accurate" };
        for size in [1e-3, 1.0, 1e3] {
            let mut w = World::new();
            if fast {
                w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
            }
            w.add_ground(0.0, Material::new(0.5, 0.5)).unwrap();
            w.add_body(RigidBodyBuilder::from_shape(Shape::sphere(size).unwrap(), 1000.0).position(Vector3::new(
                0.0,
                0.0,
                3.0 * size,
            )))
            .unwrap();
            w.add_body(cube(size, 1000.0, Vector3::new(3.0 * size, 0.0, 2.0 * size))).unwrap();
            let _ = outcome(&format!("{size} m bodies, {mode}"), &mut w, 0.2, 0.1);
        }
        // a 1 mm box on a 1 km box
        let mut w = World::new();
        if fast {
            w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
        }
        w.add_ground(0.0, Material::default()).unwrap();
        w.add_body(cube(500.0, 1000.0, Vector3::new(0.0, 0.0, 500.0))).unwrap();
        w.add_body(cube(5e-4, 1000.0, Vector3::new(0.0, 0.0, 1000.001))).unwrap();
        let _ = outcome(&format!("1 mm box on a 1 km box, {mode}"), &mut w, 0.05, 0.025);
        // two boxes starting half inside each other
        let mut w = World::new();
        if fast {
            w.set_mode(Mode::fast(1.0 / 240.0)).unwrap();
        }
        w.add_ground(0.0, Material::default()).unwrap();
        w.add_body(cube(0.5, 1000.0, Vector3::new(0.0, 0.0, 0.5))).unwrap();
        w.add_body(cube(0.5, 1000.0, Vector3::new(0.2, 0.0, 1.0))).unwrap();
        let _ = outcome(&format!("overlapping boxes, {mode}"), &mut w, 0.1, 0.05);
    }
}

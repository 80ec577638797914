//! `World::contacts` (issue 15): the contacts of the last step with the world's handles, their normals, gaps and
//! impulses, checked against statics (a resting stack's contacts carry the weight above them).

use nalgebra::Vector3;
use tumble::{FastSettings, FastSolver, Material, Mode, RigidBodyBuilder, Shape, Target, World};

const G: f64 = 9.81;

/// A stack of two boxes on the ground (masses 2 and 0.5 kg), in the given mode.
fn stack(mode: Option<Mode>) -> (World, [tumble::BodyHandle; 3]) {
    let mut w = World::new();
    if let Some(mode) = mode {
        w.set_mode(mode).unwrap();
    }
    let ground = w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let cube = |half: f64, mass: f64, z: f64| {
        let density = mass / (8.0 * half * half * half);
        RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(half)).unwrap(), density)
            .position(Vector3::new(0.0, 0.0, z))
            .restitution(0.0)
            .friction(0.5)
    };
    let low = w.add_body(cube(0.1, 2.0, 0.1)).unwrap();
    let high = w.add_body(cube(0.05, 0.5, 0.25)).unwrap();
    (w, [ground, low, high])
}

/// The upward force each pair carries: the sum over its contacts of the force on the upper body.
fn carried(w: &World, lower: Target, upper: Target) -> f64 {
    w.contacts()
        .iter()
        .map(|c| {
            assert!((c.normal.z.abs() - 1.0).abs() < 1e-9, "a resting face contact's normal is vertical");
            if (c.a, c.b) == (lower, upper) {
                c.force * c.normal.z
            } else if (c.a, c.b) == (upper, lower) {
                -c.force * c.normal.z
            } else {
                0.0
            }
        })
        .sum()
}

#[test]
fn a_resting_stack_carries_the_weight_above_each_contact() {
    let fast = |solver| Some(Mode::Fast(FastSettings { solver, sleep: false, ..FastSettings::new(1.0 / 240.0) }));
    // At rest a step's impulses on each body cancel gravity's over the step, to the solver's residual and rounding:
    // measured within 2.5e-13 relative in all three modes (accurate mode's contact steps, fast mode's soft step
    // and its exact cone program); bound 1e-9.
    let tol = 1e-9;
    let modes =
        [("accurate", None), ("fast soft", fast(FastSolver::default())), ("fast exact", fast(FastSolver::exact()))];
    for (name, mode) in modes {
        let (mut w, [ground, low, high]) = stack(mode);
        assert!(w.contacts().is_empty(), "no contacts before the first step");
        w.step(1.0).unwrap();
        let (g, l, h) = (Target::Body(ground), Target::Body(low), Target::Body(high));
        let on_ground = carried(&w, g, l);
        let on_low = carried(&w, l, h);
        assert!((on_ground - 2.5 * G).abs() < tol * 2.5 * G, "{name}: the ground carries {on_ground} N");
        assert!((on_low - 0.5 * G).abs() < tol * 0.5 * G, "{name}: the lower box carries {on_low} N");
        assert!(w.contacts().iter().all(|c| c.gap.abs() < 1e-3 && c.impulse >= 0.0));
        assert_eq!(w.contacts().len(), 8, "{name}: four corners a face");
        let b = w.body(high).unwrap().position();
        w.set_body_state(high, b, Default::default(), Vector3::zeros(), Vector3::zeros()).unwrap();
        assert!(w.contacts().is_empty(), "a state set since the last step has no contacts yet");
    }
}

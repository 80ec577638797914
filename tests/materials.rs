//! A surface changed between steps (`World::set_material`) acts from the next step on, in both modes: a box sliding
//! frictionless keeps its speed, and once given friction decelerates at Coulomb's mu g (mu the geometric mean of
//! the two surfaces' frictions); copies and files keep the new material; bad values are refused by name and change
//! nothing.

use nalgebra::Vector3;
use tumble::{FastSettings, Material, Mode, RigidBodyBuilder, Shape, Target, World, WorldError};

const G: f64 = 9.81;

/// A 0.2 m cube resting on a ground of friction 1, sliding along x at 2 m/s, frictionless itself.
fn sliding(mode: Mode) -> (World, tumble::BodyHandle, tumble::BodyHandle) {
    let mut w = World::new();
    w.set_mode(mode).unwrap();
    let ground = w.add_ground(0.0, Material { restitution: 0.0, friction: 1.0 }).unwrap();
    let cube = RigidBodyBuilder::from_shape(Shape::cuboid(Vector3::repeat(0.1)).unwrap(), 500.0)
        .position(Vector3::new(0.0, 0.0, 0.1))
        .velocity(Vector3::new(2.0, 0.0, 0.0))
        .restitution(0.0)
        .friction(0.0);
    let b = w.add_body(cube).unwrap();
    (w, ground, b)
}

fn speed(w: &World, b: tumble::BodyHandle) -> f64 {
    w.body(b).unwrap().velocity().x
}

/// Both modes: (mode, tolerance on the speed with its reason).
fn modes() -> [(Mode, f64, &'static str); 2] {
    [
        // accurate mode holds Coulomb's law to its contact tolerance (1e-6 of the scene's size): 1e-5 m/s is ample
        (Mode::default(), 1e-5, "accurate"),
        // fast mode's soft contacts slide a little slow or fast while the friction row converges: 2% of the change
        (Mode::Fast(FastSettings::new(1.0 / 240.0)), 0.02 * 0.5 * G * 0.25, "fast"),
    ]
}

#[test]
fn friction_given_between_steps_decelerates_the_sliding_box_at_mu_g() {
    for (mode, tol, name) in modes() {
        let (mut w, _, b) = sliding(mode);
        w.step(0.25).unwrap();
        let v0 = speed(&w, b);
        assert!((v0 - 2.0).abs() < tol, "{name}: frictionless sliding keeps its speed, got {v0}");
        // mu = sqrt(0.25 * 1) = 0.5 between the box and the ground
        w.set_material(Target::Body(b), Some(0.25), None).unwrap();
        assert_eq!(w.body(b).unwrap().material(), Material { restitution: 0.0, friction: 0.25 });
        w.step(0.25).unwrap();
        let v1 = speed(&w, b);
        let expected = v0 - 0.5 * G * 0.25;
        assert!((v1 - expected).abs() < tol, "{name}: {v1} m/s after the change, Coulomb gives {expected}");
    }
}

#[test]
fn copies_and_files_keep_the_new_material() {
    for (mode, _, name) in modes() {
        let (mut w, ground, b) = sliding(mode);
        w.step(0.1).unwrap();
        w.set_material(Target::Body(ground), None, Some(0.3)).unwrap();
        w.set_material(Target::Body(b), Some(0.7), Some(0.2)).unwrap();
        let want =
            [(ground, Material { restitution: 0.3, friction: 1.0 }), (b, Material { restitution: 0.2, friction: 0.7 })];
        let copy = w.clone();
        let json = World::from_json(&w.to_json().unwrap()).unwrap();
        let binary = World::from_bytes(&w.to_bytes().unwrap()).unwrap();
        for (h, m) in want {
            assert_eq!(copy.body(h).unwrap().material(), m, "{name}: the copy");
            let row = w.body_row(h).unwrap();
            for (file, loaded) in [("JSON", &json), ("binary", &binary)] {
                let (_, body) = loaded.bodies().nth(row).unwrap();
                assert_eq!(body.material(), m, "{name}: the {file} file");
            }
        }
        // and the copy goes on as the original does, to the bit
        let mut copy = copy;
        w.step(0.1).unwrap();
        copy.step(0.1).unwrap();
        assert_eq!(w.body(b).unwrap().position(), copy.body(b).unwrap().position(), "{name}");
    }
}

#[test]
fn a_bad_material_is_refused_by_name_and_changes_nothing() {
    let (mut w, _, b) = sliding(Mode::default());
    w.step(0.05).unwrap();
    let before = w.body(b).unwrap().material();
    let named = |e: WorldError| e.argument().unwrap_or_default();
    assert_eq!(named(w.set_material(Target::Body(b), Some(-1.0), Some(0.5)).unwrap_err()), "friction");
    assert_eq!(named(w.set_material(Target::Body(b), Some(0.5), Some(1.5)).unwrap_err()), "restitution");
    assert_eq!(named(w.set_material(Target::Body(b), Some(f64::NAN), None).unwrap_err()), "friction");
    assert_eq!(w.body(b).unwrap().material(), before);
    let mut other = World::new();
    let stranger = other.add_body(RigidBodyBuilder::fixed(None)).unwrap();
    assert_eq!(named(w.set_material(Target::Body(stranger), Some(0.1), None).unwrap_err()), "target");
}

//! A surface changed between steps (`World::set_material`) acts from the next step on, in both modes: a box sliding
//! frictionless keeps its speed, and once given friction decelerates at Coulomb's mu g (mu the geometric mean of
//! the two surfaces' frictions); copies and files keep the new material; bad values are refused by name and change
//! nothing.
// (accurate mode here lifts sunk contacts apart by the position projection, or uses the chapter's QPs: clarabel's)
#![cfg(feature = "clarabel")]

use nalgebra::Vector3;
use tumble::{
    Combine, CombineRules, FastSettings, Material, MaterialChange, Mode, RigidBodyBuilder, Shape, Target, World,
    WorldError,
};

/// A change of friction and restitution.
fn change(friction: Option<f64>, restitution: Option<f64>) -> MaterialChange {
    MaterialChange { friction, restitution, ..Default::default() }
}

const G: f64 = 9.81;

/// A 0.2 m cube resting on a ground of friction 1, sliding along x at 2 m/s, frictionless itself.
fn sliding(mode: Mode) -> (World, tumble::BodyHandle, tumble::BodyHandle) {
    let mut w = World::new();
    w.set_mode(mode).unwrap();
    let ground = w.add_ground(0.0, Material::new(0.0, 1.0)).unwrap();
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
        w.set_material(Target::Body(b), change(Some(0.25), None)).unwrap();
        assert_eq!(w.body(b).unwrap().material(), Material::new(0.0, 0.25));
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
        w.set_material(Target::Body(ground), change(None, Some(0.3))).unwrap();
        let more = MaterialChange {
            rolling_resistance: Some(0.05),
            torsional_resistance: Some(0.01),
            friction_combine: Some(Some(Combine::Product)),
            restitution_combine: Some(Some(Combine::Min)),
            ..change(Some(0.7), Some(0.2))
        };
        w.set_material(Target::Body(b), more).unwrap();
        w.set_combine_rules(CombineRules { friction: Combine::Average, restitution: Combine::Product });
        let mut own = Material::new(0.2, 0.7);
        (own.rolling_resistance, own.torsional_resistance) = (0.05, 0.01);
        (own.friction_combine, own.restitution_combine) = (Some(Combine::Product), Some(Combine::Min));
        let want = [(ground, Material::new(0.3, 1.0)), (b, own)];
        let copy = w.clone();
        let json = World::from_json(&w.to_json().unwrap()).unwrap();
        let binary = World::from_bytes(&w.to_bytes().unwrap()).unwrap();
        for (h, m) in want {
            assert_eq!(copy.body(h).unwrap().material(), m, "{name}: the copy");
            let row = w.body_row(h).unwrap();
            for (file, loaded) in [("JSON", &json), ("binary", &binary)] {
                let (_, body) = loaded.bodies().nth(row).unwrap();
                assert_eq!(body.material(), m, "{name}: the {file} file");
                assert_eq!(loaded.combine_rules(), w.combine_rules(), "{name}: the {file} file's rules");
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
    assert_eq!(named(w.set_material(Target::Body(b), change(Some(-1.0), Some(0.5))).unwrap_err()), "friction");
    assert_eq!(named(w.set_material(Target::Body(b), change(Some(0.5), Some(1.5))).unwrap_err()), "restitution");
    assert_eq!(named(w.set_material(Target::Body(b), change(Some(f64::NAN), None)).unwrap_err()), "friction");
    assert_eq!(w.body(b).unwrap().material(), before);
    let mut other = World::new();
    let stranger = other.add_body(RigidBodyBuilder::fixed(None)).unwrap();
    assert_eq!(named(w.set_material(Target::Body(stranger), change(Some(0.1), None)).unwrap_err()), "target");
}

#[test]
fn a_bad_resistance_or_rule_is_refused_by_name() {
    let (mut w, _, b) = sliding(Mode::default());
    let named = |e: WorldError| e.argument().unwrap_or_default();
    let rolling = MaterialChange { rolling_resistance: Some(-0.1), ..Default::default() };
    assert_eq!(named(w.set_material(Target::Body(b), rolling).unwrap_err()), "rolling_resistance");
    let torsion = MaterialChange { torsional_resistance: Some(f64::INFINITY), ..Default::default() };
    assert_eq!(named(w.set_material(Target::Body(b), torsion).unwrap_err()), "torsional_resistance");
    assert_eq!(named(Combine::parse("friction_combine", "mean").unwrap_err()), "friction_combine");
    // the chapter's resting forces have no rows for resistance: asking for both is refused, whichever comes first
    let resting = Mode::Accurate(tumble::AccurateSettings {
        persistent: tumble::Persistent::RestingForces,
        ..Default::default()
    });
    let turning = MaterialChange { rolling_resistance: Some(0.1), ..Default::default() };
    w.set_material(Target::Body(b), turning).unwrap();
    assert_eq!(named(w.set_mode(resting).unwrap_err()), "mode");
    let mut other = World::new();
    other.set_mode(resting).unwrap();
    let ball = RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0).rolling_resistance(0.1);
    assert_eq!(named(other.add_body(ball).unwrap_err()), "rolling_resistance");
}

/// A ball of restitution `e_ball` dropped from 1 m onto a ground of restitution `e_ground` in accurate mode: the
/// speed it leaves the first bounce with, as a fraction of the speed it arrives with.
fn bounce(rules: CombineRules, ball: Material, e_ground: f64) -> f64 {
    let mut w = World::new();
    w.set_combine_rules(rules);
    w.add_ground(0.0, Material::new(e_ground, 0.0)).unwrap();
    let b = RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0)
        .position(Vector3::new(0.0, 0.0, 1.1))
        .material(ball);
    let h = w.add_body(b).unwrap();
    // the impact at sqrt(2 / g) = 0.4515 s; 0.5 s is after it and before any apex
    w.step(0.5).unwrap();
    let v = w.body(h).unwrap().velocity().z;
    let arrive = (2.0 * G * 1.0f64).sqrt();
    (v + G * (0.5 - (2.0 / G).sqrt())) / arrive
}

#[test]
fn combine_rules_per_world_and_per_body_set_a_pairs_coefficients() {
    let default = CombineRules::default();
    let product = CombineRules { friction: Combine::Product, restitution: Combine::Product };
    let own = |e: f64, rule: Option<Combine>| Material { restitution_combine: rule, ..Material::new(e, 0.0) };
    // accurate mode locates the impact and applies Newton's law exactly: the rebound to 1e-9 of its speed
    let cases = [
        ("the default, the larger", default, own(0.5, None), 0.8, 0.8),
        ("the world's product", product, own(0.5, None), 0.8, 0.4),
        ("the body's product over the world's max", default, own(0.5, Some(Combine::Product)), 0.8, 0.4),
        (
            "min over the world's average",
            CombineRules { restitution: Combine::Average, ..default },
            own(0.5, Some(Combine::Min)),
            0.8,
            0.5,
        ),
        ("the body's average over the world's max", default, own(0.5, Some(Combine::Average)), 0.8, 0.65),
        (
            "geometric mean",
            CombineRules { restitution: Combine::GeometricMean, ..default },
            own(0.5, None),
            0.8,
            0.4f64.sqrt(),
        ),
    ];
    for (name, rules, ball, ground, want) in cases {
        let e = bounce(rules, ball, ground);
        assert!((e - want).abs() < 1e-9, "{name}: rebound {e}, want {want}");
    }
    // friction by the product: a box at 2 m/s on friction 1 with its own 0.5 slows at 0.5 g (geometric mean: 0.71 g)
    for (mode, tol, name) in modes() {
        let (mut w, _, b) = sliding(mode);
        w.set_combine_rules(CombineRules { friction: Combine::Product, ..default });
        w.set_material(Target::Body(b), change(Some(0.5), None)).unwrap();
        w.step(0.25).unwrap();
        let expected = 2.0 - 0.5 * G * 0.25;
        assert!((speed(&w, b) - expected).abs() < tol, "{name}: {} m/s, the product gives {expected}", speed(&w, b));
    }
}

//! Bodies' names and colours: kept by copies, by both file formats and by the hand-editable scene, refused by name
//! when bad (the world left as it was), and no part of the physics (a world with them steps to the same bits).

use crate::common;

use common::{random_drop, state_bits};
use tumble::{FastSettings, Look, Mode, RigidBodyBuilder, Shape, World, WorldError};

/// The same seeded drop (every shape kind) with a name and a colour on every other body.
fn named(seed: u64) -> World {
    let plain = random_drop(seed);
    let text = plain.to_json_scene().unwrap();
    let mut scene: serde_json::Value = serde_json::from_str(&text).unwrap();
    for (k, body) in scene["bodies"].as_array_mut().unwrap().iter_mut().enumerate() {
        if k % 2 == 0 {
            body["name"] = format!("part {k} — ünïcode/ok").into();
            body["color"] = serde_json::json!([0.1 * (k % 10) as f64, 0.5, 1.0, 0.75]);
        }
    }
    World::from_json(&scene.to_string()).unwrap()
}

fn looks(w: &World) -> Vec<(Option<String>, Option<[f64; 4]>)> {
    w.bodies().map(|(_, b)| (b.name().map(str::to_owned), b.color())).collect()
}

#[test]
fn names_and_colours_travel_with_copies_and_files() {
    for seed in 0..4 {
        let w = named(seed);
        let given = looks(&w);
        assert!(given.iter().any(|(n, c)| n.is_some() && c.is_some()), "seed {seed}: some bodies have looks");
        assert!(given.iter().skip(1).step_by(2).all(|(n, c)| n.is_none() && c.is_none()), "the others none");
        let copies = [
            ("clone", w.clone()),
            ("json", World::from_json(&w.to_json().unwrap()).unwrap()),
            ("binary", World::from_bytes(&w.to_bytes().unwrap()).unwrap()),
            ("scene", World::from_json(&w.to_json_scene().unwrap()).unwrap()),
        ];
        for (how, copy) in copies {
            assert_eq!(looks(&copy), given, "seed {seed}: {how}");
        }
    }
}

#[test]
fn names_and_colours_are_no_part_of_the_physics() {
    for (seed, fast) in [(1, false), (2, true)] {
        let mut plain = random_drop(seed);
        let mut with = named(seed);
        if fast {
            for w in [&mut plain, &mut with] {
                w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
            }
        }
        plain.step(0.5).unwrap();
        with.step(0.5).unwrap();
        assert_eq!(state_bits(&plain), state_bits(&with), "seed {seed}, fast {fast}");
    }
}

fn argument(e: WorldError) -> &'static str {
    e.argument().unwrap_or_else(|| panic!("expected a named argument error, got {e:?}"))
}

#[test]
fn bad_names_and_colours_are_refused_by_name() {
    let mut w = World::new();
    let ball = || RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0);
    let long = "x".repeat(tumble::MAX_NAME + 1);
    for bad in ["", "a\nb", "tab\there", long.as_str()] {
        assert_eq!(argument(w.add_body(ball().name(bad)).unwrap_err()), "name", "{bad:?}");
    }
    for bad in [[1.5, 0.0, 0.0, 1.0], [0.0, -0.1, 0.0, 1.0], [0.0, 0.0, f64::NAN, 1.0], [0.0, 0.0, 0.0, 2.0]] {
        assert_eq!(argument(w.add_body(ball().color(bad)).unwrap_err()), "color", "{bad:?}");
    }
    assert_eq!(w.body_count(), 0, "nothing was added");
    // the longest name and the corners of the colour cube are taken
    w.add_body(ball().name("y".repeat(tumble::MAX_NAME)).color([0.0, 1.0, 0.0, 1.0])).unwrap();
    // RGB is opaque RGBA; other lengths are refused
    assert_eq!(Look::color_of(&[0.2, 0.4, 0.6]).unwrap(), [0.2, 0.4, 0.6, 1.0]);
    assert_eq!(Look::color_of(&[0.2, 0.4, 0.6, 0.5]).unwrap(), [0.2, 0.4, 0.6, 0.5]);
    for bad in [&[0.1, 0.2][..], &[0.1; 5][..]] {
        assert_eq!(argument(Look::color_of(bad).unwrap_err()), "color");
    }
    // a file with a bad colour names the body's row
    let head = r#""format": "tumble-scene", "version": 1"#;
    let text = format!(
        r#"{{{head}, "bodies": [{{"colliders": [{{"shape": {{"sphere": {{"radius": 0.1}}}}}}], "density": 1.0,
            "color": [0.5, 0.5, 3.0, 1.0]}}]}}"#
    );
    let e = World::from_json(&text).err().expect("a bad colour is refused");
    assert!(e.to_string().contains("bodies[0].color"), "{e}");
}

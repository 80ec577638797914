//! The formats a world is saved in: a readable scene file (JSON, `file.rs`) that a person can write by hand, and a
//! versioned binary format (an 8-byte magic, the version, the same scene in postcard, then the engine's memory).
//! Both hold every object with its state to the bit, the settings and the start `reset` returns to, and both hold
//! the engine's memory (fast mode's warm starts, kept manifolds and sleep; accurate mode's integration, resting
//! contacts and touching phase: in JSON as base64 of its binary form), so that a loaded world continues bit for
//! bit as the original. A scene saved without the memory (hand-editable) starts its engine afresh from the saved
//! state, as a world built by hand and set to it would. A file of another version, a truncated file or a bad
//! value is a clear error naming the field, and no world is half-built. `World::save`, `load`, `to_json` and the
//! others (`world/files.rs`) call these.

mod file;
mod load;
mod save;

use crate::engine::EngineMemory;
use crate::error::WorldError;
use crate::world::World;
use base64::Engine as _;
use file::SceneFile;

/// The first bytes of a binary world.
const MAGIC: &[u8; 8] = b"TUMBLEW\0";

/// The engine part of a file.
#[derive(serde::Serialize, serde::Deserialize)]
struct SavedEngine {
    /// The world's state was set after the engine last ran (the scene holds it, the memory the engine's).
    edited: bool,
    /// The engine's divergence limit, set from the state's scale where it was built.
    divergence_limit: f64,
    memory: EngineMemory,
}

/// The binary format's version (the scene inside it has the scene file's own, `VERSION`).
const BINARY_VERSION: u32 = 9;

fn decode_error(format: &str, e: impl std::fmt::Display) -> WorldError {
    WorldError::invalid("file", format!("not a readable {format} scene: {e}"))
}

fn encode_error(e: impl std::fmt::Display) -> WorldError {
    WorldError::invalid("file", e.to_string())
}

/// The world as JSON, with the engine's memory (base64 of its binary form) if `memory`.
pub(crate) fn to_json(world: &World, memory: bool) -> Result<String, WorldError> {
    let mut scene = save::scene_file(world)?;
    if memory {
        if let Some(saved) = saved_memory(world) {
            let bytes = postcard::to_stdvec(&saved).map_err(encode_error)?;
            scene.memory = Some(base64::engine::general_purpose::STANDARD.encode(bytes));
        }
    }
    serde_json::to_string_pretty(&scene).map_err(encode_error)
}

/// A world from JSON (written by `to_json` or by hand), given the memory the file holds.
pub(crate) fn from_json(text: &str) -> Result<World, WorldError> {
    let scene: SceneFile = serde_json::from_str(text).map_err(|e| decode_error("JSON", e))?;
    let memory = match &scene.memory {
        None => None,
        Some(text) => {
            let bytes = base64::engine::general_purpose::STANDARD
                .decode(text)
                .map_err(|e| WorldError::invalid("memory", format!("the file's engine memory is not base64: {e}")))?;
            let saved: SavedEngine = postcard::from_bytes(&bytes)
                .map_err(|e| WorldError::invalid("memory", format!("the file's engine memory is not readable: {e}")))?;
            Some(saved)
        }
    };
    let mut world = load::world_from(&scene)?;
    restore_memory(&mut world, memory)?;
    Ok(world)
}

/// The world in the binary format: `TUMBLEW\0`, the version (4 bytes, little-endian), the scene, the engine's
/// memory (if `memory` and the world has an engine: it has stepped since its structure or settings last changed).
pub(crate) fn to_bytes(world: &World, memory: bool) -> Result<Vec<u8>, WorldError> {
    let scene = save::scene_file(world)?;
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&BINARY_VERSION.to_le_bytes());
    let out = postcard::to_extend(&scene, out).map_err(encode_error)?;
    let saved = if memory { saved_memory(world) } else { None };
    postcard::to_extend(&saved, out).map_err(encode_error)
}

/// A world from `to_bytes`. A truncated file, another version or a bad value is an error naming it.
pub(crate) fn from_bytes(bytes: &[u8]) -> Result<World, WorldError> {
    if bytes.len() < 12 || &bytes[..8] != MAGIC {
        return Err(WorldError::invalid("file", "not a tumble world (it does not start with TUMBLEW)"));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().expect("four bytes"));
    if version != BINARY_VERSION {
        return Err(WorldError::invalid(
            "version",
            format!(
                "this tumble reads version {BINARY_VERSION} of the binary world format, the file is version {version}"
            ),
        ));
    }
    let (scene, rest): (SceneFile, &[u8]) =
        postcard::take_from_bytes(&bytes[12..]).map_err(|e| decode_error("binary", e))?;
    let (memory, rest) = postcard::take_from_bytes(rest).map_err(|e| decode_error("binary", e))?;
    if !rest.is_empty() {
        return Err(decode_error("binary", format!("{} bytes left over after the scene", rest.len())));
    }
    if scene.memory.is_some() {
        return Err(decode_error("binary", "its scene holds a memory of its own"));
    }
    let mut world = load::world_from(&scene)?;
    restore_memory(&mut world, memory)?;
    Ok(world)
}

/// The engine's memory, and whether the world's state was set since the engine last ran (the next step then gives
/// the engine that state, keeping its contact memory, as the original's would).
fn saved_memory(world: &World) -> Option<SavedEngine> {
    world.engine.as_ref().map(|e| SavedEngine {
        edited: world.state_changed,
        divergence_limit: e.divergence_limit(),
        memory: e.memory(),
    })
}

/// Gives the world the memory read with its scene, checked against it first; on an error no world is made.
fn restore_memory(world: &mut World, saved: Option<SavedEngine>) -> Result<(), WorldError> {
    let Some(SavedEngine { edited, divergence_limit, memory }) = saved else { return Ok(()) };
    let refused = |why: String| WorldError::invalid("memory", format!("the file's engine memory: {why}"));
    if !(divergence_limit > 0.0 && divergence_limit.is_finite()) {
        return Err(refused(format!("its divergence limit {divergence_limit} is not positive and finite")));
    }
    let engine = world.engine()?;
    engine.set_divergence_limit(divergence_limit);
    engine.set_memory(memory).map_err(refused)?;
    if edited {
        // the scene holds the state set since; the engine applies it at the next step
        world.state_changed = true;
        return Ok(());
    }
    // The scene holds the world's arrays as they were, the memory the engine's state: the same state (the arrays are
    // the engine's state unpacked, or were set and packed into it, quaternions normalized on the way), to the
    // rounding; a memory of another time or another motion is refused.
    let engine = world.engine.as_ref().expect("built above");
    let packed = engine.handles().pack(&world.particles, &world.bodies);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
    let same = engine.state().len() == packed.len()
        && engine.state().iter().zip(&packed).all(|(a, b)| close(*a, *b))
        && close(engine.time(), world.time);
    if !same {
        return Err(refused("its state is not the scene's".into()));
    }
    Ok(())
}

/// A shape as the scene file writes it (JSON), e.g. `{"sphere":{"radius":0.1}}`.
pub fn shape_to_json(shape: &tumble_collide::Shape) -> String {
    serde_json::to_string(&save::shape_file(shape)).expect("a shape always writes")
}

/// A shape from `shape_to_json`'s text (or written by hand).
pub fn shape_from_json(text: &str) -> Result<tumble_collide::Shape, WorldError> {
    let file: file::ShapeFile = serde_json::from_str(text).map_err(|e| decode_error("JSON shape", e))?;
    load::shape(&file)
}

/// Whether a path names a JSON file (by its extension).
pub(crate) fn is_json(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

#[cfg(test)]
mod tests {
    use crate::{FastSettings, Material, Mode, RigidBodyBuilder, Shape, World, WorldError};
    use nalgebra::Vector3;

    /// `count` boxes on a ground, in fast mode or accurate, stepped `steps` times.
    fn boxes(steps: usize, count: usize, fast: bool) -> World {
        let mut w = World::new();
        if fast {
            w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
        }
        w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
        for k in 0..count {
            let shape = Shape::cuboid(Vector3::repeat(0.1)).unwrap();
            w.add_body(RigidBodyBuilder::from_shape(shape, 500.0).position(Vector3::new(
                0.0,
                0.0,
                0.1 + 0.25 * k as f64,
            )))
            .unwrap();
        }
        for _ in 0..steps {
            w.step(1.0 / 240.0).unwrap();
        }
        w
    }

    /// A file with one world's scene and another's memory.
    fn spliced(scene_of: &World, memory_of: &World) -> Vec<u8> {
        let mut out = super::MAGIC.to_vec();
        out.extend_from_slice(&super::BINARY_VERSION.to_le_bytes());
        let out = postcard::to_extend(&super::save::scene_file(scene_of).unwrap(), out).unwrap();
        postcard::to_extend(&super::saved_memory(memory_of), out).unwrap()
    }

    #[test]
    fn a_memory_that_does_not_fit_its_scene_is_refused() {
        for fast in [true, false] {
            // accurate mode: 60 steps, so that the boxes touch and the touching phase is part of the memory
            let steps = if fast { 30 } else { 60 };
            let (a, later, bigger) = (boxes(steps, 2, fast), boxes(steps + 1, 2, fast), boxes(steps, 3, fast));
            let other_mode = boxes(steps, 2, !fast);
            assert!(World::from_bytes(&spliced(&a, &a)).is_ok());
            for (what, bytes) in [
                ("another state", spliced(&a, &later)),
                ("another structure", spliced(&a, &bigger)),
                ("another mode", spliced(&a, &other_mode)),
            ] {
                match World::from_bytes(&bytes) {
                    Err(WorldError::InvalidArgument { name: "memory", reason }) => {
                        assert!(reason.contains("engine memory"), "{reason}")
                    }
                    other => panic!("fast {fast}, {what}: expected the memory refused, got {:?}", other.map(|_| ())),
                }
            }
        }
    }
}

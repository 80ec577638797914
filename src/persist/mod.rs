//! Saving and loading worlds: a readable scene file (JSON, `file.rs`) that a person can write by hand, and a
//! versioned binary format (an 8-byte magic, the version, the same scene in postcard, then the engine's memory).
//! Both hold every object with its state to the bit, the settings and the start `reset` returns to. The binary
//! format also holds fast mode's memory (warm starts, kept manifolds, sleep), so that a loaded fast world continues
//! bit for bit as the original; a world loaded from JSON, or in accurate mode (whose integrator memory holds
//! factorizations), starts its engine afresh from the saved state, as a world built by hand and set to it would. A
//! file of another version, a truncated file or a bad value is a clear error naming the field, and no world is
//! half-built.

mod file;
mod load;
mod save;

use file::VERSION;

use crate::error::WorldError;
use crate::world::World;
use file::SceneFile;

/// The first bytes of a binary world.
const MAGIC: &[u8; 8] = b"TUMBLEW\0";

fn decode_error(format: &str, e: impl std::fmt::Display) -> WorldError {
    WorldError::invalid("file", format!("not a readable {format} scene: {e}"))
}

impl World {
    /// The world as a readable scene (JSON). A world with force callbacks cannot be saved: the error names `loads`.
    pub fn to_json(&self) -> Result<String, WorldError> {
        let scene = self.scene_file()?;
        serde_json::to_string_pretty(&scene).map_err(|e| WorldError::invalid("file", e.to_string()))
    }

    /// A world from a scene written by `to_json` or by hand. Bad JSON, an unknown field, a wrong format or version
    /// or a bad value is an error naming it.
    pub fn from_json(text: &str) -> Result<World, WorldError> {
        let scene: SceneFile = serde_json::from_str(text).map_err(|e| decode_error("JSON", e))?;
        World::from_scene_file(&scene)
    }

    /// The world in the binary format: `TUMBLEW\0`, the version (4 bytes, little-endian), the scene, fast mode's
    /// memory (if any).
    pub fn to_bytes(&self) -> Result<Vec<u8>, WorldError> {
        let scene = self.scene_file()?;
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&VERSION.to_le_bytes());
        let fail = |e: postcard::Error| WorldError::invalid("file", e.to_string());
        let out = postcard::to_extend(&scene, out).map_err(fail)?;
        postcard::to_extend(&self.saved_memory(), out).map_err(fail)
    }

    /// Fast mode's memory, when the world's state is its engine's.
    #[cfg(feature = "contact")]
    fn saved_memory(&self) -> Option<crate::engine::fast::FastSnapshot> {
        self.engine.as_ref().filter(|_| !self.state_changed).and_then(|e| e.fast_memory())
    }

    #[cfg(not(feature = "contact"))]
    fn saved_memory(&self) -> Option<()> {
        None
    }

    /// Gives the world the memory read with its scene, checked against it first.
    #[cfg(feature = "contact")]
    fn restore_memory(&mut self, memory: Option<crate::engine::fast::FastSnapshot>) -> Result<(), WorldError> {
        let Some(memory) = memory else { return Ok(()) };
        let before = self.state();
        let refused = |why: String| WorldError::invalid("memory", format!("the file's engine memory: {why}"));
        self.engine()?.restore_fast_memory(memory).map_err(refused)?;
        self.state_changed = false;
        self.store_state();
        if !self.state().same_arrays(&before) {
            return Err(refused("its state is not the scene's".into()));
        }
        Ok(())
    }

    #[cfg(not(feature = "contact"))]
    fn restore_memory(&mut self, memory: Option<()>) -> Result<(), WorldError> {
        match memory {
            None => Ok(()),
            Some(()) => Err(WorldError::invalid("memory", "fast mode's memory needs the `contact` feature")),
        }
    }

    /// A world from `to_bytes`. A truncated file, another version or a bad value is an error naming it.
    pub fn from_bytes(bytes: &[u8]) -> Result<World, WorldError> {
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err(WorldError::invalid("file", "not a tumble world (it does not start with TUMBLEW)"));
        }
        let version = u32::from_le_bytes(bytes[8..12].try_into().expect("four bytes"));
        if version != VERSION {
            return Err(WorldError::invalid(
                "version",
                format!("this tumble reads version {VERSION} of the world format, the file is version {version}"),
            ));
        }
        let (scene, rest): (SceneFile, &[u8]) =
            postcard::take_from_bytes(&bytes[12..]).map_err(|e| decode_error("binary", e))?;
        let (memory, rest) = postcard::take_from_bytes(rest).map_err(|e| decode_error("binary", e))?;
        if !rest.is_empty() {
            return Err(decode_error("binary", format!("{} bytes left over after the scene", rest.len())));
        }
        let mut world = World::from_scene_file(&scene)?;
        world.restore_memory(memory)?;
        Ok(world)
    }

    /// Saves the world to `path`: JSON if it ends in `.json`, else the binary format.
    pub fn save(&self, path: impl AsRef<std::path::Path>) -> Result<(), WorldError> {
        let path = path.as_ref();
        let bytes = if is_json(path) { self.to_json()?.into_bytes() } else { self.to_bytes()? };
        std::fs::write(path, bytes).map_err(|e| WorldError::invalid("path", format!("{}: {e}", path.display())))
    }

    /// Loads a world saved by `save` (JSON if `path` ends in `.json`, else binary).
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<World, WorldError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| WorldError::invalid("path", format!("{}: {e}", path.display())))?;
        if is_json(path) {
            let text = String::from_utf8(bytes).map_err(|e| decode_error("JSON", e))?;
            World::from_json(&text)
        } else {
            World::from_bytes(&bytes)
        }
    }
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

fn is_json(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

#[cfg(all(test, feature = "contact"))]
mod tests {
    use crate::{FastSettings, Material, Mode, RigidBodyBuilder, Shape, World, WorldError};
    use nalgebra::Vector3;

    /// Two boxes on a ground in fast mode, stepped `steps` times.
    fn boxes(steps: usize, count: usize) -> World {
        let mut w = World::new();
        w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
        w.add_ground(0.0, Material { restitution: 0.0, friction: 0.5 }).unwrap();
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
        out.extend_from_slice(&super::VERSION.to_le_bytes());
        let out = postcard::to_extend(&scene_of.scene_file().unwrap(), out).unwrap();
        postcard::to_extend(&memory_of.saved_memory(), out).unwrap()
    }

    #[test]
    fn a_memory_that_does_not_fit_its_scene_is_refused() {
        let (a, later, bigger) = (boxes(30, 2), boxes(31, 2), boxes(30, 3));
        assert!(World::from_bytes(&spliced(&a, &a)).is_ok());
        for (what, bytes) in [("another state", spliced(&a, &later)), ("another structure", spliced(&a, &bigger))] {
            match World::from_bytes(&bytes) {
                Err(WorldError::InvalidArgument { name: "memory", .. }) => {}
                other => panic!("{what}: expected the memory refused, got {:?}", other.map(|_| ())),
            }
        }
    }
}

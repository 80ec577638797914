//! Saving and loading worlds: a readable scene file (JSON, `file.rs`) that a person can write by hand, and a
//! versioned binary format (an 8-byte magic, the version, then the same scene in postcard). Both hold every object
//! with its state to the bit, the settings and the start `reset` returns to. A loaded world starts its engine afresh
//! from the saved state, as a world built by hand and set to it would (the engine's memory, such as warm starts, is
//! not saved). A file of another version, a truncated file or a bad value is a clear error naming the field, and
//! no world is half-built.

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

    /// The world in the binary format: `TUMBLEW\0`, the version (4 bytes, little-endian), the scene.
    pub fn to_bytes(&self) -> Result<Vec<u8>, WorldError> {
        let scene = self.scene_file()?;
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&VERSION.to_le_bytes());
        postcard::to_extend(&scene, out).map_err(|e| WorldError::invalid("file", e.to_string()))
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
        if !rest.is_empty() {
            return Err(decode_error("binary", format!("{} bytes left over after the scene", rest.len())));
        }
        World::from_scene_file(&scene)
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

fn is_json(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

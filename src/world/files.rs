//! Saving and loading a world (the formats are `persist`'s): readable JSON and the versioned binary format, both
//! with the engine's memory so that a loaded world continues bit for bit; or the scene alone, hand-editable, whose
//! engine starts afresh when loaded.

use super::World;
use crate::error::WorldError;
use crate::persist;
use std::path::Path;

impl World {
    /// The world as readable JSON, with the engine's memory: loaded (`from_json`), it continues bit for bit as this
    /// one. A world with force callbacks cannot be saved: the error names `loads`.
    pub fn to_json(&self) -> Result<String, WorldError> {
        persist::to_json(self, true)
    }

    /// The scene alone as readable JSON, as a person writes it: no engine memory, so a world loaded from it starts
    /// its engine afresh from the saved state.
    pub fn to_json_scene(&self) -> Result<String, WorldError> {
        persist::to_json(self, false)
    }

    /// A world from JSON written by `to_json`, `to_json_scene` or by hand. Bad JSON, an unknown field, a wrong format
    /// or version or a bad value is an error naming it.
    pub fn from_json(text: &str) -> Result<World, WorldError> {
        persist::from_json(text)
    }

    /// The world in the binary format: `TUMBLEW\0`, the version (4 bytes, little-endian), the scene, the engine's
    /// memory (if the world has an engine: it has stepped since its structure or settings last changed).
    pub fn to_bytes(&self) -> Result<Vec<u8>, WorldError> {
        persist::to_bytes(self, true)
    }

    /// The scene alone in the binary format, without the engine's memory.
    pub fn to_bytes_scene(&self) -> Result<Vec<u8>, WorldError> {
        persist::to_bytes(self, false)
    }

    /// A world from `to_bytes` or `to_bytes_scene`. A truncated file, another version or a bad value is an error
    /// naming it.
    pub fn from_bytes(bytes: &[u8]) -> Result<World, WorldError> {
        persist::from_bytes(bytes)
    }

    /// Saves the world to `path`, with the engine's memory: JSON if it ends in `.json`, else the binary format.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), WorldError> {
        self.write(path.as_ref(), true)
    }

    /// Saves the scene alone to `path` (JSON if it ends in `.json`, else binary), without the engine's memory.
    pub fn save_scene(&self, path: impl AsRef<Path>) -> Result<(), WorldError> {
        self.write(path.as_ref(), false)
    }

    fn write(&self, path: &Path, memory: bool) -> Result<(), WorldError> {
        let bytes = if persist::is_json(path) {
            persist::to_json(self, memory)?.into_bytes()
        } else {
            persist::to_bytes(self, memory)?
        };
        std::fs::write(path, bytes).map_err(|e| WorldError::invalid("path", format!("{}: {e}", path.display())))
    }

    /// Loads a world saved by `save` or `save_scene` (JSON if `path` ends in `.json`, else binary).
    pub fn load(path: impl AsRef<Path>) -> Result<World, WorldError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| WorldError::invalid("path", format!("{}: {e}", path.display())))?;
        if persist::is_json(path) {
            let text = String::from_utf8(bytes)
                .map_err(|e| WorldError::invalid("file", format!("not a readable JSON scene: {e}")))?;
            World::from_json(&text)
        } else {
            World::from_bytes(&bytes)
        }
    }
}

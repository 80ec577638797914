//! An engine's memory, as the run loop, a world's state and a file hold it: accurate mode's or fast mode's.

use super::accurate::AccurateMemory;
use serde::{Deserialize, Serialize};

use super::fast::FastMemory;

/// The memory of one engine.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Serialize, Deserialize)]
pub(crate) enum EngineMemory {
    Accurate(Box<AccurateMemory>),
    Fast(Box<FastMemory>),
}

impl EngineMemory {
    /// The engine it comes from, for errors.
    pub fn engine_name(&self) -> &'static str {
        match self {
            EngineMemory::Accurate(m) => super::accurate::engine_name(&m.contact),
            EngineMemory::Fast(_) => "fast mode",
        }
    }
}

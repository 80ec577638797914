//! An engine's memory, as the run loop, a world's state and a file hold it: accurate mode's or fast mode's. The
//! variants keep their order with or without the `contact` feature, so that the binary format does not depend on
//! it.

use super::accurate::AccurateMemory;
use serde::{Deserialize, Serialize};

#[cfg(feature = "contact")]
use super::fast::FastMemory;

/// Without the `contact` feature there is no fast mode (the type keeps the format the same in both builds).
#[cfg(not(feature = "contact"))]
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) enum FastMemory {}

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

//! A body's look: its name and colour, for people and the tools they take a run into; no part of the physics.

use crate::error::WorldError;

/// A body's name and colour, for people and the tools they take a run into; no part of the physics.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Look {
    /// Its name (glTF node, USD prim, viewer label); none: the exporters call it by its place.
    pub name: Option<String>,
    /// Its colour as linear RGBA, each in [0, 1]; none: the exporters' palette.
    pub color: Option<[f64; 4]>,
}

/// Longest name a body may have (characters).
pub const MAX_NAME: usize = 256;

impl Look {
    /// A colour from RGB (opaque) or RGBA components, as the bindings and files take it.
    pub fn color_of(components: &[f64]) -> Result<[f64; 4], WorldError> {
        match *components {
            [r, g, b] => Ok([r, g, b, 1.0]),
            [r, g, b, a] => Ok([r, g, b, a]),
            _ => Err(WorldError::invalid(
                "color",
                format!("expected 3 (RGB) or 4 (RGBA) numbers, got {}", components.len()),
            )),
        }
    }

    /// Checks the name (1 to `MAX_NAME` characters, no control characters) and the colour (each component in [0, 1]).
    pub(crate) fn check(&self) -> Result<(), WorldError> {
        if let Some(name) = &self.name {
            let count = name.chars().count();
            if count == 0 || count > MAX_NAME || name.chars().any(char::is_control) {
                return Err(WorldError::invalid(
                    "name",
                    format!("must be 1 to {MAX_NAME} characters without control characters, got {name:?}"),
                ));
            }
        }
        if let Some(c) = self.color {
            if !c.iter().all(|v| (0.0..=1.0).contains(v)) {
                return Err(WorldError::invalid(
                    "color",
                    format!("must be linear RGBA with each component in [0, 1], got {c:?}"),
                ));
            }
        }
        Ok(())
    }
}

//! How a closed mesh collides: decomposed into convex pieces (a moving body's default), as one convex hull (the cheap
//! choice), or exactly as its triangles (a static body's default; a moving body cannot, having no convex pieces).

use crate::error::WorldError;
use tumble_collide::{Decomposition, Shape};

/// The collision geometry a closed mesh is given on a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MeshShape {
    /// Approximate convex decomposition with these parameters.
    Decomposed(Decomposition),
    /// The convex hull of the mesh's vertices.
    Hull,
    /// The exact triangles (static bodies only).
    Exact,
}

impl MeshShape {
    /// By name: "decomposed" (with `decomposition`, or the defaults), "hull" or "exact". Parameters with another
    /// choice are an option that does not apply: an error naming `decomposition`.
    pub fn named(name: &str, decomposition: Option<Decomposition>) -> Result<MeshShape, WorldError> {
        let choice = match name {
            "decomposed" => return Ok(MeshShape::Decomposed(decomposition.unwrap_or_default())),
            "hull" => MeshShape::Hull,
            "exact" => MeshShape::Exact,
            other => {
                return Err(WorldError::invalid(
                    "shape",
                    format!("a mesh's shape is \"decomposed\", \"hull\" or \"exact\", got \"{other}\""),
                ))
            }
        };
        if decomposition.is_some() {
            return Err(WorldError::invalid(
                "decomposition",
                format!("applies to shape=\"decomposed\", not \"{name}\""),
            ));
        }
        Ok(choice)
    }

    /// The choice as `add_body` spells it: "decomposed", "hull" or "exact".
    pub fn name(&self) -> &'static str {
        match self {
            MeshShape::Decomposed(_) => "decomposed",
            MeshShape::Hull => "hull",
            MeshShape::Exact => "exact",
        }
    }

    /// The shape a body carries for `shape`: a closed mesh becomes its decomposition (moving bodies, by default),
    /// its hull, or stays exact (static bodies, by default); other shapes are kept as they are (a choice given for a
    /// body without a mesh is the builder's error).
    pub(crate) fn resolve(shape: &Shape, choice: Option<&MeshShape>, is_static: bool) -> Result<Shape, WorldError> {
        let Shape::Mesh(mesh) = shape else { return Ok(shape.clone()) };
        let default = if is_static { MeshShape::Exact } else { MeshShape::Decomposed(Decomposition::default()) };
        Ok(match choice.copied().unwrap_or(default) {
            MeshShape::Decomposed(params) => Shape::decomposed(mesh, &params)?,
            MeshShape::Hull => Shape::hull_of(mesh)?,
            MeshShape::Exact if is_static => shape.clone(),
            MeshShape::Exact => {
                return Err(WorldError::invalid(
                    "shape",
                    "an exact mesh collides only as a static body: a moving one is decomposed (\"decomposed\") or \
                     given its hull (\"hull\")",
                ))
            }
        })
    }
}

//! One contact point of a pair: its points on both surfaces, normal, signed distance, the features that carry it and
//! its kind in the chapter's terms. Contacts of polyhedra are vertex-face or edge-edge; the degenerate kinds
//! (vertex-vertex, vertex-edge) are folded into vertex-face. A point of a curved surface acts as a vertex against a
//! face and as a face against a vertex or an edge.

use nalgebra::{Point3, Unit, Vector3};

/// The feature of a shape that carries a contact point.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// A vertex (parry's id).
    Vertex(u32),
    /// An edge (parry's id).
    Edge(u32),
    /// A face (parry's id).
    Face(u32),
    /// A point of a curved surface (sphere, capsule).
    Curved,
    /// Not known (parry's deepest-point fallback).
    Unknown,
}

/// The kind of a contact in the chapter's terms.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactKind {
    /// A vertex of A (or a point of its curved surface) on a face of B; normal = B's face normal.
    VertexFace,
    /// A face of A against a vertex of B; normal = A's face normal.
    FaceVertex,
    /// An edge of A crossing an edge of B; normal = the cross product of the edges.
    EdgeEdge,
    /// Two curved surfaces (sphere on sphere, say); normal = their common normal.
    Curved,
}

/// One contact point of a pair (A, B), in world coordinates.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct ShapeContact {
    /// The point of A's surface.
    pub point_a: Point3<f64>,
    /// The point of B's surface.
    pub point_b: Point3<f64>,
    /// Unit normal from A toward B.
    pub normal: Unit<Vector3<f64>>,
    /// Signed distance `normal . (point_b - point_a)`: positive apart, negative interpenetrating.
    pub distance: f64,
    /// The kind of contact.
    pub kind: ContactKind,
    /// A's feature.
    pub feature_a: Feature,
    /// B's feature.
    pub feature_b: Feature,
}

/// The kind of contact the features of A and B make.
pub(crate) fn kind(a: Feature, b: Feature) -> ContactKind {
    use Feature::*;
    match (a, b) {
        (Edge(_), Edge(_)) => ContactKind::EdgeEdge,
        (Curved, Curved) => ContactKind::Curved,
        (Face(_) | Curved, Vertex(_) | Edge(_)) | (Face(_), Curved) => ContactKind::FaceVertex,
        // A vertex on a face, and the folded kinds: vertex-vertex, vertex-edge, edge-face, face-face, unknown.
        (Edge(_), Vertex(_)) => ContactKind::FaceVertex,
        _ => ContactKind::VertexFace,
    }
}

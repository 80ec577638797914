//! A fractured object: its pieces added as bodies where they were modelled, and each pair that shares a face glued
//! by a breakable weld whose bounds are the face's area times the glue's strength, so that the object moves as
//! one until a load breaks it, bond by bond.

use super::World;
use crate::body::RigidBodyBuilder;
use crate::collider::Material;
use crate::error::WorldError;
use crate::joint::{JointBuilder, JointHandle};
use crate::limits;
use crate::mesh_shape::MeshShape;
use crate::spring::BodyHandle;
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use tumble_collide::{shared_faces, Mesh, Shape, SharedFace, MAX_PIECES};

/// The strongest glue: 1e12 Pa, past diamond's strength.
pub const MAX_STRENGTH: f64 = 1e12;

/// Pieces fill their mesh where their volumes add up to its own to this share (a fracture's do to rounding).
const FILLS: f64 = 1e-6;

/// The weakest glue: a millipascal (a bond weaker than that holds nothing a simulation would notice).
pub const MIN_STRENGTH: f64 = 1e-3;

/// The glue's break window by default (s): a bond is judged by its load averaged over about this long
/// (`Breaking::window`), so that what breaks converges as the step shrinks.
pub const GLUE_WINDOW: f64 = 0.01;

/// How to glue a fractured object's pieces: the pieces' `density` (kg/m^3), the glue's `strength` (Pa: the
/// tensile stress a bond fails at) and the `window` its load is averaged over (s), the object's pose, and the
/// pieces' material.
#[derive(Clone, Debug)]
pub struct Glue {
    pub density: f64,
    pub strength: f64,
    pub window: f64,
    pub position: Vector3<f64>,
    pub orientation: UnitQuaternion<f64>,
    pub material: Material,
}

impl Glue {
    /// Pieces of `density` glued at `strength` pascals, where they were modelled, of the default material.
    pub fn new(density: f64, strength: f64) -> Glue {
        Glue {
            density,
            strength,
            window: GLUE_WINDOW,
            position: Vector3::zeros(),
            orientation: UnitQuaternion::identity(),
            material: Material::default(),
        }
    }
}

/// What `add_fractured` added: each piece's body, in the pieces' order, and each bond's weld with the face it
/// holds (the faces' pieces index `bodies`).
#[derive(Clone, Debug)]
pub struct Fractured {
    pub bodies: Vec<BodyHandle>,
    pub bonds: Vec<(JointHandle, SharedFace)>,
}

/// A bond's bounds from its face's `area` and the glue's `strength`: the force that pulls the face apart
/// (strength times area) and the bending moment that cracks it (strength times the section modulus of a round
/// face of that area, pi r^3 / 4 = area r / 4).
pub fn bond_bounds(area: f64, strength: f64) -> (f64, f64) {
    let radius = (area / std::f64::consts::PI).sqrt();
    (strength * area, strength * area * radius / 4.0)
}

/// A shared face smaller than this share of the object's median face is a touch, not a bond: it is left unglued.
/// (Where cells meet the surface at a glancing angle they share slivers of face; glued, each held a hundredth of
/// a typical bond's load and broke under the object's own weight, whatever shares the load among the welds.)
pub const SMALLEST_BOND: f64 = 0.05;

/// The bonds that glue `pieces` (closed meshes in one frame) at `strength` (Pa): each face they share of at least
/// `SMALLEST_BOND` of the median face's area, with its force and torque bounds (`bond_bounds`).
pub fn bonds(pieces: &[Mesh], strength: f64) -> Vec<(SharedFace, f64, f64)> {
    glued_faces(shared_faces(pieces))
        .into_iter()
        .map(|f| {
            let (force, torque) = bond_bounds(f.area, strength);
            (f, force, torque)
        })
        .collect()
}

/// The faces to glue: those of at least `SMALLEST_BOND` of the median face's area.
fn glued_faces(mut faces: Vec<SharedFace>) -> Vec<SharedFace> {
    let mut areas: Vec<f64> = faces.iter().map(|f| f.area).collect();
    areas.sort_by(f64::total_cmp);
    if let Some(&median) = areas.get(areas.len() / 2) {
        faces.retain(|f| f.area >= SMALLEST_BOND * median);
    }
    faces
}

impl World {
    /// Adds the `pieces` of fractured `mesh` (closed meshes in its frame that fill it, as `Mesh::fracture` makes them) as
    /// bodies where they were modelled, the frame placed at `glue`'s pose; a convex piece collides as its hull,
    /// another as its convex decomposition. Each pair that shares a face is welded by a joint that breaks past
    /// `bond_bounds` of the face's area. Nothing is added when an argument is wrong (the error names it).
    pub fn add_fractured(&mut self, mesh: &Mesh, pieces: &[Mesh], glue: &Glue) -> Result<Fractured, WorldError> {
        if pieces.is_empty() || pieces.len() > MAX_PIECES {
            return Err(WorldError::invalid(
                "pieces",
                format!("expected 1 to {MAX_PIECES} meshes, got {}", pieces.len()),
            ));
        }
        let filled: f64 = pieces.iter().map(Mesh::volume).sum();
        if (filled - mesh.volume()).abs() > FILLS * mesh.volume() {
            return Err(WorldError::invalid(
                "pieces",
                format!(
                    "do not fill `mesh` ({}): their volumes add up to {filled:e} m^3, its own is {:e} m^3",
                    mesh.name(),
                    mesh.volume()
                ),
            ));
        }
        limits::in_range("strength", glue.strength, MIN_STRENGTH, MAX_STRENGTH, "Pa")?;
        limits::non_negative("window", glue.window, limits::TIME, "s")?;
        limits::vector("position", &glue.position, limits::COORDINATE, "m")?;
        let glued = bonds(pieces, glue.strength);
        // every body built (and so checked) before any is added
        let built = pieces
            .iter()
            .map(|piece| {
                let shape = if piece.is_convex() { MeshShape::Hull } else { MeshShape::Decomposed(Default::default()) };
                let body = RigidBodyBuilder::from_shape(Shape::Mesh(piece.clone()), glue.density)
                    .mesh_shape(shape)
                    .position(glue.position)
                    .orientation(glue.orientation)
                    .material(glue.material)
                    .name(piece.name());
                self.built_body(body)
            })
            .collect::<Result<Vec<_>, _>>()?;
        // each bond's weld, its anchors in its pieces' frames as built
        let frame = Isometry3::from_parts(glue.position.into(), glue.orientation);
        let welds: Vec<(Vector3<f64>, Vector3<f64>)> = glued
            .iter()
            .map(|(face, _, _)| {
                let at = frame * face.centre;
                let local = |k: usize| built[k].orientation.inverse() * (at.coords - built[k].position);
                (local(face.a), local(face.b))
            })
            .collect();
        let bodies: Vec<BodyHandle> = built.into_iter().map(|b| self.insert_body(b)).collect();
        let mut welded = Vec::with_capacity(glued.len());
        for ((anchor_a, anchor_b), (face, force, torque)) in welds.into_iter().zip(glued) {
            // two bodies just added, anchors inside them, bounds above zero and finite: nothing a weld refuses
            let joint = JointBuilder::weld(Some(bodies[face.a]), Some(bodies[face.b]))
                .anchor_a(anchor_a)
                .anchor_b(anchor_b)
                .breaking_averaged(force, torque, glue.window)
                .cluster(true);
            welded.push((self.add_joint(joint)?, face));
        }
        Ok(Fractured { bodies, bonds: welded })
    }
}

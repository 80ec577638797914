//! parry's view of a `Shape`: the parry shape it stands for and the fixed offset between the two frames (parry's
//! cylinder runs along y, ours along z), so that every query can hand parry a `&dyn Shape` and a parry pose.

use crate::convert::{pose_to_parry, to_parry};
use crate::shape::Shape;
use nalgebra::Isometry3;
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::shape::{
    Ball, Capsule, Compound, ConvexPolyhedron, Cuboid, Cylinder, HalfSpace, Shape as ParryShape, TriMesh, Triangle,
};

/// A parry shape borrowed or built from one of ours.
pub(crate) enum ParryView<'a> {
    Ball(Ball),
    Cuboid(Cuboid),
    Capsule(Capsule),
    Cylinder(Cylinder),
    Hull(&'a ConvexPolyhedron),
    Mesh(&'a TriMesh),
    Compound(&'a Compound),
    HalfSpace(HalfSpace),
}

impl<'a> ParryView<'a> {
    pub(crate) fn of(shape: &'a Shape) -> Self {
        match shape {
            Shape::Sphere { radius } => ParryView::Ball(Ball::new(*radius)),
            Shape::Cuboid { half_extents } => ParryView::Cuboid(Cuboid::new(to_parry(half_extents))),
            Shape::Capsule { half_height, radius } => ParryView::Capsule(Capsule::new_z(*half_height, *radius)),
            Shape::Cylinder { half_height, radius } => ParryView::Cylinder(Cylinder::new(*half_height, *radius)),
            Shape::ConvexHull(h) => ParryView::Hull(&h.polyhedron),
            Shape::TriMesh(m) => ParryView::Mesh(&m.mesh),
            Shape::Mesh(m) => ParryView::Mesh(&m.exact),
            Shape::Decomposed(d) => ParryView::Compound(&d.compound),
            Shape::HalfSpace { normal } => ParryView::HalfSpace(HalfSpace::new(to_parry(normal))),
        }
    }

    pub(crate) fn as_dyn(&self) -> &dyn ParryShape {
        match self {
            ParryView::Ball(s) => s,
            ParryView::Cuboid(s) => s,
            ParryView::Capsule(s) => s,
            ParryView::Cylinder(s) => s,
            ParryView::Hull(s) => *s,
            ParryView::Mesh(s) => *s,
            ParryView::Compound(s) => *s,
            ParryView::HalfSpace(s) => s,
        }
    }

    /// Triangle `index` of a mesh (parry's manifolds of a mesh are per triangle); `None` for other shapes.
    pub(crate) fn triangle(&self, index: u32) -> Option<Triangle> {
        match self {
            ParryView::Mesh(m) if (index as usize) < m.indices().len() => Some(m.triangle(index)),
            _ => None,
        }
    }

    /// Convex piece `index` of a compound; `None` for other shapes.
    pub(crate) fn piece(&self, index: u32) -> Option<&'a dyn ParryShape> {
        match self {
            ParryView::Compound(c) => c.shapes().get(index as usize).map(|(_, s)| s.as_ref()),
            _ => None,
        }
    }

    /// The pose parry needs for a shape of ours at `pose`.
    pub(crate) fn pose(&self, pose: &Isometry3<f64>) -> Pose {
        let p = pose_to_parry(pose);
        match self {
            // parry's y axis is our z axis: turn its frame by +90 degrees about x (y -> z).
            ParryView::Cylinder(_) => p * Pose::from_rotation(cylinder_turn()),
            _ => p,
        }
    }
}

fn cylinder_turn() -> Rotation {
    Rotation::from_axis_angle(Vector::X, std::f64::consts::FRAC_PI_2)
}

//! Mass properties as numbers: a mass, its centre and its inertia tensor, and a tensor turned into another frame.

use nalgebra::{Matrix3, Vector3};

/// Mass, centre of mass and inertia tensor about the centre of mass, in the shape's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass.
    pub mass: f64,
    /// Centre of mass in the shape's frame.
    pub local_com: Vector3<f64>,
    /// Inertia tensor about the centre of mass, axes of the shape's frame.
    pub inertia: Matrix3<f64>,
}

/// A body-frame tensor (an inertia or its inverse) expressed in the frame rotated by `r` from it: R T R^T. The one
/// place the world inertia of a turned body is formed.
pub fn rotated_tensor(r: &Matrix3<f64>, tensor: &Matrix3<f64>) -> Matrix3<f64> {
    r * tensor * r.transpose()
}

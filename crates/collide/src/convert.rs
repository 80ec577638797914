//! The one place where nalgebra meets parry's glam types.

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use parry3d_f64::math::{Matrix, Pose, Rotation, Vector};

pub(crate) fn to_parry(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

pub(crate) fn point_to_parry(p: &Point3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

pub(crate) fn from_parry(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

pub(crate) fn point_from_parry(v: Vector) -> Point3<f64> {
    Point3::new(v.x, v.y, v.z)
}

pub(crate) fn matrix_from_parry(m: Matrix) -> Matrix3<f64> {
    let c = m.to_cols_array();
    Matrix3::from_column_slice(&c)
}

pub(crate) fn pose_to_parry(iso: &Isometry3<f64>) -> Pose {
    let q = iso.rotation.quaternion();
    Pose::from_parts(to_parry(&iso.translation.vector), Rotation::from_xyzw(q.i, q.j, q.k, q.w))
}

//! Axis-aligned bounding boxes: of a posed shape, and swept over a step so that they enclose the shape's whole motion.

use crate::convert::{from_parry, point_from_parry};
use crate::error::ShapeError;
use crate::geometry::ParryView;
use crate::shape::Shape;
use nalgebra::{Isometry3, Point3, Vector3};

/// A closed axis-aligned box `[min, max]`; bounds may be infinite (a ground plane), never NaN.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Point3<f64>,
    /// Upper corner.
    pub max: Point3<f64>,
}

impl Aabb {
    /// A box from its corners: no NaN, and `min <= max` on every axis (a zero-size box is allowed).
    pub fn new(min: Point3<f64>, max: Point3<f64>) -> Result<Aabb, ShapeError> {
        let b = Aabb { min, max };
        b.check("aabb")?;
        Ok(b)
    }

    /// The box around a set of points (`None` when there are none).
    pub fn from_points(points: &[Point3<f64>]) -> Option<Aabb> {
        let first = points.first()?;
        Some(
            points.iter().fold(Aabb { min: *first, max: *first }, |b, p| Aabb { min: b.min.inf(p), max: b.max.sup(p) }),
        )
    }

    /// Checks the box is well formed, naming it `name` in the error.
    pub(crate) fn check(&self, name: &'static str) -> Result<(), ShapeError> {
        for k in 0..3 {
            if self.min[k].is_nan() || self.max[k].is_nan() || self.min[k] > self.max[k] {
                return Err(ShapeError::new(
                    name,
                    format!("axis {k}: bounds [{}, {}] are NaN or reversed", self.min[k], self.max[k]),
                ));
            }
        }
        Ok(())
    }

    /// Whether the two closed boxes share a point (boxes that touch overlap).
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= other.max[k] && other.min[k] <= self.max[k])
    }

    /// Whether `p` lies in the closed box.
    pub fn contains(&self, p: &Point3<f64>) -> bool {
        (0..3).all(|k| self.min[k] <= p[k] && p[k] <= self.max[k])
    }

    /// The smallest box holding both.
    pub fn merged(&self, other: &Aabb) -> Aabb {
        Aabb { min: self.min.inf(&other.min), max: self.max.sup(&other.max) }
    }

    /// The box grown by `margin` (>= 0) on every side.
    pub fn loosened(&self, margin: f64) -> Aabb {
        let m = Vector3::repeat(margin.max(0.0));
        Aabb { min: self.min - m, max: self.max + m }
    }

    /// The centre (infinite bounds give an infinite or NaN centre; test `is_finite` first).
    pub fn center(&self) -> Point3<f64> {
        nalgebra::center(&self.min, &self.max)
    }

    /// Whether every bound is finite.
    pub fn is_finite(&self) -> bool {
        self.min.iter().chain(self.max.iter()).all(|v| v.is_finite())
    }
}

pub(crate) fn check_pose(name: &'static str, pose: &Isometry3<f64>) -> Result<(), ShapeError> {
    let q = pose.rotation.quaternion();
    if pose.translation.vector.iter().chain(q.coords.iter()).all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(ShapeError::new(name, format!("the pose is not finite: {pose:?}")))
    }
}

impl Shape {
    /// The world box of the shape at `pose`. A half-space is unbounded except along its normal when that is a
    /// coordinate axis.
    pub fn aabb(&self, pose: &Isometry3<f64>) -> Result<Aabb, ShapeError> {
        check_pose("pose", pose)?;
        if let Shape::HalfSpace { normal } = self {
            let n = pose.rotation * normal.into_inner();
            let mut b = Aabb {
                min: Point3::from(Vector3::repeat(f64::NEG_INFINITY)),
                max: Point3::from(Vector3::repeat(f64::INFINITY)),
            };
            let axis = (0..3).find(|&k| n[k].abs() == 1.0);
            if let Some(k) = axis {
                let h = pose.translation.vector[k];
                if n[k] > 0.0 {
                    b.max[k] = h;
                } else {
                    b.min[k] = h;
                }
            }
            return Ok(b);
        }
        let view = ParryView::of(self);
        let b = view.as_dyn().compute_aabb(&view.pose(pose));
        Ok(Aabb { min: point_from_parry(b.mins), max: point_from_parry(b.maxs) })
    }

    /// The radius of the smallest ball about the shape's origin that holds it (infinite for a half-space).
    pub fn bounding_radius(&self) -> f64 {
        match self {
            Shape::Sphere { radius } => *radius,
            Shape::Cuboid { half_extents } => half_extents.norm(),
            Shape::Capsule { half_height, radius } => half_height + radius,
            Shape::Cylinder { half_height, radius } => half_height.hypot(*radius),
            Shape::HalfSpace { .. } => f64::INFINITY,
            _ => {
                let view = ParryView::of(self);
                let s = view.as_dyn().compute_local_bounding_sphere();
                from_parry(s.center).norm() + s.radius
            }
        }
    }

    /// A box that holds the shape during the whole motion from `start` to `end` when the origin moves on the straight
    /// line between them and the orientation turns at a constant rate about a fixed axis (a `Motion`): the union of
    /// the two end boxes, grown by the largest distance a point of the shape strays from the chord between its two end
    /// positions, `r (1 - cos(theta / 2))` for a turn of theta and bounding radius r. Other motions need their own
    /// margin (`Aabb::loosened`).
    pub fn swept_aabb(&self, start: &Isometry3<f64>, end: &Isometry3<f64>) -> Result<Aabb, ShapeError> {
        check_pose("start", start)?;
        check_pose("end", end)?;
        let b = self.aabb(start)?.merged(&self.aabb(end)?);
        let theta = start.rotation.angle_to(&end.rotation);
        if theta == 0.0 || !b.is_finite() {
            return Ok(b);
        }
        Ok(b.loosened(self.bounding_radius() * (1.0 - (0.5 * theta).cos())))
    }
}

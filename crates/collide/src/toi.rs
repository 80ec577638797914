//! Collision time. The chapter's scheme: the pair is apart at t_i and interpenetrating at t_i+1, so the time of
//! contact t_c lies between and bisection finds it to a tolerance. Two alternatives that also see a contact that
//! starts and ends inside the interval (a fast body through a thin wall): conservative advancement on parry's
//! distance (any pair parry can measure, half-spaces included) and parry's nonlinear shape cast.

use crate::aabb::check_pose;
use crate::error::ShapeError;
use crate::geometry::ParryView;
use crate::motion::Motion;
use crate::polyhedron::Polyhedron;
use crate::proximity::{distance, intersects, unsupported_pair};
use crate::shape::Shape;
use nalgebra::{Isometry3, Vector3};
use parry3d_f64::query::{DefaultQueryDispatcher, QueryDispatcher, ShapeCastStatus};

/// How `time_of_impact` looks for the collision time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToiMethod {
    /// The chapter's bisection on intersection tests. When the pair is apart at both ends, the interval is first
    /// sampled finely enough that a body cannot pass through the other between samples (spacing: the sum of the two
    /// inner radii); a grazing touch shallower than that can be missed.
    Bisection,
    /// Conservative advancement: step forward by distance / (bound on the closing speed) until the gap is closed.
    ConservativeAdvancement,
    /// parry's nonlinear shape cast (convex shapes and triangle meshes; not half-spaces).
    ShapeCast,
}

/// Options of `time_of_impact`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToiOptions {
    /// The method.
    pub method: ToiMethod,
    /// Time tolerance (> 0): bisection stops on a bracket this wide; conservative advancement once the next advance
    /// would be shorter.
    pub tolerance: f64,
    /// Cap on queries (intersection tests or distances); reaching it is an error.
    pub max_iterations: usize,
}

impl Default for ToiOptions {
    fn default() -> Self {
        ToiOptions { method: ToiMethod::Bisection, tolerance: 1e-9, max_iterations: 10_000 }
    }
}

/// The first contact of a pair in an interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// The collision time to the tolerance; the pair is apart (or just touching) at this time.
    pub time: f64,
    /// Distance between the shapes at `time` (>= 0).
    pub distance: f64,
    /// Intersection or distance queries made.
    pub iterations: usize,
}

/// The result of the chapter's bisection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bisection {
    /// The last time found with the shapes apart.
    pub before: f64,
    /// The first time found with the shapes in contact; `after - before <= tolerance`.
    pub after: f64,
    /// Intersection tests made.
    pub steps: usize,
}

fn positive(name: &'static str, v: f64) -> Result<f64, ShapeError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ShapeError::new(name, format!("must be finite and > 0, got {v}")))
    }
}

/// The chapter's bisection for any motion: `poses(t)` gives the poses of A and B at t; the pair must be apart at
/// `t0` and in contact at `t1`. Halves [t0, t1] until it is narrower than `tolerance`.
pub fn bisect_collision_time(
    a: &Shape,
    b: &Shape,
    mut poses: impl FnMut(f64) -> (Isometry3<f64>, Isometry3<f64>),
    t0: f64,
    t1: f64,
    tolerance: f64,
) -> Result<Bisection, ShapeError> {
    positive("tolerance", tolerance)?;
    if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
        return Err(ShapeError::new("t1", format!("the interval [{t0}, {t1}] must be finite with t1 > t0")));
    }
    let mut touching = |t: f64| -> Result<bool, ShapeError> {
        let (pa, pb) = poses(t);
        intersects(a, &pa, b, &pb)
    };
    if touching(t0)? {
        return Err(ShapeError::new("t0", format!("the shapes are already in contact at t0 = {t0}")));
    }
    if !touching(t1)? {
        return Err(ShapeError::new("t1", format!("the shapes are not in contact at t1 = {t1}: nothing to bisect")));
    }
    let (mut before, mut after, mut steps) = (t0, t1, 2);
    while after - before > tolerance {
        let mid = 0.5 * (before + after);
        if mid <= before || mid >= after {
            break; // the interval cannot be split further in floating point
        }
        steps += 1;
        if touching(mid)? {
            after = mid;
        } else {
            before = mid;
        }
    }
    Ok(Bisection { before, after, steps })
}

/// The radius of a ball that fits inside the shape (about its origin for a box or curved shape, about the vertex
/// mean for a hull); infinite for a half-space, zero for a triangle mesh.
fn inner_radius(shape: &Shape) -> f64 {
    match shape {
        Shape::Sphere { radius } | Shape::Capsule { radius, .. } => *radius,
        Shape::Cuboid { half_extents } => half_extents.min(),
        Shape::Cylinder { half_height, radius } => half_height.min(*radius),
        Shape::HalfSpace { .. } => f64::INFINITY,
        Shape::TriMesh(_) => 0.0,
        Shape::ConvexHull(_) => match Polyhedron::from_shape(shape) {
            Ok(p) => {
                let c = p.vertices().iter().sum::<Vector3<f64>>() / p.vertices().len() as f64;
                p.faces().iter().map(|(n, d)| d - n.dot(&c)).fold(f64::INFINITY, f64::min)
            }
            Err(_) => 0.0,
        },
    }
}

/// The first time in [0, t_end] at which `a` moving by `motion_a` touches `b` moving by `motion_b`, or `None` when
/// they stay apart. They must be apart at time 0.
pub fn time_of_impact(
    a: &Shape,
    motion_a: &Motion,
    b: &Shape,
    motion_b: &Motion,
    t_end: f64,
    options: &ToiOptions,
) -> Result<Option<Impact>, ShapeError> {
    positive("t_end", t_end)?;
    positive("tolerance", options.tolerance)?;
    check_pose("motion_a", &motion_a.start)?;
    check_pose("motion_b", &motion_b.start)?;
    let d0 = distance(a, &motion_a.start, b, &motion_b.start)?;
    if d0 <= 0.0 {
        return Err(ShapeError::new("motion_a", "the shapes are already in contact at time 0"));
    }
    // A bound on how fast the gap can close.
    let rel = (motion_b.linvel - motion_a.linvel).norm();
    let spin = |m: &Motion, s: &Shape| {
        let w = m.angvel.norm();
        if w > 0.0 {
            w * s.bounding_radius()
        } else {
            0.0
        }
    };
    let closing = rel + spin(motion_a, a) + spin(motion_b, b);
    if !closing.is_finite() {
        return Err(ShapeError::new("motion_a", "a turning half-space has no bound on its speed"));
    }
    if closing * t_end < d0 {
        return Ok(None);
    }
    match options.method {
        ToiMethod::Bisection => by_bisection(a, motion_a, b, motion_b, t_end, closing, options),
        ToiMethod::ConservativeAdvancement => by_advancement(a, motion_a, b, motion_b, t_end, closing, d0, options),
        ToiMethod::ShapeCast => by_shape_cast(a, motion_a, b, motion_b, t_end),
    }
}

fn by_bisection(
    a: &Shape,
    motion_a: &Motion,
    b: &Shape,
    motion_b: &Motion,
    t_end: f64,
    closing: f64,
    options: &ToiOptions,
) -> Result<Option<Impact>, ShapeError> {
    let poses = |t: f64| (motion_a.pose_at(t), motion_b.pose_at(t));
    let spacing = inner_radius(a) + inner_radius(b);
    let samples = (closing * t_end / spacing).ceil().max(1.0);
    if samples > options.max_iterations as f64 {
        return Err(ShapeError::new(
            "options",
            format!("sampling against tunnelling needs {samples} intersection tests, over max_iterations"),
        ));
    }
    let n = samples as usize;
    let mut prev = 0.0;
    for k in 1..=n {
        let t = t_end * k as f64 / n as f64;
        let (pa, pb) = poses(t);
        if intersects(a, &pa, b, &pb)? {
            let r = bisect_collision_time(a, b, poses, prev, t, options.tolerance)?;
            let (pa, pb) = poses(r.before);
            let d = distance(a, &pa, b, &pb)?;
            return Ok(Some(Impact { time: r.before, distance: d, iterations: k + r.steps }));
        }
        prev = t;
    }
    Ok(None)
}

#[allow(clippy::too_many_arguments)]
fn by_advancement(
    a: &Shape,
    motion_a: &Motion,
    b: &Shape,
    motion_b: &Motion,
    t_end: f64,
    closing: f64,
    d0: f64,
    options: &ToiOptions,
) -> Result<Option<Impact>, ShapeError> {
    let (mut t, mut d) = (0.0, d0);
    for iterations in 1..=options.max_iterations {
        let advance = d / closing;
        if advance <= options.tolerance {
            return Ok(Some(Impact { time: t, distance: d, iterations }));
        }
        t += advance;
        if t > t_end {
            return Ok(None);
        }
        d = distance(a, &motion_a.pose_at(t), b, &motion_b.pose_at(t))?;
    }
    Err(ShapeError::new(
        "options",
        format!("conservative advancement did not converge in {} steps", options.max_iterations),
    ))
}

fn by_shape_cast(
    a: &Shape,
    motion_a: &Motion,
    b: &Shape,
    motion_b: &Motion,
    t_end: f64,
) -> Result<Option<Impact>, ShapeError> {
    let (va, vb) = (ParryView::of(a), ParryView::of(b));
    let hit = DefaultQueryDispatcher
        .cast_shapes_nonlinear(
            &motion_a.to_parry(&va),
            va.as_dyn(),
            &motion_b.to_parry(&vb),
            vb.as_dyn(),
            0.0,
            t_end,
            true,
        )
        .map_err(|_| unsupported_pair(a, b))?;
    let Some(hit) = hit else { return Ok(None) };
    if hit.status == ShapeCastStatus::Failed {
        return Err(ShapeError::new("motion_a", "parry's shape cast failed to converge"));
    }
    let t = hit.time_of_impact;
    let d = distance(a, &motion_a.pose_at(t), b, &motion_b.pose_at(t))?;
    Ok(Some(Impact { time: t, distance: d, iterations: 0 }))
}

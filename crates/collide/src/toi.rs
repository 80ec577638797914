//! Collision time. The chapter's scheme: the pair is apart at t_i and interpenetrating at t_i+1, so the time of
//! contact t_c lies between and bisection finds it to a tolerance. Two alternatives that also see a contact that
//! starts and ends inside the interval (a fast body through a thin wall): conservative advancement on parry's
//! distance (any pair parry can measure, half-spaces included) and parry's nonlinear shape cast.

use crate::aabb::check_pose;
use crate::error::ShapeError;
use crate::geometry::ParryView;
use crate::motion::Motion;
use crate::proximity::{distance, intersects, unsupported_pair};
use crate::shape::Shape;
use nalgebra::{Isometry3, Vector3};
use parry3d_f64::query::{DefaultQueryDispatcher, QueryDispatcher, ShapeCastStatus};

/// How `time_of_impact` looks for the collision time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToiMethod {
    /// The chapter's bisection on intersection tests. An interval with the pair apart at both ends is halved only
    /// while the distances at its ends leave room for a contact inside (a gap cannot close faster than the bound on
    /// the closing speed), so no contact is missed; a near miss closer than closing speed x tolerance counts as a
    /// touch.
    Bisection,
    /// Conservative advancement: step forward by distance / (bound on the closing speed) until the gap is closed.
    ConservativeAdvancement,
    /// parry's nonlinear shape cast (convex shapes and triangle meshes; not half-spaces).
    ShapeCast,
    /// The fastest that applies (the default), as measured by `cargo bench -p tumble-collide --bench narrow_phase`:
    /// conservative advancement when neither shape turns (it lands in one or two distance queries), parry's shape
    /// cast when one turns and parry takes the pair, conservative advancement otherwise.
    Auto,
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
        ToiOptions { method: ToiMethod::Auto, tolerance: 1e-9, max_iterations: 10_000 }
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
    let mut steps = 2;
    let (before, after) = halve(t0, t1, tolerance, |t| {
        steps += 1;
        touching(t)
    })?;
    Ok(Bisection { before, after, steps })
}

/// Halves [before, after] (apart at `before`, in contact at `after`) until it is narrower than `tolerance` or cannot
/// be split in floating point.
fn halve(
    mut before: f64,
    mut after: f64,
    tolerance: f64,
    mut in_contact: impl FnMut(f64) -> Result<bool, ShapeError>,
) -> Result<(f64, f64), ShapeError> {
    while after - before > tolerance {
        let mid = 0.5 * (before + after);
        if mid <= before || mid >= after {
            break;
        }
        if in_contact(mid)? {
            after = mid;
        } else {
            before = mid;
        }
    }
    Ok((before, after))
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
    let method = match options.method {
        ToiMethod::Auto => {
            let turning = motion_a.angvel != Vector3::zeros() || motion_b.angvel != Vector3::zeros();
            let castable = !matches!(a, Shape::HalfSpace { .. }) && !matches!(b, Shape::HalfSpace { .. });
            if turning && castable {
                ToiMethod::ShapeCast
            } else {
                ToiMethod::ConservativeAdvancement
            }
        }
        m => m,
    };
    match method {
        ToiMethod::Bisection => by_bisection(a, motion_a, b, motion_b, t_end, closing, d0, options),
        ToiMethod::ConservativeAdvancement | ToiMethod::Auto => {
            by_advancement(a, motion_a, b, motion_b, t_end, closing, d0, options)
        }
        ToiMethod::ShapeCast => by_shape_cast(a, motion_a, b, motion_b, t_end),
    }
}

#[allow(clippy::too_many_arguments)]
fn by_bisection(
    a: &Shape,
    motion_a: &Motion,
    b: &Shape,
    motion_b: &Motion,
    t_end: f64,
    closing: f64,
    d0: f64,
    options: &ToiOptions,
) -> Result<Option<Impact>, ShapeError> {
    let mut poses = |t: f64| Ok((motion_a.pose_at(t), motion_b.pose_at(t)));
    let mut search = Search { a, b, poses: &mut poses, closing, options, queries: 1 };
    let d_end = search.distance(t_end)?;
    search.first_contact(0.0, d0, t_end, d_end)
}

/// The first contact in [t0, t1] of two shapes moving along any path (an integrator's dense output, say):
/// `poses(t)` gives both poses, and `closing` bounds how fast their distance can shrink (m/s). The pair must be
/// apart at t0. The same search as `ToiMethod::Bisection`: halve only where the distances at the ends leave room
/// for a contact, then bisect the first interval that ends in contact to `options.tolerance`.
pub fn first_contact(
    a: &Shape,
    b: &Shape,
    mut poses: impl FnMut(f64) -> Result<(Isometry3<f64>, Isometry3<f64>), ShapeError>,
    t0: f64,
    t1: f64,
    closing: f64,
    options: &ToiOptions,
) -> Result<Option<Impact>, ShapeError> {
    positive("tolerance", options.tolerance)?;
    if !(t0.is_finite() && t1.is_finite() && t1 >= t0) {
        return Err(ShapeError::new("t1", format!("the interval [{t0}, {t1}] must be finite with t1 >= t0")));
    }
    if !(closing.is_finite() && closing >= 0.0) {
        return Err(ShapeError::new("closing", format!("must be finite and >= 0, got {closing}")));
    }
    let mut search = Search { a, b, poses: &mut poses, closing, options, queries: 0 };
    let d0 = search.distance(t0)?;
    if d0 <= 0.0 {
        return Err(ShapeError::new("t0", format!("the shapes are already in contact at t0 = {t0}")));
    }
    let d1 = search.distance(t1)?;
    search.first_contact(t0, d0, t1, d1)
}

type Poses<'p> = dyn FnMut(f64) -> Result<(Isometry3<f64>, Isometry3<f64>), ShapeError> + 'p;

/// The bisection search, with its query count.
struct Search<'s, 'p> {
    a: &'s Shape,
    b: &'s Shape,
    poses: &'s mut Poses<'p>,
    closing: f64,
    options: &'s ToiOptions,
    queries: usize,
}

impl Search<'_, '_> {
    fn distance(&mut self, t: f64) -> Result<f64, ShapeError> {
        self.queries += 1;
        if self.queries > self.options.max_iterations {
            return Err(ShapeError::new(
                "options",
                format!("bisection needed more than {} queries", self.options.max_iterations),
            ));
        }
        let (pa, pb) = (self.poses)(t)?;
        distance(self.a, &pa, self.b, &pb)
    }

    /// The first contact in [lo, hi], the pair being `d_lo` > 0 apart at lo and `d_hi` >= 0 at hi. In contact at
    /// hi: the chapter's bisection. Apart at both ends: a contact inside is possible only if the gaps can close in
    /// time, d_lo + d_hi <= closing (hi - lo); if so, halve and look left first.
    fn first_contact(&mut self, lo: f64, d_lo: f64, hi: f64, d_hi: f64) -> Result<Option<Impact>, ShapeError> {
        let tol = self.options.tolerance;
        if d_hi <= 0.0 {
            let (before, _) = halve(lo, hi, tol, |t| Ok(self.distance(t)? <= 0.0))?;
            let d = if before == lo { d_lo } else { self.distance(before)? };
            return Ok(Some(Impact { time: before, distance: d, iterations: self.queries }));
        }
        if d_lo + d_hi > self.closing * (hi - lo) {
            return Ok(None);
        }
        if hi - lo <= tol {
            // Within the tolerance the pair comes closer than closing * tolerance: a touch.
            return Ok(Some(Impact { time: lo, distance: d_lo, iterations: self.queries }));
        }
        let mid = 0.5 * (lo + hi);
        let d_mid = self.distance(mid)?;
        match self.first_contact(lo, d_lo, mid, d_mid)? {
            Some(hit) => Ok(Some(hit)),
            None => self.first_contact(mid, d_mid, hi, d_hi),
        }
    }
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
            &motion_a.as_parry(&va),
            va.as_dyn(),
            &motion_b.as_parry(&vb),
            vb.as_dyn(),
            0.0,
            t_end,
            true,
        )
        .map_err(|_| unsupported_pair(a, b))?;
    let Some(hit) = hit else { return Ok(None) };
    // parry reports `Failed` when its last advance lands the pair exactly in contact; that is a hit. Only running
    // out of iterations leaves the time unknown.
    if hit.status == ShapeCastStatus::OutOfIterations {
        return Err(ShapeError::new("options", "parry's shape cast ran out of iterations"));
    }
    let t = hit.time_of_impact;
    let d = distance(a, &motion_a.pose_at(t), b, &motion_b.pose_at(t))?;
    Ok(Some(Impact { time: t, distance: d, iterations: 0 }))
}

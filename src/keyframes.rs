//! A kinematic body's path: poses at keyframe times, followed whatever touches the body. Between two keyframes the
//! body moves at one velocity and turns at one angular velocity (position linear in time, orientation the shortest
//! turn at a constant rate: slerp); before the first keyframe and after the last it holds still.

use crate::error::WorldError;
use crate::limits;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Keyframed poses of a kinematic body's frame (its shapes' frame: the body's `position` and `orientation`).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframes {
    times: Vec<f64>,
    positions: Vec<Vector3<f64>>,
    orientations: Vec<UnitQuaternion<f64>>,
}

impl Keyframes {
    /// Keyframes at increasing `times` (s), with a position (m) for each and an orientation for each (or none: the
    /// identity throughout). At least one keyframe; times strictly increasing.
    pub fn new(
        times: Vec<f64>,
        positions: Vec<Vector3<f64>>,
        orientations: Option<Vec<UnitQuaternion<f64>>>,
    ) -> Result<Keyframes, WorldError> {
        if times.is_empty() {
            return Err(WorldError::invalid("times", "a path needs at least one keyframe"));
        }
        if positions.len() != times.len() {
            return Err(WorldError::invalid(
                "positions",
                format!("{} positions for {} keyframe times", positions.len(), times.len()),
            ));
        }
        for (k, t) in times.iter().enumerate() {
            limits::in_range("times", *t, -limits::TIME, limits::TIME, "s")?;
            if k > 0 && !(*t > times[k - 1]) {
                return Err(WorldError::invalid(
                    "times",
                    format!("keyframe times must increase: {} follows {}", t, times[k - 1]),
                ));
            }
        }
        for p in &positions {
            limits::vector("positions", p, limits::COORDINATE, "m")?;
        }
        let orientations = match orientations {
            None => vec![UnitQuaternion::identity(); times.len()],
            Some(q) if q.len() == times.len() => q,
            Some(q) => {
                return Err(WorldError::invalid(
                    "orientations",
                    format!("{} orientations for {} keyframe times", q.len(), times.len()),
                ))
            }
        };
        if orientations.iter().any(|q| !q.coords.iter().all(|c| c.is_finite())) {
            return Err(WorldError::invalid("orientations", "every orientation must be finite"));
        }
        let path = Keyframes { times, positions, orientations };
        for k in 0..path.times.len().saturating_sub(1) {
            let (v, w) = path.segment_velocity(k);
            limits::vector("positions", &v, limits::SPEED, "m/s between keyframes")?;
            limits::vector("orientations", &w, limits::SPEED, "rad/s between keyframes")?;
        }
        Ok(path)
    }

    /// The keyframe times (s).
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The keyframe positions (m).
    pub fn positions(&self) -> &[Vector3<f64>] {
        &self.positions
    }

    /// The keyframe orientations.
    pub fn orientations(&self) -> &[UnitQuaternion<f64>] {
        &self.orientations
    }

    /// The segment the body moves along just after time t (keyframes k and k + 1), or `None` where it holds
    /// still (before the first keyframe or from the last on). A time within `slack` of a keyframe counts as it.
    fn segment(&self, t: f64) -> Option<usize> {
        let t = t + slack(t);
        let k = self.times.partition_point(|&tk| tk <= t);
        (k >= 1 && k < self.times.len()).then(|| k - 1)
    }

    /// Velocity and angular velocity (world axes) along segment k.
    fn segment_velocity(&self, k: usize) -> (Vector3<f64>, Vector3<f64>) {
        let dt = self.times[k + 1] - self.times[k];
        let turn = self.orientations[k + 1] * self.orientations[k].inverse();
        ((self.positions[k + 1] - self.positions[k]) / dt, turn.scaled_axis() / dt)
    }

    /// The pose at time t.
    pub fn pose_at(&self, t: f64) -> Isometry3<f64> {
        let last = self.times.len() - 1;
        let (x, q) = if t <= self.times[0] {
            (self.positions[0], self.orientations[0])
        } else if t >= self.times[last] {
            (self.positions[last], self.orientations[last])
        } else {
            let k = self.times.partition_point(|&tk| tk <= t) - 1;
            let (v, w) = self.segment_velocity(k);
            let s = t - self.times[k];
            (self.positions[k] + v * s, UnitQuaternion::from_scaled_axis(w * s) * self.orientations[k])
        };
        Isometry3::from_parts(Translation3::from(x), q)
    }

    /// Velocity and angular velocity (world axes) just after time t: zero where the body holds still.
    pub fn velocity_at(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        self.segment(t).map_or((Vector3::zeros(), Vector3::zeros()), |k| self.segment_velocity(k))
    }

    /// Velocity and angular velocity (world axes) just before time t: the motion the body has coming to t (zero
    /// before the first keyframe and after the last).
    pub fn velocity_before(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let last = self.times.len() - 1;
        if t <= self.times[0] || t > self.times[last] {
            return (Vector3::zeros(), Vector3::zeros());
        }
        self.segment_velocity(self.times.partition_point(|&tk| tk < t) - 1)
    }

    /// The velocities that take the body from its pose at t to its pose at t + h in a step of h (fast mode's: the
    /// step lands on the path whatever keyframes it crosses).
    pub fn step_velocity(&self, t: f64, h: f64) -> (Vector3<f64>, Vector3<f64>) {
        let (a, b) = (self.pose_at(t), self.pose_at(t + h));
        let turn = b.rotation * a.rotation.inverse();
        ((b.translation.vector - a.translation.vector) / h, turn.scaled_axis() / h)
    }

    /// The first keyframe time after t (beyond `slack`), where the velocity may change.
    pub fn next_time_after(&self, t: f64) -> Option<f64> {
        let t = t + slack(t);
        self.times.iter().copied().find(|&tk| tk > t)
    }

    /// Whether the body still has moving to do after time t.
    pub fn moves_after(&self, t: f64) -> bool {
        let t = t + slack(t);
        (0..self.times.len() - 1).any(|k| {
            let (v, w) = self.segment_velocity(k);
            self.times[k + 1] > t && (v != Vector3::zeros() || w != Vector3::zeros())
        })
    }
}

/// Times this close to a keyframe count as at it (the steps that land on a keyframe land within an ulp or two).
fn slack(t: f64) -> f64 {
    1e-12 * t.abs().max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path() -> Keyframes {
        let q1 = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 1.0));
        Keyframes::new(
            vec![1.0, 3.0, 4.0],
            vec![Vector3::zeros(), Vector3::new(2.0, 0.0, 0.0), Vector3::new(2.0, 0.0, 0.0)],
            Some(vec![UnitQuaternion::identity(), q1, q1]),
        )
        .unwrap()
    }

    #[test]
    fn poses_interpolate_linearly_and_turn_at_a_constant_rate() {
        let p = path();
        // halfway along the first segment: half the displacement and half the turn (exact up to rounding)
        let mid = p.pose_at(2.0);
        assert!((mid.translation.vector - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-15);
        assert!((mid.rotation.angle() - 0.5).abs() < 1e-15);
        assert_eq!(p.velocity_at(2.0).0, Vector3::new(1.0, 0.0, 0.0));
        assert!((p.velocity_at(2.0).1 - Vector3::new(0.0, 0.0, 0.5)).norm() < 1e-15);
        // before the first keyframe and after the last it holds still
        assert_eq!(p.pose_at(0.0), p.pose_at(1.0));
        assert_eq!(p.velocity_at(0.0).0, Vector3::zeros());
        assert_eq!(p.velocity_at(5.0).0, Vector3::zeros());
        // at a keyframe the velocity is the next segment's
        assert_eq!(p.velocity_at(1.0).0, Vector3::new(1.0, 0.0, 0.0));
        assert_eq!(p.velocity_at(3.0).0, Vector3::zeros());
        assert_eq!(p.next_time_after(1.0), Some(3.0));
        assert_eq!(p.next_time_after(4.0), None);
        assert!(p.moves_after(0.0) && p.moves_after(2.0) && !p.moves_after(3.0));
    }

    #[test]
    fn a_step_across_a_keyframe_lands_on_the_path() {
        let p = path();
        let (v, _) = p.step_velocity(2.5, 1.0);
        // from x = 1.5 at 2.5 s to x = 2 at 3.5 s
        assert!((v - Vector3::new(0.5, 0.0, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn bad_keyframes_name_their_argument() {
        let x = Vector3::zeros();
        let name = |r: Result<Keyframes, WorldError>| r.unwrap_err().argument();
        assert_eq!(name(Keyframes::new(vec![], vec![], None)), Some("times"));
        assert_eq!(name(Keyframes::new(vec![1.0, 1.0], vec![x, x], None)), Some("times"));
        assert_eq!(name(Keyframes::new(vec![f64::NAN], vec![x], None)), Some("times"));
        assert_eq!(name(Keyframes::new(vec![0.0], vec![x, x], None)), Some("positions"));
        assert_eq!(
            name(Keyframes::new(vec![0.0], vec![Vector3::new(f64::INFINITY, 0.0, 0.0)], None)),
            Some("positions")
        );
        assert_eq!(name(Keyframes::new(vec![0.0], vec![x], Some(vec![]))), Some("orientations"));
        assert_eq!(
            name(Keyframes::new(vec![0.0, 1e-30], vec![x, Vector3::new(1.0, 0.0, 0.0)], None)),
            Some("positions")
        );
    }
}

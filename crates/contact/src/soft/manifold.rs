//! What the soft step solves a body pair's contact by: a manifold, its points (up to four) with their normal
//! impulses, its friction impulses (at the friction centre, and the twist about the normal), and its colour in the
//! constraint graph (`graph.rs`). The caller keeps manifolds from step to step: the impulses go in as the last
//! step's (the warm start) and come out as this step's.

use crate::body::BodyState;
use crate::error::ContactError;
use nalgebra::{Point3, Vector3};

/// Points of a manifold (parry's manifolds are reduced to four).
pub const MANIFOLD_POINTS: usize = 4;

/// One contact point of a manifold.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftPoint {
    /// Where the bodies touch (world, at the step's start).
    pub point: Point3<f64>,
    /// Unit normal from A toward B.
    pub normal: Vector3<f64>,
    /// Gap along the normal at the step's start (negative: overlapping).
    pub gap: f64,
    /// Its normal impulse over a substep: the last step's on the way in, this step's last substep's on the way out
    /// (none out for a point that closed faster than the bounce threshold and pushed: an impact's impulse stopped
    /// an approach that is over, and as the next step's start it pushed the struck body on into its neighbours).
    pub normal_impulse: f64,
    /// Its normal impulse over the whole step (out).
    pub step_normal: f64,
}

/// A body pair's contact points as one constraint of the soft step.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, PartialEq)]
pub struct SoftManifold {
    /// The bodies (indices into the step's bodies); the normals point from A toward B.
    pub a: usize,
    pub b: usize,
    /// Its colour in the constraint graph (`ColourGraph::add`): manifolds of one colour other than the overflow
    /// colour must share no moving body.
    pub colour: u32,
    pub friction: f64,
    pub restitution: f64,
    /// Its points (the first `count`).
    pub points: [SoftPoint; MANIFOLD_POINTS],
    pub count: usize,
    /// Its friction impulse over a substep (a world vector, so that it carries to the next step's tangents) and its
    /// twist impulse about the normal: in and out as the points' normal impulses (none out after an impact).
    pub tangent_impulse: Vector3<f64>,
    pub twist_impulse: f64,
    /// Coefficients of rolling and torsional resistance (as `Contact`'s), and its rolling impulse over a substep
    /// (an angular impulse on B, a world vector; in and out as the friction impulse).
    #[serde(default)]
    pub rolling_resistance: f64,
    #[serde(default)]
    pub torsional_resistance: f64,
    #[serde(default)]
    pub rolling_impulse: Vector3<f64>,
}

impl SoftManifold {
    /// A manifold between `a` and `b` with no points and no colour.
    pub fn new(a: usize, b: usize, friction: f64, restitution: f64) -> SoftManifold {
        SoftManifold {
            a,
            b,
            colour: super::graph::UNCOLOURED,
            friction,
            restitution,
            points: [SoftPoint::default(); MANIFOLD_POINTS],
            count: 0,
            tangent_impulse: Vector3::zeros(),
            twist_impulse: 0.0,
            rolling_resistance: 0.0,
            torsional_resistance: 0.0,
            rolling_impulse: Vector3::zeros(),
        }
    }

    /// With these coefficients of rolling and torsional resistance.
    pub fn with_resistance(mut self, rolling: f64, torsional: f64) -> SoftManifold {
        self.rolling_resistance = rolling;
        self.torsional_resistance = torsional;
        self
    }

    /// Its points.
    pub fn points(&self) -> &[SoftPoint] {
        &self.points[..self.count]
    }

    /// Checks it against the bodies: bodies in range and distinct, one of them moving, a colour, materials and every
    /// number of its points finite, normals of unit length, friction and restitution not negative; `index` names it.
    pub(crate) fn check(&self, index: usize, bodies: &[BodyState]) -> Result<(), ContactError> {
        let bad = |reason: String| Err(ContactError::invalid("manifolds", format!("manifold {index}: {reason}")));
        if self.a >= bodies.len() || self.b >= bodies.len() || self.a == self.b {
            return bad(format!("joins bodies {} and {} of {}", self.a, self.b, bodies.len()));
        }
        if !(bodies[self.a].is_dynamic() || bodies[self.b].is_dynamic()) {
            return bad("joins two bodies that do not move".into());
        }
        if self.count > MANIFOLD_POINTS {
            return bad(format!("has {} points, at most {MANIFOLD_POINTS}", self.count));
        }
        if self.colour > super::graph::OVERFLOW && self.count > 0 {
            return bad("has points and no colour".into());
        }
        if !(self.rolling_resistance >= 0.0 && self.torsional_resistance >= 0.0) {
            return bad(format!(
                "rolling resistance {} and torsional resistance {}",
                self.rolling_resistance, self.torsional_resistance
            ));
        }
        if !(self.friction >= 0.0 && self.friction.is_finite() && self.restitution >= 0.0 && self.restitution <= 1.0) {
            return bad(format!("friction {} and restitution {}", self.friction, self.restitution));
        }
        // one sum of every number: finite only if each is (a sum of finite numbers can overflow, and is refused too)
        let t = &self.tangent_impulse;
        let r = &self.rolling_impulse;
        let mut sum = t.x + t.y + t.z + self.twist_impulse + r.x + r.y + r.z;
        sum += self.rolling_resistance + self.torsional_resistance;
        let mut unit = true;
        for p in self.points() {
            let n = &p.normal;
            sum += p.point.x + p.point.y + p.point.z + n.x + n.y + n.z + p.gap + p.normal_impulse;
            unit &= (n.norm_squared() - 1.0).abs() <= 1e-6;
        }
        if !sum.is_finite() {
            return bad("a point or an impulse has a number that is not finite".into());
        }
        if !unit {
            return bad("a point's normal is not of unit length".into());
        }
        Ok(())
    }
}

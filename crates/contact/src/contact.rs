//! A contact as the solvers take it: the two bodies, the point and the normal (from A toward B), the gap, the
//! material coefficients and how the normal turns with the bodies.

use crate::body::BodyState;
use crate::error::ContactError;
use nalgebra::{Point3, Unit, Vector3};

/// How a contact normal turns as the bodies move, for the n' term of the normal acceleration.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub enum NormalMotion {
    /// The normal belongs to a face of A (a face-vertex contact): n' = w_a x n.
    WithA,
    /// The normal belongs to a face of B (a vertex-face contact, or any contact on a static ground): n' = w_b x n.
    WithB,
    /// The normal is the cross product of an edge of A and an edge of B (world unit directions): it turns with both.
    EdgeEdge { edge_a: Unit<Vector3<f64>>, edge_b: Unit<Vector3<f64>> },
    /// The normal runs between the centres of mass (two spheres): n = (x_b - x_a) / |x_b - x_a|.
    BetweenCentres,
}

/// One contact between bodies `a` and `b` (indices into the bodies slice).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Body A.
    pub a: usize,
    /// Body B.
    pub b: usize,
    /// The contact point (world).
    pub point: Point3<f64>,
    /// Unit normal from A toward B. Forces and impulses push B along it and A against it.
    pub normal: Unit<Vector3<f64>>,
    /// Signed gap along the normal (negative: interpenetrating), for the time-stepping bias.
    pub distance: f64,
    /// Coefficient of restitution in [0, 1].
    pub restitution: f64,
    /// Coefficient of friction >= 0.
    pub friction: f64,
    /// How the normal turns.
    pub normal_motion: NormalMotion,
    /// Coefficients of rolling and torsional resistance (>= 0, dimensionless): the contact resists the bodies'
    /// relative turn across its normal (rolling) and about it (torsion) with a torque of at most the coefficient
    /// times the normal force times the rolling radius, the distance along the normal from the contact point to the
    /// centre of mass of the turning body (the farther one's where both turn; a ball's radius). Zero: none.
    #[serde(default)]
    pub rolling_resistance: f64,
    #[serde(default)]
    pub torsional_resistance: f64,
}

impl Contact {
    /// A frictionless, perfectly inelastic contact at zero gap whose normal belongs to B.
    pub fn new(a: usize, b: usize, point: Point3<f64>, normal: Unit<Vector3<f64>>) -> Contact {
        Contact {
            a,
            b,
            point,
            normal,
            distance: 0.0,
            restitution: 0.0,
            friction: 0.0,
            normal_motion: NormalMotion::WithB,
            rolling_resistance: 0.0,
            torsional_resistance: 0.0,
        }
    }

    /// With these coefficients of rolling and torsional resistance.
    pub fn with_resistance(mut self, rolling: f64, torsional: f64) -> Contact {
        self.rolling_resistance = rolling;
        self.torsional_resistance = torsional;
        self
    }

    /// The rolling radius (m): the distance along the normal from the point to the centre of mass of the farther of
    /// the two bodies that turn (zero if neither turns).
    pub fn rolling_radius(&self, bodies: &[BodyState]) -> f64 {
        [self.a, self.b]
            .into_iter()
            .filter(|&k| bodies[k].is_dynamic() && bodies[k].rotates())
            .map(|k| self.normal.dot(&(self.point - bodies[k].position)).abs())
            .fold(0.0, f64::max)
    }

    /// With this coefficient of restitution.
    pub fn with_restitution(mut self, e: f64) -> Contact {
        self.restitution = e;
        self
    }

    /// With this coefficient of friction.
    pub fn with_friction(mut self, mu: f64) -> Contact {
        self.friction = mu;
        self
    }

    /// With this signed gap.
    pub fn with_distance(mut self, d: f64) -> Contact {
        self.distance = d;
        self
    }

    /// With this normal motion.
    pub fn with_normal_motion(mut self, m: NormalMotion) -> Contact {
        self.normal_motion = m;
        self
    }

    /// The relative normal velocity n . (v_B(p) - v_A(p)): positive separating, negative colliding (the chapter's
    /// v_rel with A and B named the other way round).
    pub fn relative_normal_velocity(&self, bodies: &[BodyState]) -> f64 {
        self.normal.dot(&(bodies[self.b].point_velocity(&self.point) - bodies[self.a].point_velocity(&self.point)))
    }

    /// The rate of change of the normal.
    #[cfg(feature = "clarabel")]
    pub(crate) fn normal_rate(&self, bodies: &[BodyState]) -> Vector3<f64> {
        let (a, b) = (&bodies[self.a], &bodies[self.b]);
        let n = self.normal.into_inner();
        match self.normal_motion {
            NormalMotion::WithA => a.angular_velocity.cross(&n),
            NormalMotion::WithB => b.angular_velocity.cross(&n),
            NormalMotion::EdgeEdge { edge_a, edge_b } => {
                let c = edge_a.cross(&edge_b);
                let len = c.norm();
                let c_dot =
                    a.angular_velocity.cross(&edge_a).cross(&edge_b) + edge_a.cross(&b.angular_velocity.cross(&edge_b));
                // n = s c / |c| with s = +-1 fixed by the given normal; n' = s (c' - (c'.u) u) / |c|, u = c / |c|.
                let u = c / len;
                let s = n.dot(&u).signum();
                s * (c_dot - u * c_dot.dot(&u)) / len
            }
            NormalMotion::BetweenCentres => {
                let d = b.position - a.position;
                let dv = b.velocity - a.velocity;
                (dv - n * n.dot(&dv)) / d.norm()
            }
        }
    }

    /// Checks the contact against the bodies; `index` names it in the error.
    pub(crate) fn check(&self, index: usize, bodies: &[BodyState]) -> Result<(), ContactError> {
        let bad = |reason: String| Err(ContactError::invalid("contacts", format!("contact {index}: {reason}")));
        if self.a >= bodies.len() || self.b >= bodies.len() {
            return bad(format!("bodies {} and {} must be below {}", self.a, self.b, bodies.len()));
        }
        if self.a == self.b {
            return bad(format!("both sides are body {}", self.a));
        }
        let n = self.normal.into_inner();
        if !(self.point.iter().chain(n.iter()).all(|v| v.is_finite()) && self.distance.is_finite()) {
            return bad("a non-finite point, normal or distance".into());
        }
        if (n.norm() - 1.0).abs() > 1e-9 {
            return bad(format!("the normal must be a unit vector, its length is {}", n.norm()));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return bad(format!("restitution must be in [0, 1], got {}", self.restitution));
        }
        if !(self.friction.is_finite() && self.friction >= 0.0) {
            return bad(format!("friction must be finite and >= 0, got {}", self.friction));
        }
        for (name, v) in
            [("rolling_resistance", self.rolling_resistance), ("torsional_resistance", self.torsional_resistance)]
        {
            if !(v.is_finite() && v >= 0.0) {
                return bad(format!("{name} must be finite and >= 0, got {v}"));
            }
        }
        if let NormalMotion::EdgeEdge { edge_a, edge_b } = self.normal_motion {
            if edge_a.cross(&edge_b).norm() < 1e-9 {
                return bad("the two edges of an edge-edge contact are parallel".into());
            }
        }
        if !bodies[self.a].is_dynamic() && !bodies[self.b].is_dynamic() {
            return bad("both bodies are static".into());
        }
        Ok(())
    }
}

/// Checks bodies and contacts together.
pub(crate) fn check_all(bodies: &[BodyState], contacts: &[Contact]) -> Result<(), ContactError> {
    for (i, b) in bodies.iter().enumerate() {
        b.check(i)?;
    }
    for (i, c) in contacts.iter().enumerate() {
        c.check(i, bodies)?;
    }
    Ok(())
}

/// Two unit tangents completing the normal to a right-handed frame (t1, t2, n).
pub(crate) fn tangents(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let seed = if n.x.abs() < 0.6 { Vector3::x() } else { Vector3::y() };
    let t1 = seed.cross(n).normalize();
    (t1, n.cross(&t1))
}

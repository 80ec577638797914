//! A damped Hooke spring between two points: the one spring law of tumble, used by the equations of motion (the
//! world's springs as forces) and by the soft step (springs evaluated at every substep). Its force on the first
//! point is -n (stiffness (l - rest_length) + damping n . (v_a - v_b)), with l the points' distance and n the unit
//! vector from the second point to the first; the second point feels the opposite.

use nalgebra::Vector3;

/// Stiffness (N/m), damping (N s/m) and rest length (m) of a spring.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpringLaw {
    /// N/m, >= 0.
    pub stiffness: f64,
    /// N s/m, >= 0.
    pub damping: f64,
    /// m, >= 0.
    pub rest_length: f64,
}

/// Below this distance (m) the two points coincide and the spring has no direction: it pushes on neither.
pub const COINCIDENT: f64 = 1e-300;

impl SpringLaw {
    /// The force on the first point, at `pa` moving at `va`, from the second at `pb` moving at `vb`; `None` when
    /// the points coincide.
    #[inline]
    pub fn force(
        &self,
        pa: &Vector3<f64>,
        va: &Vector3<f64>,
        pb: &Vector3<f64>,
        vb: &Vector3<f64>,
    ) -> Option<Vector3<f64>> {
        let d = pa - pb;
        let len = d.norm();
        if len <= COINCIDENT {
            return None;
        }
        let n = d / len;
        Some(-n * (self.stiffness * (len - self.rest_length) + self.damping * (va - vb).dot(&n)))
    }

    /// The potential energy at a distance `length` between the points (J).
    #[inline]
    pub fn energy(&self, length: f64) -> f64 {
        0.5 * self.stiffness * (length - self.rest_length).powi(2)
    }

    /// Whether every number is finite and none is negative.
    pub fn is_valid(&self) -> bool {
        [self.stiffness, self.damping, self.rest_length].iter().all(|x| x.is_finite() && *x >= 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stretched_spring_pulls_and_its_damper_resists_the_opening() {
        let law = SpringLaw { stiffness: 100.0, damping: 2.0, rest_length: 1.0 };
        let (pa, pb) = (Vector3::new(1.5, 0.0, 0.0), Vector3::zeros());
        // 0.5 m too long: -100 * 0.5 along +x; opening at 3 m/s: another -2 * 3
        let f = law.force(&pa, &Vector3::new(3.0, 1.0, 0.0), &pb, &Vector3::zeros()).unwrap();
        assert_eq!(f, Vector3::new(-56.0, 0.0, 0.0));
        assert_eq!(law.energy(1.5), 12.5);
        assert!(law.force(&pb, &Vector3::zeros(), &pb, &Vector3::zeros()).is_none());
    }
}

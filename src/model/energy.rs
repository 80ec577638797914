//! Energy and momenta of a state: kinetic energy of particles and bodies (1/2 m v^2, 1/2 P^2 / M + 1/2 L . w);
//! potential energy of gravity, springs and the particles' restoring terms; linear momentum; angular momentum
//! about the origin. Kinematic bodies, which nothing pushes, carry none of them.

use crate::model::layout::{get3, get_quat};
use crate::model::Model;
use nalgebra::{UnitQuaternion, Vector3};

/// A body's kinetic energy from its momenta (P, and L turned into its frame): 1/2 P^2 / M + 1/2 L . w, where
/// L . w = (R^T L) . I_body^-1 (R^T L).
fn momentum_form(b: &crate::model::BodyProps, p: Vector3<f64>, local: Vector3<f64>) -> f64 {
    0.5 * p.norm_squared() * b.inv_mass + 0.5 * local.dot(&(b.inv_inertia * local))
}

impl Model {
    pub(crate) fn kinetic_energy(&self, y: &[f64]) -> f64 {
        self.kinetic(y, momentum_form)
    }

    /// The kinetic energy of one actor (a particle, then the bodies in order; a kinematic body carries none) in
    /// state y.
    pub(crate) fn actor_kinetic_energy(&self, y: &[f64], actor: usize) -> f64 {
        self.actor_kinetic(y, actor, &momentum_form)
    }

    /// The kinetic energy of state y, each body's from `body(props, its linear block, its angular block turned into the
    /// body's frame)`: the particles' 1/2 m v^2 and the bodies' (kinematic bodies carry none).
    pub(super) fn kinetic(
        &self,
        y: &[f64],
        body: impl Fn(&crate::model::BodyProps, Vector3<f64>, Vector3<f64>) -> f64,
    ) -> f64 {
        let l = self.layout;
        let particles: f64 = (0..l.particles).map(|i| self.actor_kinetic(y, i, &body)).sum();
        let bodies: f64 = (0..l.bodies).map(|j| self.actor_kinetic(y, l.body_actor(j), &body)).sum();
        particles + bodies
    }

    /// One actor's share of `kinetic`.
    fn actor_kinetic(
        &self,
        y: &[f64],
        actor: usize,
        body: &impl Fn(&crate::model::BodyProps, Vector3<f64>, Vector3<f64>) -> f64,
    ) -> f64 {
        let l = self.layout;
        if actor < l.particles {
            return 0.5 * self.particles[actor].mass * get3(y, l.pv(actor)).norm_squared();
        }
        let j = actor - l.particles;
        if self.bodies[j].kinematic.is_some() {
            return 0.0;
        }
        let q = UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
        let local = q.inverse_transform_vector(&get3(y, l.bl(j)));
        body(&self.bodies[j], get3(y, l.bp(j)), local)
    }

    pub(crate) fn potential_energy(&self, y: &[f64]) -> f64 {
        let l = self.layout;
        let mut u = 0.0;
        for (i, p) in self.particles.iter().enumerate() {
            let x = get3(y, l.px(i));
            u -= p.mass * self.gravity.dot(&x);
            u += 0.5 * p.stiffness * (x - p.anchor).norm_squared();
        }
        for (j, b) in self.bodies.iter().enumerate().filter(|(_, b)| b.kinematic.is_none()) {
            u -= b.mass * self.gravity.dot(&get3(y, l.bx(j)));
        }
        if self.springs.is_empty() {
            return u;
        }
        let kin: Vec<_> = (0..l.bodies).map(|j| self.body_kin(y, j)).collect();
        for s in &self.springs {
            let (pa, _, _) = self.end_state(&kin, y, s.a);
            let (pb, _, _) = self.end_state(&kin, y, s.b);
            u += s.law.energy((pa - pb).norm());
        }
        u
    }

    pub(crate) fn momentum(&self, y: &[f64]) -> Vector3<f64> {
        let l = self.layout;
        let p: Vector3<f64> = self.particles.iter().enumerate().map(|(i, p)| get3(y, l.pv(i)) * p.mass).sum();
        p + self.free_bodies().map(|j| get3(y, l.bp(j))).sum::<Vector3<f64>>()
    }

    pub(crate) fn angular_momentum(&self, y: &[f64]) -> Vector3<f64> {
        let l = self.layout;
        let p: Vector3<f64> =
            self.particles.iter().enumerate().map(|(i, p)| get3(y, l.px(i)).cross(&(get3(y, l.pv(i)) * p.mass))).sum();
        p + self
            .free_bodies()
            .map(|j| get3(y, l.bx(j)).cross(&get3(y, l.bp(j))) + get3(y, l.bl(j)))
            .sum::<Vector3<f64>>()
    }
}

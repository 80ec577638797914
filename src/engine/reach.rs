//! How far the actors of a collider set can move in a step: each actor's reach at its velocities (the margin its
//! boxes grow by in the broad phase, and the speeds sleep and the contact steps judge by).

use crate::engine::collider_set::ColliderSet;

impl ColliderSet {
    /// Each actor's radius: of a ball about its origin that holds all its colliders (infinite with a half-space).
    fn radii(&self) -> Vec<f64> {
        let mut radius = vec![0.0f64; self.actors()];
        for c in &self.colliders {
            let a = self.index(c.actor);
            radius[a] = radius[a].max(c.reach);
        }
        radius
    }

    /// Each actor's reach (`reach`) and the part of it its spin gives (w r h).
    pub fn reach_and_spin(&self, states: &[tumble_contact::BodyState], h: f64) -> (Vec<f64>, Vec<f64>) {
        let radius = self.radii();
        let spin: Vec<f64> = states
            .iter()
            .zip(&radius)
            .map(|(s, r)| {
                let w = s.angular_velocity.norm();
                if w > 0.0 && r.is_finite() {
                    w * r * h
                } else {
                    0.0
                }
            })
            .collect();
        let reach = states.iter().zip(&spin).map(|(s, spin)| s.velocity.norm() * h + spin).collect();
        (reach, spin)
    }

    /// How far any point of each actor can travel in time `h` at the velocities of `states` (one per actor):
    /// (|v| + |w| r) h, r the radius of a ball about the actor's origin that holds its colliders.
    pub fn reach(&self, states: &[tumble_contact::BodyState], h: f64) -> Vec<f64> {
        let radius = self.radii();
        states
            .iter()
            .zip(&radius)
            .map(|(s, r)| {
                let w = s.angular_velocity.norm();
                let spin = if w > 0.0 && r.is_finite() { w * r } else { 0.0 };
                (s.velocity.norm() + spin) * h
            })
            .collect()
    }
}

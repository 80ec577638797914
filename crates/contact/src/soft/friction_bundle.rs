//! A bundle's friction: each lane's manifold friction at its friction centre, its twist and its rolling
//! resistance, with their impulses of the current substep and summed over the step.

use super::bundle::{AxisLanes, Lanes, Zeroed, P, W};
use nalgebra::Vector3;

/// Each lane's manifold friction, at its friction centre (Box3D's, Rapier's simplified and Jolt's newer friction):
/// two tangent rows through the centre, bounded together by mu times the manifold's normal impulse (Coulomb's
/// circle), and a twist row about the manifold's normal, bounded by mu times each point's normal impulse times its
/// lever arm from the centre, summed.
#[derive(Clone, Debug, Default)]
pub(crate) struct FrictionBundle {
    pub axes: [AxisLanes; 2],
    /// The inverse of the two tangent rows' 2 x 2 K (its entries 00, 01, 11): they are solved as one block, so that
    /// an update stops the centre's slip exactly (two rows coupled through the bodies' turn, updated one beside
    /// the other, overshoot and can gain energy).
    pub block: [Lanes; 3],
    pub tangent: [Lanes; 2],
    /// The twist row: no linear part, its angular Jacobian the normal (`ca` = `cb`).
    pub twist_axis: AxisLanes,
    pub twist: Lanes,
    pub friction: Lanes,
    /// Each point's distance from the friction centre.
    pub lever: [Lanes; P],
    /// Whether a lane resists rolling or torsion (`resistance`); the rest of the fields are then used.
    pub resists: bool,
    /// Rolling and torsional resistance: each coefficient times the lane's rolling radius (m), bounding the
    /// angular impulses by it times the manifold's normal impulse; torsion widens the twist's bound.
    pub rolling: Lanes,
    pub torsion: Lanes,
    /// The rolling rows: angular alone, about the two tangents (`ca` = `cb`), solved as one block (`roll_block`,
    /// as `block`) within the disc of `rolling` times the normal impulse.
    pub roll_axes: [AxisLanes; 2],
    pub roll_block: [Lanes; 3],
    pub roll: [Lanes; 2],
    /// The tangent, twist and rolling impulses summed over the step's substeps so far, each substep's weighed by
    /// the lane's decay once a later substep (`end_substep`).
    pub step_tangent: [Lanes; 2],
    pub step_twist: Lanes,
    pub step_roll: [Lanes; 2],
}

impl FrictionBundle {
    /// Lane `l`'s friction impulse as a world vector.
    pub fn vector(&self, l: usize) -> Vector3<f64> {
        self.axes[0].dir_of(l) * self.tangent[0][l] + self.axes[1].dir_of(l) * self.tangent[1][l]
    }

    /// Adds the substep's tangent, twist and rolling impulses to the step's, those so far weighed by `decay`.
    pub fn end_substep(&mut self, decay: &Lanes) {
        for l in 0..W {
            for k in 0..2 {
                self.step_tangent[k][l] = self.step_tangent[k][l] * decay[l] + self.tangent[k][l];
                self.step_roll[k][l] = self.step_roll[k][l] * decay[l] + self.roll[k][l];
            }
            self.step_twist[l] = self.step_twist[l] * decay[l] + self.twist[l];
        }
    }

    /// Lane `l`'s friction, twist and rolling impulses over the step on B: linear, and angular about B's centre
    /// (at the step's start, where the rows' arms are taken).
    pub fn step_impulse(&self, l: usize) -> (Vector3<f64>, Vector3<f64>) {
        let cb = |a: &AxisLanes| Vector3::new(a.cb[0][l], a.cb[1][l], a.cb[2][l]);
        let (t0, t1) = (self.step_tangent[0][l], self.step_tangent[1][l]);
        let linear = self.axes[0].dir_of(l) * t0 + self.axes[1].dir_of(l) * t1;
        let mut angular = cb(&self.axes[0]) * t0 + cb(&self.axes[1]) * t1 + cb(&self.twist_axis) * self.step_twist[l];
        if self.resists {
            angular += cb(&self.roll_axes[0]) * self.step_roll[0][l] + cb(&self.roll_axes[1]) * self.step_roll[1][l];
        }
        (linear, angular)
    }

    /// Lane `l`'s rolling impulse as a world vector (an angular impulse on B).
    pub fn roll_vector(&self, l: usize) -> Vector3<f64> {
        let axis = |a: &AxisLanes| Vector3::new(a.ca[0][l], a.ca[1][l], a.ca[2][l]);
        axis(&self.roll_axes[0]) * self.roll[0][l] + axis(&self.roll_axes[1]) * self.roll[1][l]
    }
}

// SAFETY: f64 arrays and a bool.
unsafe impl Zeroed for FrictionBundle {}

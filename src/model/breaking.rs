//! Breakable joints: what a joint carries (the force its rows put on B, and their torque about B's anchor) and the
//! rule that breaks it (either past its bound). Both engines give the rows' forces their own way (accurate mode's
//! right-hand side or convex program, fast mode's soft step) and break joints here; a broken joint gives no rows
//! and no longer keeps its bodies from colliding.

use crate::model::joints::EndState;
use crate::model::Model;
use nalgebra::Vector3;
use tumble_contact::JointRow;

/// What one joint carries: the force on B (N) and the torque on B about B's anchor (N m); A takes the opposite. (Or
/// what it carried over a step, in N s and N m s; or its load averaged over its window.)
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct JointLoad {
    pub force: Vector3<f64>,
    pub torque: Vector3<f64>,
}

impl JointLoad {
    /// This average over `window` brought on by a step of `h` in substeps of `substep` that carried `carried`
    /// (`Model::judged_loads`): e^(-h / window) of it plus (1 - e^(-substep / window)) / substep of `carried`.
    fn brought_on(&self, carried: &JointLoad, window: f64, h: f64, substep: f64) -> JointLoad {
        let keep = (-h / window).exp();
        // (1 - e^(-substep / window)) / substep: 1 / window for a substep far below the window
        let share = -(-substep / window).exp_m1() / substep;
        JointLoad {
            force: self.force * keep + carried.force * share,
            torque: self.torque * keep + carried.torque * share,
        }
    }

    /// Adds a row's force `lambda` (the row's linear part `lin` and angular part on B `ang_b`; B's anchor at `rb`
    /// from B's centre, world axes).
    pub fn add(&mut self, lin: &Vector3<f64>, ang_b: &Vector3<f64>, rb: &Vector3<f64>, lambda: f64) {
        self.force += lin * lambda;
        self.torque += (ang_b - rb.cross(lin)) * lambda;
    }
}

impl Model {
    /// Whether a joint that holds can break.
    pub(crate) fn can_break(&self) -> bool {
        self.holding_joints().any(|(_, j)| j.breaking.is_some())
    }

    /// B's anchor from B's centre (world axes) for joint `k` with its ends at `ends`.
    pub(crate) fn anchor_b(&self, k: usize, ends: &(EndState, EndState)) -> Vector3<f64> {
        ends.1.q * self.joints[k].anchor_b
    }

    /// The loads of every joint from each row's force (`rows` with their joints' indices, `lambda` by row).
    pub(crate) fn joint_loads(
        &self,
        rows: &[(usize, JointRow)],
        ends: &[(EndState, EndState)],
        lambda: impl Fn(usize, &JointRow) -> f64,
    ) -> Vec<JointLoad> {
        let mut out = vec![JointLoad::default(); self.joints.len()];
        for (i, (k, r)) in rows.iter().enumerate() {
            out[*k].add(&r.lin, &r.ang_b, &self.anchor_b(*k, &ends[*k]), lambda(i, r));
        }
        out
    }

    /// The loads to judge each joint by after a step of `h` taken in substeps of `substep`: a joint with a window
    /// its load averaged over it, `averages` (one a joint, kept from step to step) brought on by the step's
    /// `carried` impulses, each substep's taken as a force constant over it. `carried` sums the substeps' impulses
    /// p_i, each weighed by e^(-substep / window) a later substep, and average = e^(-h / window) average + (1 -
    /// e^(-substep / window)) carried / substep: a steady load is judged as itself whatever the step, and an
    /// impulse in a substep far shorter than the window counts as impulse / window. Any other joint is judged by
    /// its `instant` load.
    pub(crate) fn judged_loads(
        &self,
        averages: &mut Vec<JointLoad>,
        instant: &[JointLoad],
        carried: &[JointLoad],
        h: f64,
        substep: f64,
    ) -> Vec<JointLoad> {
        averages.resize(self.joints.len(), JointLoad::default());
        let mut judged = instant.to_vec();
        for (k, j) in self.holding_joints() {
            let Some(b) = j.breaking.filter(|b| b.window > 0.0) else { continue };
            averages[k] = averages[k].brought_on(&carried[k], b.window, h, substep);
            judged[k] = averages[k];
        }
        judged
    }

    /// Where a step's blow took glued joints' loads, averaged over their windows, at its peak: their `averages`
    /// before the step brought on by `peaks`, the step's impulses with the blow at its full weight
    /// (`SoftStep::manifold_peak_impulses`); `judged` (the loads at the step's end) raised to them where they are
    /// larger, force and torque apart. A blow is judged where it struck, not at the step's end, whatever the step.
    pub(crate) fn judge_peaks(
        &self,
        judged: &mut [JointLoad],
        averages: &std::collections::BTreeMap<usize, JointLoad>,
        peaks: &std::collections::BTreeMap<usize, JointLoad>,
        h: f64,
        substep: f64,
    ) {
        for (&k, peak) in peaks {
            let Some(b) = self.joints[k].breaking.filter(|b| b.window > 0.0) else { continue };
            let at = averages.get(&k).copied().unwrap_or_default().brought_on(peak, b.window, h, substep);
            let l = &mut judged[k];
            if at.force.norm() > l.force.norm() {
                l.force = at.force;
            }
            if at.torque.norm() > l.torque.norm() {
                l.torque = at.torque;
            }
        }
    }

    /// Whether any holding joint that can break has a window.
    pub(crate) fn has_break_windows(&self) -> bool {
        self.holding_joints().any(|(_, j)| j.breaking.is_some_and(|b| b.window > 0.0))
    }

    /// The holding joints that `loads` (one per joint) take past their bounds, in order.
    pub(crate) fn overloaded(&self, loads: &[JointLoad]) -> Vec<usize> {
        self.holding_joints()
            .filter_map(|(k, j)| {
                let b = j.breaking?;
                let l = &loads[k];
                (l.force.norm() > b.force || l.torque.norm() > b.torque).then_some(k)
            })
            .collect()
    }

    /// Each joint's broken flag.
    pub(crate) fn broken_joints(&self) -> Vec<bool> {
        self.joints.iter().map(|j| j.broken).collect()
    }

    /// Sets each joint's broken flag (a memory given back), or says why it does not fit.
    pub(crate) fn set_broken_joints(&mut self, broken: &[bool]) -> Result<(), String> {
        if broken.len() != self.joints.len() {
            return Err(format!("it has {} joints' flags for {} joints", broken.len(), self.joints.len()));
        }
        for (j, &b) in self.joints.iter_mut().zip(broken) {
            j.broken = b;
        }
        Ok(())
    }

    /// The pieces joints `joints` (between bodies; others are passed over) bind into one: each a sorted list of
    /// actors, in the order of their smallest actor (union-find, each root its piece's smallest actor).
    pub(crate) fn pieces_bound_by(&self, joints: &[usize]) -> Vec<Vec<usize>> {
        use std::collections::{BTreeMap, BTreeSet};
        let l = self.layout;
        let mut sets = tumble_contact::UnionFind::new(l.actors());
        let mut members = BTreeSet::new();
        for &k in joints {
            let Some((a, b)) = self.joints[k].actors(l) else { continue };
            sets.union(a, b);
            members.extend([a, b]);
        }
        let mut pieces: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for a in members {
            pieces.entry(sets.find(a)).or_default().push(a);
        }
        pieces.into_values().collect()
    }

    /// The actor pairs a holding joint joins directly (they do not collide, unless the joint lets them), and every
    /// pair of bodies one piece of holding cluster joints binds (`JointBuilder::cluster`), sorted, each once.
    pub(crate) fn joined_pairs(&self) -> Vec<(usize, usize)> {
        let l = self.layout;
        let mut joined: Vec<(usize, usize)> = self
            .holding_joints()
            .filter(|(_, j)| !j.collide)
            .filter_map(|(_, j)| j.actors(l))
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        let cluster: Vec<usize> = self.holding_joints().filter(|(_, j)| j.cluster).map(|(k, _)| k).collect();
        let pieces = self.pieces_bound_by(&cluster);
        for piece in &pieces {
            for (i, &a) in piece.iter().enumerate() {
                joined.extend(piece[i + 1..].iter().map(|&b| (a.min(b), a.max(b))));
            }
        }
        joined.sort_unstable();
        joined.dedup();
        joined
    }
}

#[cfg(test)]
mod tests {
    use super::JointLoad;
    use nalgebra::Vector3;

    #[test]
    fn a_load_is_the_rows_force_on_b_and_their_torque_about_bs_anchor() {
        // a coinciding anchor's row along x at B's anchor rb: angular part rb x e on B, so no torque about the
        // anchor; an angular row about z: a torque alone
        let rb = Vector3::new(0.3, -0.2, 0.5);
        let mut load = JointLoad::default();
        load.add(&Vector3::x(), &rb.cross(&Vector3::x()), &rb, 4.0);
        load.add(&Vector3::zeros(), &Vector3::z(), &rb, -2.0);
        assert!((load.force - Vector3::new(4.0, 0.0, 0.0)).norm() < 1e-15);
        assert!((load.torque - Vector3::new(0.0, 0.0, -2.0)).norm() < 1e-15);
    }
}

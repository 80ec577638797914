//! The touching phase's energy guard: a contact step's extrapolated state is kept only if it has no more energy than
//! the step's start, beyond the solves' own accuracy and rounding (extrapolating a rocking body's steps can gain
//! energy; the halves are kept then).

use super::convex_step::ANSWER_SHARE;
use super::step_estimate::momenta;
use crate::engine::found_contact::ContactKey;
use crate::model::Model;
use nalgebra::Vector3;
use std::collections::BTreeMap;

/// A step's states and what its slack is made of.
pub(super) struct Guarded<'a> {
    pub model: &'a Model,
    /// The state at the step's start.
    pub start: &'a [f64],
    /// The free actors' state at its end, where some fly free (their own change of energy, the same in every
    /// candidate, is taken out: only the touching ones' is judged).
    pub free: Option<&'a [f64]>,
    /// The actors the step's contacts involve, and the halves' state.
    pub involved: &'a [bool],
    pub halves: &'a [f64],
    /// The contact tolerance (m) and the step (s).
    pub tolerance: f64,
    pub h: f64,
    /// Each contact's force (N, normal and friction) in the second half and in the whole step.
    pub second: &'a BTreeMap<ContactKey, Vector3<f64>>,
    pub whole: &'a BTreeMap<ContactKey, Vector3<f64>>,
}

impl Guarded<'_> {
    /// Whether state `candidate` has no more energy than the start beyond the slack: the velocities' rounding (1e-9
    /// of tol / h times the momenta), the work the contact impulses may do on the closing speeds the answers leave
    /// (`ANSWER_SHARE` of tol / h: that times the impulses, of the halves twice and of the whole step once, as the
    /// extrapolation weighs them) and rounding (1e-12 of the kinetic and potential energies' sizes, whose
    /// difference the total may be).
    pub fn keeps_energy(&self, candidate: &[f64]) -> bool {
        let model = self.model;
        let energy = |y: &[f64]| model.kinetic_energy(y) + model.potential_energy(y);
        let (kinetic, potential) = (model.kinetic_energy(self.start), model.potential_energy(self.start));
        let before = kinetic + potential;
        let free_gain = self.free.map_or(0.0, |f| energy(f) - before);
        let slack = 1e-12 * (kinetic.abs() + potential.abs())
            + 1e-9 * self.tolerance / self.h * momenta(model, self.involved, self.halves)
            + ANSWER_SHARE * self.tolerance * (4.0 * pushing(self.second) + pushing(self.whole));
        energy(candidate) - free_gain <= before + slack
    }
}

/// The sum of a convex step's contact force magnitudes (N), from its `wrenches`.
fn pushing(wrenches: &BTreeMap<ContactKey, Vector3<f64>>) -> f64 {
    wrenches.values().map(|f| f.norm()).sum()
}

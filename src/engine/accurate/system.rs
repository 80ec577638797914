//! Accurate mode's equations of motion, the ODE system its integrators step: the model's own (gravity, damping,
//! springs, loads, callbacks), then what accurate mode adds inside them: the joints' constraint forces (and, after
//! each accepted step, the projection back onto the joints), the resting contacts' QP forces while the chapter's
//! resting contact carries them, and the components held still while some actors fly free beside touching ones.
//! Fast mode steps the model's equations itself and pays for none of this.

use super::joint_forces::{add_joint_forces, project_joints, JOINT_DRIFT};
use crate::model::{Kinematics, Model, Tally};
use tumble_integrate::{JacobianStructure, OdeSystem, Split, SystemError};

/// The model with accurate mode's additions.
#[derive(Clone)]
pub(crate) struct AccurateSystem {
    pub model: Model,
    /// The resting contacts whose forces the right-hand side adds (`Persistent::RestingForces`), lent by the engine's
    /// memory for each integration.
    pub resting: Option<super::resting::RestingContacts>,
    /// The static actors' poses, for the resting forces.
    pub statics: std::sync::Arc<[nalgebra::Isometry3<f64>]>,
    /// clarabel's settings for the resting forces.
    pub solver: tumble_contact::SolverSettings,
    /// Resting-force solves and their wall time since the report was last taken.
    pub resting_solves: usize,
    pub resting_seconds: f64,
    /// State components whose rates are held at zero (the touching actors, while the others fly free); empty
    /// otherwise.
    pub held_components: Vec<usize>,
    /// What the equations of motion did since the report was last taken.
    pub tally: Tally,
}

impl AccurateSystem {
    /// The model's equations with nothing added yet.
    pub fn new(model: Model) -> AccurateSystem {
        AccurateSystem {
            model,
            resting: None,
            statics: std::sync::Arc::new([]),
            solver: Default::default(),
            resting_solves: 0,
            resting_seconds: 0.0,
            held_components: Vec::new(),
            tally: Tally::default(),
        }
    }

    /// Adds accurate mode's forces to the p rates `dp`: the joints', then the resting contacts'.
    fn add_forces(&mut self, kin: &Kinematics, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        add_joint_forces(&self.model, y, dp);
        if let Some(set) = &self.resting {
            let (solves, seconds) =
                super::resting::add_resting_forces(&self.model, kin, set, &self.statics, &self.solver, y, dp)?;
            self.resting_solves += solves;
            self.resting_seconds += seconds;
        }
        Ok(())
    }
}

impl AccurateSystem {
    /// The right-hand side into `dy`, returning the kinematics of y it used (for the contact steps' actors).
    pub fn rates(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<Kinematics, SystemError> {
        let kin = self.model.rates(&mut self.tally, t, y, dy, true)?;
        let q = self.model.layout.positions();
        self.add_forces(&kin, y, &mut dy[q..])?;
        self.model.hold_kinematic(&mut dy[q..]);
        for &k in &self.held_components {
            dy[k] = 0.0;
        }
        Ok(kin)
    }
}

impl OdeSystem for AccurateSystem {
    fn dim(&self) -> usize {
        self.model.layout.dim()
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        self.rates(t, y, dy).map(|_| ())
    }

    fn jacobian_structure(&self) -> JacobianStructure {
        self.model.jacobian_structure()
    }

    fn sparse_jacobian(&mut self, _t: f64, y: &[f64], values: &mut [f64]) -> Result<(), SystemError> {
        self.model.jacobian_values(y, values);
        Ok(())
    }

    fn is_autonomous(&self) -> bool {
        self.model.is_autonomous()
    }

    fn split(&self) -> Option<Split> {
        Some(self.model.split())
    }

    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        let kin = self.model.kinematics(y);
        self.model.position_part(&mut self.tally, &kin, y, dq);
        let q = dq.len();
        for &k in self.held_components.iter().filter(|k| **k < q) {
            dq[k] = 0.0;
        }
        Ok(())
    }

    fn velocity_rate(&mut self, t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        let kin = self.model.kinematics(y);
        self.model.force_part(&mut self.tally, &kin, t, y, dp, true)?;
        self.add_forces(&kin, y, dp)?;
        let q = self.model.layout.positions();
        for &k in self.held_components.iter().filter(|k| **k >= q) {
            dp[k - q] = 0.0;
        }
        Ok(())
    }

    /// Quaternions back on unit length, kinematic bodies back on their paths, then the state back on the joints.
    fn project(&mut self, t: f64, y: &mut [f64]) -> bool {
        let mut changed = self.model.normalize_quaternions(y);
        if self.model.place_kinematic(t, y) {
            changed = true;
        }
        if project_joints(&self.model, y, JOINT_DRIFT) {
            changed = true;
        }
        if changed {
            self.tally.forces.projections += 1;
        }
        changed
    }
}

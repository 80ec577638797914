//! The equations of motion as an `OdeSystem`: particles m x'' = m g - d v - h (x - anchor) + F; rigid bodies
//! x' = P / M, q' = 1/2 (0, w) q with w = R I_body^-1 R^T L, P' = F, L' = tau; forces from gravity, damping, springs,
//! loads and callbacks. The kinematic part (q rates) and the force part (p rates) are separate, which is the split
//! the symplectic methods use. These are the plain equations of motion; an engine that adds forces of its own
//! (accurate mode's joints and resting contacts) wraps them in its own ODE system.

use crate::load::{TargetState, Wrench};
use crate::model::layout::{add3, get3, get_quat, set3};
use crate::model::{BodyKin, CompiledLoad, JacobianKind, Kinematics, Model, ResolvedAttachment, ResolvedTarget, Tally};
use crate::plan::Stage;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use tumble_integrate::{JacobianStructure, Split, SystemError};

/// Quaternions further than this from unit length are renormalised after a step.
const NORM_DRIFT: f64 = 1e-12;

impl Model {
    /// Position and velocity of a spring end, and for a body end its lever arm (world axes); `kin` holds the
    /// bodies' kinematics at `y`.
    pub(crate) fn end_state(
        &self,
        kin: &[BodyKin],
        y: &[f64],
        end: ResolvedAttachment,
    ) -> (Vector3<f64>, Vector3<f64>, Option<Vector3<f64>>) {
        let l = self.layout;
        match end {
            ResolvedAttachment::Particle(i) => (get3(y, l.px(i)), get3(y, l.pv(i)), None),
            ResolvedAttachment::Body(j, local) => {
                let k = &kin[j];
                let r = k.rot * local;
                (get3(y, l.bx(j)) + r, k.velocity + k.omega.cross(&r), Some(r))
            }
            ResolvedAttachment::Point(p) => (p, Vector3::zeros(), None),
        }
    }

    /// dq/dt into `dq` (the first `layout.positions()` rates), from the kinematics `kin` of y.
    pub(crate) fn position_part(&self, tally: &mut Tally, kin: &Kinematics, y: &[f64], dq: &mut [f64]) {
        let l = self.layout;
        if l.bodies > 0 {
            tally.stages.mark(Stage::Rotation);
        }
        dq[..3 * l.particles].copy_from_slice(&y[l.pv(0)..l.pv(0) + 3 * l.particles]);
        for (j, k) in kin.0.iter().enumerate() {
            set3(dq, l.bx(j), &k.velocity);
            let q = get_quat(y, l.bq(j));
            let dq_j = Quaternion::from_imag(k.omega) * q * 0.5;
            let o = l.bq(j);
            dq[o] = dq_j.w;
            dq[o + 1] = dq_j.i;
            dq[o + 2] = dq_j.j;
            dq[o + 3] = dq_j.k;
        }
    }

    /// Adds a force (and its torque about the centre of mass for a body point) to the p rates.
    fn apply(&self, dp: &mut [f64], end: Option<ResolvedTarget>, f: &Vector3<f64>, arm: Option<Vector3<f64>>) {
        let (l, q) = (self.layout, self.layout.positions());
        match end {
            Some(ResolvedTarget::Particle(i)) => add3(dp, l.pv(i) - q, &(f * self.particles[i].inv_mass)),
            Some(ResolvedTarget::Body(j)) => {
                add3(dp, l.bp(j) - q, f);
                if let Some(r) = arm {
                    add3(dp, l.bl(j) - q, &r.cross(f));
                }
            }
            None => {}
        }
    }

    /// dp/dt into `dp` (the rates after the positions), from the kinematics `kin` of y: all forces and torques,
    /// or with `springs` false all but the springs' and the particles' anchor pulls (fast mode's soft step evaluates
    /// those itself, `engine/fast/soft_solve.rs`).
    pub(crate) fn force_part(
        &self,
        tally: &mut Tally,
        kin: &Kinematics,
        t: f64,
        y: &[f64],
        dp: &mut [f64],
        springs: bool,
    ) -> Result<(), SystemError> {
        tally.forces.evaluations += 1;
        let (l, q) = (self.layout, self.layout.positions());
        self.mark_force_stages(tally);
        for (i, p) in self.particles.iter().enumerate() {
            let mut a = self.gravity;
            if p.damping != 0.0 || (springs && p.stiffness != 0.0) {
                let pull = if springs { (get3(y, l.px(i)) - p.anchor) * p.stiffness } else { Vector3::zeros() };
                a -= (get3(y, l.pv(i)) * p.damping + pull) * p.inv_mass;
            }
            set3(dp, l.pv(i) - q, &a);
        }
        for (j, b) in self.bodies.iter().enumerate() {
            let k = &kin[j];
            set3(dp, l.bp(j) - q, &(self.gravity * b.mass - k.velocity * b.linear_damping));
            set3(dp, l.bl(j) - q, &(-k.omega * b.angular_damping));
        }
        let counted = if springs { &self.springs[..] } else { &[] };
        tally.forces.spring_evaluations += counted.len();
        for s in counted {
            let (pa, va, arm_a) = self.end_state(&kin.0, y, s.a);
            let (pb, vb, arm_b) = self.end_state(&kin.0, y, s.b);
            let Some(f) = s.law.force(&pa, &va, &pb, &vb) else { continue };
            self.apply(dp, end_on(s.a), &f, arm_a);
            self.apply(dp, end_on(s.b), &-f, arm_b);
        }
        for load in &self.loads {
            match load {
                CompiledLoad::Force { on, force, at } => {
                    tally.forces.load_evaluations += 1;
                    let arm = match (on, at) {
                        (ResolvedTarget::Body(j), Some(local)) => Some(kin[*j].rot * local),
                        _ => None,
                    };
                    self.apply(dp, Some(*on), force, arm);
                }
                CompiledLoad::Torque { body, torque } => {
                    tally.forces.load_evaluations += 1;
                    add3(dp, l.bl(*body) - q, torque);
                }
                CompiledLoad::Callback { on, callback } => {
                    tally.forces.callback_calls += 1;
                    let state = self.target_state(kin, y, *on);
                    let mut f = callback.lock().map_err(|_| SystemError::new("a force callback panicked earlier"))?;
                    let w: Wrench = f(t, &state).map_err(SystemError::new)?;
                    drop(f);
                    self.apply(dp, Some(*on), &w.force, None);
                    if let ResolvedTarget::Body(j) = on {
                        add3(dp, l.bl(*j) - q, &w.torque);
                    }
                }
            }
        }
        self.hold_kinematic(dp);
        Ok(())
    }

    /// Counts one run of each force term present (the loops below enter only these).
    fn mark_force_stages(&self, tally: &mut Tally) {
        for &stage in &self.terms {
            if stage != Stage::Rotation {
                tally.stages.mark(stage);
            }
        }
    }

    fn target_state(&self, kin: &Kinematics, y: &[f64], on: ResolvedTarget) -> TargetState {
        let l = self.layout;
        match on {
            ResolvedTarget::Particle(i) => TargetState {
                position: get3(y, l.px(i)),
                velocity: get3(y, l.pv(i)),
                orientation: UnitQuaternion::identity(),
                angular_velocity: Vector3::zeros(),
            },
            ResolvedTarget::Body(j) => TargetState {
                position: get3(y, l.bx(j)),
                velocity: kin[j].velocity,
                orientation: UnitQuaternion::new_normalize(get_quat(y, l.bq(j))),
                angular_velocity: kin[j].omega,
            },
        }
    }
}

impl Model {
    /// The right-hand side into `dy`, with the springs' forces or (`springs` false)
    /// without them and the particles' anchor pulls: fast mode's soft step evaluates those at every substep
    /// (`engine/fast/soft_solve.rs`), the rest once a step. Returns the kinematics of y it used.
    pub(crate) fn rates(
        &self,
        tally: &mut Tally,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        springs: bool,
    ) -> Result<Kinematics, SystemError> {
        let kin = self.kinematics(y);
        let (dq, dp) = dy.split_at_mut(self.layout.positions());
        self.position_part(tally, &kin, y, dq);
        self.force_part(tally, &kin, t, y, dp, springs)?;
        Ok(kin)
    }

    /// Puts every quaternion of y back on unit length if it drifted; returns whether any changed.
    pub(crate) fn normalize_quaternions(&self, y: &mut [f64]) -> bool {
        let mut changed = false;
        for j in 0..self.layout.bodies {
            let o = self.layout.bq(j);
            let norm = y[o..o + 4].iter().map(|v| v * v).sum::<f64>().sqrt();
            if (norm - 1.0).abs() > NORM_DRIFT && norm > 0.0 {
                y[o..o + 4].iter_mut().for_each(|v| *v /= norm);
                changed = true;
            }
        }
        changed
    }

    /// How the integrators see the Jacobian: analytic sparse blocks, or a coupling pattern for coloured finite
    /// differences.
    pub(crate) fn jacobian_structure(&self) -> JacobianStructure {
        match self.jacobian {
            JacobianKind::Analytic => JacobianStructure::Sparse(self.analytic_pattern()),
            JacobianKind::Colored => JacobianStructure::SparseFiniteDifference(self.coupling_pattern()),
        }
    }

    /// The analytic Jacobian's values at y, in the order of its pattern.
    pub(crate) fn jacobian_values(&self, y: &[f64], values: &mut [f64]) {
        let mut k = 0;
        self.analytic_entries(Some(y), &mut |_, _, v| {
            values[k] = v;
            k += 1;
        });
    }

    /// Whether the forces ignore time (no callbacks).
    pub(crate) fn is_autonomous(&self) -> bool {
        !self.loads.iter().any(|l| matches!(l, CompiledLoad::Callback { .. }))
    }

    /// The (q, p) split of the state for the symplectic methods.
    pub(crate) fn split(&self) -> Split {
        Split {
            positions: self.layout.positions(),
            force_depends_on_velocity: self.velocity_dependent,
            kinematic_identity: self.layout.bodies == 0,
        }
    }
}

/// The object a spring end pushes on (fixed points push on nothing).
fn end_on(e: ResolvedAttachment) -> Option<ResolvedTarget> {
    match e {
        ResolvedAttachment::Particle(i) => Some(ResolvedTarget::Particle(i)),
        ResolvedAttachment::Body(j, _) => Some(ResolvedTarget::Body(j)),
        ResolvedAttachment::Point(_) => None,
    }
}

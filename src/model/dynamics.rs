//! The equations of motion as an `OdeSystem`: particles m x'' = m g - d v - h (x - anchor) + F; rigid bodies
//! x' = P / M, q' = 1/2 (0, w) q with w = R I_body^-1 R^T L, P' = F, L' = tau; forces from gravity, damping, springs,
//! loads and callbacks. The kinematic part (q rates) and the force part (p rates) are separate, which is the split
//! the symplectic methods use.

use crate::load::{TargetState, Wrench};
use crate::model::layout::{add3, get3, get_quat, set3};
use crate::model::{BodyKin, CompiledLoad, End, JacobianKind, Model, On};
use crate::plan::Stage;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use tumble_integrate::{JacobianStructure, OdeSystem, Split, SystemError};

/// Quaternions further than this from unit length are renormalised after a step.
const NORM_DRIFT: f64 = 1e-12;
/// Joint errors (m, rad) and speeds (m/s, rad/s) above this are projected away after a step.
#[cfg(feature = "contact")]
pub(crate) const JOINT_DRIFT: f64 = 1e-12;

impl Model {
    /// A body's kinematics from the state (its quaternion normalised first).
    pub(crate) fn body_kin(&self, y: &[f64], j: usize) -> BodyKin {
        let (l, b) = (self.layout, &self.bodies[j]);
        let rot = UnitQuaternion::new_normalize(get_quat(y, l.bq(j))).to_rotation_matrix().into_inner();
        let inv_inertia = rot * b.inv_inertia * rot.transpose();
        BodyKin { rot, omega: inv_inertia * get3(y, l.bl(j)), velocity: get3(y, l.bp(j)) * b.inv_mass }
    }

    pub(crate) fn update_kin(&mut self, y: &[f64]) {
        for j in 0..self.bodies.len() {
            self.kin[j] = self.body_kin(y, j);
        }
    }

    /// Position and velocity of a spring end, and for a body end its lever arm (world axes); `kin` holds the
    /// bodies' kinematics at `y`.
    pub(crate) fn end_state(
        &self,
        kin: &[BodyKin],
        y: &[f64],
        end: End,
    ) -> (Vector3<f64>, Vector3<f64>, Option<Vector3<f64>>) {
        let l = self.layout;
        match end {
            End::Particle(i) => (get3(y, l.px(i)), get3(y, l.pv(i)), None),
            End::Body(j, local) => {
                let k = &kin[j];
                let r = k.rot * local;
                (get3(y, l.bx(j)) + r, k.velocity + k.omega.cross(&r), Some(r))
            }
            End::Point(p) => (p, Vector3::zeros(), None),
        }
    }

    /// dq/dt into `dq` (the first `layout.positions()` rates).
    fn position_part(&mut self, y: &[f64], dq: &mut [f64]) {
        let l = self.layout;
        if l.bodies > 0 {
            self.stage_runs.mark(Stage::Rotation);
        }
        dq[..3 * l.particles].copy_from_slice(&y[l.pv(0)..l.pv(0) + 3 * l.particles]);
        for (j, k) in self.kin.iter().enumerate() {
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
    fn apply(&self, dp: &mut [f64], end: Option<On>, f: &Vector3<f64>, arm: Option<Vector3<f64>>) {
        let (l, q) = (self.layout, self.layout.positions());
        match end {
            Some(On::Particle(i)) => add3(dp, l.pv(i) - q, &(f * self.particles[i].inv_mass)),
            Some(On::Body(j)) => {
                add3(dp, l.bp(j) - q, f);
                if let Some(r) = arm {
                    add3(dp, l.bl(j) - q, &r.cross(f));
                }
            }
            None => {}
        }
    }

    /// dp/dt into `dp` (the rates after the positions): all forces and torques, or with `springs` false all but the
    /// springs' and the particles' anchor pulls (fast mode's soft step evaluates those itself,
    /// `engine/fast/soft_solve.rs`).
    fn force_part(&mut self, t: f64, y: &[f64], dp: &mut [f64], springs: bool) -> Result<(), SystemError> {
        self.counters.evaluations += 1;
        let (l, q) = (self.layout, self.layout.positions());
        self.mark_force_stages();
        for (i, p) in self.particles.iter().enumerate() {
            let mut a = self.gravity;
            if p.damping != 0.0 || (springs && p.stiffness != 0.0) {
                let pull = if springs { (get3(y, l.px(i)) - p.anchor) * p.stiffness } else { Vector3::zeros() };
                a -= (get3(y, l.pv(i)) * p.damping + pull) * p.inv_mass;
            }
            set3(dp, l.pv(i) - q, &a);
        }
        for (j, b) in self.bodies.iter().enumerate() {
            let k = &self.kin[j];
            set3(dp, l.bp(j) - q, &(self.gravity * b.mass - k.velocity * b.linear_damping));
            set3(dp, l.bl(j) - q, &(-k.omega * b.angular_damping));
        }
        let counted = if springs { &self.springs[..] } else { &[] };
        self.counters.spring_evaluations += counted.len();
        for s in counted {
            let (pa, va, arm_a) = self.end_state(&self.kin, y, s.a);
            let (pb, vb, arm_b) = self.end_state(&self.kin, y, s.b);
            let d = pa - pb;
            let len = d.norm();
            if len <= 1e-300 {
                continue;
            }
            let n = d / len;
            let f = -n * (s.k * (len - s.l0) + s.c * (va - vb).dot(&n));
            self.apply(dp, end_on(s.a), &f, arm_a);
            self.apply(dp, end_on(s.b), &-f, arm_b);
        }
        for load in &self.loads {
            match load {
                CompiledLoad::Force { on, force, at } => {
                    self.counters.load_evaluations += 1;
                    let arm = match (on, at) {
                        (On::Body(j), Some(local)) => Some(self.kin[*j].rot * local),
                        _ => None,
                    };
                    self.apply(dp, Some(*on), force, arm);
                }
                CompiledLoad::Torque { body, torque } => {
                    self.counters.load_evaluations += 1;
                    add3(dp, l.bl(*body) - q, torque);
                }
                CompiledLoad::Callback { on, callback } => {
                    self.counters.callback_calls += 1;
                    let state = self.target_state(y, *on);
                    let mut f = callback.lock().map_err(|_| SystemError::new("a force callback panicked earlier"))?;
                    let w: Wrench = f(t, &state).map_err(SystemError::new)?;
                    drop(f);
                    self.apply(dp, Some(*on), &w.force, None);
                    if let On::Body(j) = on {
                        add3(dp, l.bl(*j) - q, &w.torque);
                    }
                }
            }
        }
        #[cfg(feature = "contact")]
        if self.joints_in_rhs {
            self.add_joint_forces(y, dp);
        }
        #[cfg(feature = "contact")]
        self.add_resting_forces(y, dp)?;
        Ok(())
    }

    /// Counts one run of each force term present (the loops below enter only these).
    fn mark_force_stages(&mut self) {
        for &stage in &self.terms {
            if stage != Stage::Rotation {
                self.stage_runs.mark(stage);
            }
        }
    }

    fn target_state(&self, y: &[f64], on: On) -> TargetState {
        let l = self.layout;
        match on {
            On::Particle(i) => TargetState {
                position: get3(y, l.px(i)),
                velocity: get3(y, l.pv(i)),
                orientation: UnitQuaternion::identity(),
                angular_velocity: Vector3::zeros(),
            },
            On::Body(j) => TargetState {
                position: get3(y, l.bx(j)),
                velocity: self.kin[j].velocity,
                orientation: UnitQuaternion::new_normalize(get_quat(y, l.bq(j))),
                angular_velocity: self.kin[j].omega,
            },
        }
    }
}

impl Model {
    /// The right-hand side into `dy`, with the springs' forces or (`springs` false) without them.
    fn rates(&mut self, t: f64, y: &[f64], dy: &mut [f64], springs: bool) -> Result<(), SystemError> {
        self.update_kin(y);
        let (dq, dp) = dy.split_at_mut(self.layout.positions());
        self.position_part(y, dq);
        self.force_part(t, y, dp, springs)?;
        for &k in &self.frozen {
            dy[k] = 0.0;
        }
        Ok(())
    }

    /// The right-hand side without the springs' forces and the particles' anchor pulls: fast mode's soft step
    /// evaluates those at every substep (`engine/fast/soft_solve.rs`), the rest once a step.
    #[cfg(feature = "contact")]
    pub(crate) fn rates_without_springs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        self.rates(t, y, dy, false)
    }
}

/// The object a spring end pushes on (fixed points push on nothing).
fn end_on(e: End) -> Option<On> {
    match e {
        End::Particle(i) => Some(On::Particle(i)),
        End::Body(j, _) => Some(On::Body(j)),
        End::Point(_) => None,
    }
}

impl OdeSystem for Model {
    fn dim(&self) -> usize {
        self.layout.dim()
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        self.rates(t, y, dy, true)
    }

    fn jacobian_structure(&self) -> JacobianStructure {
        match self.jacobian {
            JacobianKind::Analytic => JacobianStructure::Sparse(self.analytic_pattern()),
            JacobianKind::Colored => JacobianStructure::SparseFiniteDifference(self.coupling_pattern()),
        }
    }

    fn sparse_jacobian(&mut self, _t: f64, y: &[f64], values: &mut [f64]) -> Result<(), SystemError> {
        let mut k = 0;
        self.analytic_entries(Some(y), &mut |_, _, v| {
            values[k] = v;
            k += 1;
        });
        Ok(())
    }

    fn is_autonomous(&self) -> bool {
        !self.loads.iter().any(|l| matches!(l, CompiledLoad::Callback { .. }))
    }

    fn split(&self) -> Option<Split> {
        Some(Split {
            positions: self.layout.positions(),
            force_depends_on_velocity: self.velocity_dependent,
            kinematic_identity: self.layout.bodies == 0,
        })
    }

    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        self.update_kin(y);
        self.position_part(y, dq);
        let q = dq.len();
        for &k in self.frozen.iter().filter(|k| **k < q) {
            dq[k] = 0.0;
        }
        Ok(())
    }

    fn velocity_rate(&mut self, t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        self.update_kin(y);
        self.force_part(t, y, dp, true)?;
        let q = self.layout.positions();
        for &k in self.frozen.iter().filter(|k| **k >= q) {
            dp[k - q] = 0.0;
        }
        Ok(())
    }

    fn project(&mut self, _t: f64, y: &mut [f64]) -> bool {
        let mut changed = false;
        for j in 0..self.layout.bodies {
            let o = self.layout.bq(j);
            let norm = y[o..o + 4].iter().map(|v| v * v).sum::<f64>().sqrt();
            if (norm - 1.0).abs() > NORM_DRIFT && norm > 0.0 {
                y[o..o + 4].iter_mut().for_each(|v| *v /= norm);
                changed = true;
            }
        }
        #[cfg(feature = "contact")]
        if self.joints_in_rhs && self.project_joints(y, JOINT_DRIFT) {
            changed = true;
        }
        if changed {
            self.counters.projections += 1;
        }
        changed
    }
}

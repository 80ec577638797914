//! An island's joints in the soft step, solved as Box2D v3 solves its joints: before the contacts in each stage,
//! rows rebuilt where the substeps have moved the bodies (`prepare`), the last impulses applied at each substep's
//! start (`warm_start`), a pass with a soft pull back to the joint (`sweep` with softness) and a relax pass without
//! it. A rigid joint's pull is a spring of half the substep rate (twice the contacts') with damping ratio
//! `joint_damping_ratio`; a soft joint (its own hertz and damping ratio) keeps its spring in both passes. Limits are
//! one-sided rows that let a joint close on its limit within a substep (speculative) and push only on it; a motor
//! drives its row's speed with a bounded impulse; a spring is a soft row of the given stiffness and damping
//! (implicit, stable at any step). Within a joint, springs, motors and limits are solved before the rows that hold
//! it, so that these come last and hold best.

use super::row::Mover;
use super::softness::Softness;
use crate::joint::{
    delassus, factor, joint_rows, BoundedSolve, Factor, JointConstraint, JointImpulse, JointRow, RowKind, RowPart,
};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::TAU;

/// One row where the bodies are now: its Jacobian, the inverse inertia times its angular parts, its effective mass.
#[derive(Clone, Debug)]
struct Row {
    joint: usize,
    row: JointRow,
    ia: Vector3<f64>,
    ib: Vector3<f64>,
    mass: f64,
}

/// An island's joints: each joint (its bodies by local index, and their centres at the step's start), its
/// accumulated impulses and its rows at the current substep, in solve order.
pub(crate) struct JointSet {
    joints: Vec<(JointConstraint, Vector3<f64>, Vector3<f64>)>,
    pub impulses: Vec<JointImpulse>,
    /// Each joint's impulses summed over the substeps so far, each substep's weighed by the joint's `decay` once a
    /// later substep: what it carried over the step (its plain sum where the decay is 1).
    pub step_impulses: Vec<JointImpulse>,
    decay: Vec<f64>,
    rows: Vec<Row>,
    /// The rows of rigid joints that hold them (equality rows), solved together by a direct solve, and the
    /// factorization of their K = J M^-1 J^T; empty when there are more than `DIRECT_ROWS`.
    direct: Vec<usize>,
    factor: Option<Factor>,
    /// K of the rows solved together, and the places of the holding rows among them.
    kmat: nalgebra::DMatrix<f64>,
    holding: Vec<usize>,
    /// Each local body's inverse mass (at the last `prepare`).
    masses: Vec<f64>,
}

/// Rounds of the active set: solves after a limit or motor was held at its bound.
const ROUNDS: usize = 4;

/// Most rigid rows an island solves directly (a dense factorization a substep); past it they are swept one by one
/// with the soft pull.
const DIRECT_ROWS: usize = 240;

/// How a sweep treats the rows: with the soft pull of rigid joints (biased pass) or without (relax), at substep h.
#[derive(Clone, Copy)]
pub(crate) struct JointSweep {
    pub hs: f64,
    pub rigid: Option<Softness>,
}

impl JointSet {
    /// `joints` with local body indices, their centres at the step's start, their warm starts and decays.
    pub fn new(
        joints: Vec<(JointConstraint, Vector3<f64>, Vector3<f64>)>,
        warm: Vec<JointImpulse>,
        decay: Vec<f64>,
    ) -> JointSet {
        JointSet {
            step_impulses: vec![JointImpulse::default(); warm.len()],
            decay,
            joints,
            impulses: warm,
            rows: Vec::new(),
            direct: Vec::new(),
            factor: None,
            kmat: nalgebra::DMatrix::zeros(0, 0),
            holding: Vec::new(),
            masses: Vec::new(),
        }
    }

    /// The rows where the substeps have moved the bodies (inverse inertia turned with each body).
    pub fn prepare(&mut self, movers: &[Mover]) {
        self.rows.clear();
        self.masses.clear();
        self.masses.extend(movers.iter().map(|m| if m.moves() { m.inv_mass } else { 0.0 }));
        let mut rows = Vec::new();
        for (index, (j, xa, xb)) in self.joints.iter().enumerate() {
            let (ma, mb) = (&movers[j.a], &movers[j.b]);
            let frame = j.frame.turned(&ma.dq, &mb.dq);
            rows.clear();
            joint_rows(j, &frame, &(xa + ma.dp), &(xb + mb.dp), None, &mut rows);
            let world = |m: &Mover| -> Matrix3<f64> { m.turn * m.inv_inertia * m.turn.transpose() };
            let (inva, invb) = (world(ma), world(mb));
            // springs, motors and limits first, then the rows that hold the joint
            let order = rows
                .iter()
                .filter(|r| r.kind != RowKind::Equality)
                .chain(rows.iter().filter(|r| r.kind == RowKind::Equality));
            for row in order {
                let (ia, ib) = (inva * row.ang_a, invb * row.ang_b);
                let k = row.lin.norm_squared() * (ma.inv_mass + mb.inv_mass) + row.ang_a.dot(&ia) + row.ang_b.dot(&ib);
                let mass = if k > 0.0 { 1.0 / k } else { 0.0 };
                self.rows.push(Row { joint: index, row: *row, ia, ib, mass });
            }
        }
        self.factorize();
    }

    /// The rows solved together (rigid joints' holding rows, limits and motors) and their K = J M^-1 J^T, with the
    /// factorization of its holding rows' part (what a sweep with no limit or motor acting solves).
    fn factorize(&mut self) {
        self.direct.clear();
        self.factor = None;
        let together = |r: &Row| {
            r.mass > 0.0
                && match r.row.kind {
                    RowKind::Equality => self.joints[r.joint].0.softness.is_none(),
                    RowKind::Lower | RowKind::Motor { .. } => true,
                    RowKind::Spring { .. } => false,
                }
        };
        let direct: Vec<usize> = (0..self.rows.len()).filter(|&i| together(&self.rows[i])).collect();
        if direct.is_empty() || direct.len() > DIRECT_ROWS {
            return;
        }
        // each row's parts on its two bodies, the inverse inertia times the angular part first
        let part = |body: usize, lin: Vector3<f64>, ang: Vector3<f64>, weighted: Vector3<f64>| {
            let inv_mass = self.inverse_mass(body);
            RowPart { body: (inv_mass > 0.0).then_some(body), inv_mass, lin, ang: weighted, weighted: ang }
        };
        let parts: Vec<[RowPart; 2]> = direct
            .iter()
            .map(|&i| {
                let (r, j) = (&self.rows[i], &self.joints[self.rows[i].joint].0);
                [part(j.a, -r.row.lin, r.row.ang_a, r.ia), part(j.b, r.row.lin, r.row.ang_b, r.ib)]
            })
            .collect();
        let k = delassus(&parts);
        let n = direct.len();
        self.holding = (0..n).filter(|&x| self.rows[direct[x]].row.kind == RowKind::Equality).collect();
        self.factor = factor(&k, &self.holding);
        self.direct = direct;
        self.kmat = k;
    }

    /// A body's inverse mass, read from the rows' masses (kept with the joints' bodies).
    fn inverse_mass(&self, body: usize) -> f64 {
        self.masses.get(body).copied().unwrap_or(0.0)
    }

    /// Adds the substep's impulses to the step's (those so far weighed by the decay once more).
    pub fn end_substep(&mut self) {
        for ((step, last), &decay) in self.step_impulses.iter_mut().zip(&self.impulses).zip(&self.decay) {
            for (s, p) in step.0.iter_mut().zip(&last.0) {
                *s = *s * decay + p;
            }
        }
    }

    /// Applies every row's accumulated impulse (the last substep's) to the bodies.
    pub fn warm_start(&self, movers: &mut [Mover]) {
        for r in &self.rows {
            let p = self.impulses[r.joint].0[r.row.slot];
            if p != 0.0 {
                let j = &self.joints[r.joint].0;
                apply(movers, j.a, j.b, r, p);
            }
        }
    }

    /// One sweep: Gauss-Seidel over the rows not solved directly (springs, motors, limits, soft joints, and every
    /// row of an island with too many), then the direct solve of the rigid joints' rows; returns the largest
    /// impulse change.
    pub fn sweep(&mut self, movers: &mut [Mover], s: JointSweep) -> f64 {
        let mut change = 0.0f64;
        let mut next_direct = 0;
        for (i, r) in self.rows.iter().enumerate() {
            if self.direct.get(next_direct) == Some(&i) {
                next_direct += 1;
                continue;
            }
            if r.mass == 0.0 {
                continue;
            }
            let j = &self.joints[r.joint].0;
            let (a, b) = (&movers[j.a], &movers[j.b]);
            let speed = r.row.speed(&a.v, &a.w, &b.v, &b.w);
            let acc = &mut self.impulses[r.joint].0[r.row.slot];
            let old = *acc;
            let c = r.row.error;
            // the soft pull of this row: a soft joint's own spring in both passes, a rigid joint's in the biased one
            let pull = match j.softness {
                Some((hertz, zeta)) => Some(Softness::new(hertz, zeta, s.hs)),
                None => s.rigid,
            };
            match r.row.kind {
                RowKind::Equality => {
                    let (bias, scale, keep) = match pull {
                        Some(p) => (p.bias_rate * c, p.mass_scale, p.impulse_scale),
                        None => (0.0, 1.0, 0.0),
                    };
                    *acc += -r.mass * scale * (speed + bias) - keep * old;
                }
                RowKind::Lower => {
                    // apart: close at most to the limit within the substep; on it or past: the soft pull
                    let (bias, scale, keep) = if c > 0.0 {
                        (c / s.hs, 1.0, 0.0)
                    } else {
                        match pull {
                            Some(p) => (p.bias_rate * c, p.mass_scale, p.impulse_scale),
                            None => (0.0, 1.0, 0.0),
                        }
                    };
                    *acc = (old - r.mass * scale * (speed + bias) - keep * old).max(0.0);
                }
                RowKind::Motor { speed: target, max_force } => {
                    let most = max_force * s.hs;
                    *acc = (old - r.mass * (speed - target)).clamp(-most, most);
                }
                RowKind::Spring { stiffness, damping } => {
                    // a spring and damper on this row's effective mass, as a soft row (implicit)
                    // (omega^2 = k / m, 2 zeta omega = c / m; a spring's stiffness is > 0)
                    let omega = (stiffness / r.mass).sqrt();
                    let zeta = damping / (2.0 * (stiffness * r.mass).sqrt());
                    let p = Softness::new(omega / TAU, zeta, s.hs);
                    *acc += -r.mass * p.mass_scale * (speed + p.bias_rate * c) - p.impulse_scale * old;
                }
            }
            let delta = *acc - old;
            if delta != 0.0 {
                apply(movers, j.a, j.b, r, delta);
                change = change.max(delta.abs());
            }
        }
        change.max(self.direct_solve(movers, s))
    }

    /// The rows solved together: the impulses that bring each holding row's speed to its pull back to the joint
    /// (biased pass: the error over the substep, with no relaxation, so that a loaded joint does not sag; relax:
    /// zero), each motor's to its target, and each limit that closes within the substep to its limit, with the
    /// limits' impulses kept >= 0 and the motors' within their bounds: an active set, a limit or motor that breaks
    /// its bound held there and the rest solved again (at most `ROUNDS` times).
    fn direct_solve(&mut self, movers: &mut [Mover], s: JointSweep) -> f64 {
        if self.direct.is_empty() {
            return 0.0;
        }
        // the whole error in one substep: measured on a pendulum released at 90 degrees (dt 1/60, 8 substeps), the
        // period is 1.9e-5 from the exact one against 4.8e-5 with the soft pull's rate
        let rate = if s.rigid.is_some() { 1.0 / s.hs } else { 0.0 };
        let n = self.direct.len();
        // each row's wanted impulse change alone (the residual of its condition) and its accumulated impulse
        let mut want = vec![0.0; n];
        let mut acc = vec![0.0; n];
        let mut active = Vec::with_capacity(n);
        for (x, &i) in self.direct.iter().enumerate() {
            let r = &self.rows[i];
            let j = &self.joints[r.joint].0;
            let (a, b) = (&movers[j.a], &movers[j.b]);
            let speed = r.row.speed(&a.v, &a.w, &b.v, &b.w);
            let c = r.row.error;
            acc[x] = self.impulses[r.joint].0[r.row.slot];
            want[x] = match r.row.kind {
                RowKind::Motor { speed: target, .. } => target - speed,
                RowKind::Lower if c > 0.0 => -(speed + c / s.hs),
                _ => -(speed + rate * c),
            };
            let acts = match r.row.kind {
                RowKind::Lower => acc[x] > 0.0 || want[x] > 0.0,
                _ => true,
            };
            if acts {
                active.push(x);
            }
        }
        // the bounds: a limit pushes only, a motor up to its force
        let bounds: Vec<(f64, f64)> = self
            .direct
            .iter()
            .map(|&i| match self.rows[i].row.kind {
                RowKind::Lower => (0.0, f64::INFINITY),
                RowKind::Motor { max_force, .. } => (-max_force * s.hs, max_force * s.hs),
                _ => (f64::NEG_INFINITY, f64::INFINITY),
            })
            .collect();
        let solve = BoundedSolve { k: &self.kmat, want: &want, bounds: &bounds, base: &acc, rounds: ROUNDS };
        let delta = solve.solve(active, self.factor.as_ref().map(|f| (&self.holding[..], f)));
        let mut change = 0.0f64;
        for (x, &i) in self.direct.iter().enumerate() {
            let d = delta[x];
            if d == 0.0 {
                continue;
            }
            let r = &self.rows[i];
            let (a, b) = (self.joints[r.joint].0.a, self.joints[r.joint].0.b);
            self.impulses[r.joint].0[r.row.slot] += d;
            apply(movers, a, b, r, d);
            change = change.max(d.abs());
        }
        change
    }

    /// The largest accumulated impulse of a row (for the settling test of a converging pass).
    pub fn largest(&self) -> f64 {
        self.impulses.iter().flat_map(|i| i.0).fold(0.0f64, |m, p| m.max(p.abs()))
    }

    /// The largest speed of an equality row at the bodies' velocities (m/s or rad/s): what the sweeps left of the
    /// joints' velocity conditions.
    pub fn residual(&self, movers: &[Mover]) -> f64 {
        let mut worst = 0.0f64;
        for r in self.rows.iter().filter(|r| r.row.kind == RowKind::Equality && r.mass > 0.0) {
            let j = &self.joints[r.joint].0;
            if j.softness.is_some() {
                continue;
            }
            let (a, b) = (&movers[j.a], &movers[j.b]);
            let speed = r.row.speed(&a.v, &a.w, &b.v, &b.w);
            worst = worst.max(speed.abs());
        }
        worst
    }
}

/// Applies impulse p along row r: +p on B, -p on A (the angular parts carry their own signs).
fn apply(movers: &mut [Mover], a: usize, b: usize, r: &Row, p: f64) {
    let ma = &mut movers[a];
    if ma.moves() {
        ma.v -= r.row.lin * (p * ma.inv_mass);
        ma.w += r.ia * p;
    }
    let mb = &mut movers[b];
    if mb.moves() {
        mb.v += r.row.lin * (p * mb.inv_mass);
        mb.w += r.ib * p;
    }
}

//! Accurate mode's joint solve, inside the equations of motion and after each accepted step. The right-hand side
//! gives the joints' forces: every holding row keeps its speed constant (K lambda = -(J a_free + J'v), K =
//! J M^-1 J^T), a limit or rope that is reached pushes (lambda >= 0) to stop its approach and pull it back
//! (J a >= -J'v - 2 a C' - a^2 C, a critically damped spring of rate `RATE`), a motor drives its speed towards its
//! target at `RATE` with at most its force; springs are plain forces. The rows are solved together, limits and
//! motors by an active set. After each accepted step the state is put back on the joints: positions (holding rows,
//! and limits passed), then velocities (holding rows, and limits closing at their limit: an inelastic stop), each
//! as the least change in the mass metric.

use crate::model::joints::{EndState, JointEnd};
use crate::model::layout::{add3, get3, get_quat, set_quat};
use crate::model::Model;
use nalgebra::{DMatrix, DVector, UnitQuaternion, Vector3};
use tumble_contact::{JointRow, RowKind};

/// Rate (1/s) at which a reached limit or rope is held and a motor reaches its speed: fast against motion worth
/// animating, slow enough that an explicit method's steps stay far above 1/RATE's stability bound.
const RATE: f64 = 100.0;

/// Rounds of the active set.
const ROUNDS: usize = 6;

/// A row's part on one end: the body (if it moves), linear and angular.
type Part = (Option<usize>, Vector3<f64>, Vector3<f64>);

/// The solution of K x = r with bounds on x (`lo`, `hi` per row; rows `start` false begin inactive at zero): an
/// active set, a row that breaks its bound held at it and the rest solved again. K positive semidefinite: a
/// redundant joint's singular K is solved slightly regularised.
fn bounded_solve(k: &DMatrix<f64>, r: &DVector<f64>, bounds: &[(f64, f64)], start: &[bool]) -> DVector<f64> {
    let n = r.len();
    let mut x = DVector::zeros(n);
    let mut active: Vec<usize> = (0..n).filter(|&i| start[i]).collect();
    let mut held: Vec<usize> = Vec::new();
    for _ in 0..ROUNDS {
        if active.is_empty() {
            break;
        }
        let m = active.len();
        let sub = DMatrix::from_fn(m, m, |i, j| k[(active[i], active[j])]);
        let rhs =
            DVector::from_fn(m, |i, _| r[active[i]] - held.iter().map(|&h| k[(active[i], h)] * x[h]).sum::<f64>());
        let scale = sub.diagonal().amax().max(1e-300);
        let solved = match sub.clone().cholesky() {
            Some(c) => c.solve(&rhs),
            None => match (sub + DMatrix::identity(m, m) * (1e-12 * scale)).cholesky() {
                Some(c) => c.solve(&rhs),
                None => DVector::zeros(m),
            },
        };
        for (i, &row) in active.iter().enumerate() {
            x[row] = solved[i];
        }
        let broke: Vec<usize> = active.iter().copied().filter(|&i| x[i] < bounds[i].0 || x[i] > bounds[i].1).collect();
        if broke.is_empty() {
            break;
        }
        for &i in &broke {
            x[i] = x[i].clamp(bounds[i].0, bounds[i].1);
        }
        active.retain(|i| !broke.contains(i));
        held.extend(broke);
    }
    x
}

impl Model {
    /// The rows' K = J M^-1 J^T (rows of `rows`, over the ends of their joints).
    fn delassus(&self, rows: &[(usize, JointRow)], ends: &[(EndState, EndState)]) -> DMatrix<f64> {
        let n = rows.len();
        let mut k = DMatrix::zeros(n, n);
        let body = |e: JointEnd| match e {
            JointEnd::Body(i) => Some(i),
            JointEnd::Fixed(_) => None,
        };
        let parts: Vec<[Part; 2]> = rows
            .iter()
            .map(|(j, r)| {
                let cj = &self.joints[*j];
                [(body(cj.a), -r.lin, r.ang_a), (body(cj.b), r.lin, r.ang_b)]
            })
            .collect();
        for i in 0..n {
            let ji = rows[i].0;
            for m in i..n {
                let mut sum = 0.0;
                for (side, (bi, li, ai)) in parts[i].iter().enumerate() {
                    let Some(bi) = bi else { continue };
                    for (bm, lm, am) in parts[m].iter() {
                        if *bm == Some(*bi) {
                            let e = if side == 0 { &ends[ji].0 } else { &ends[ji].1 };
                            sum += e.inv_mass * li.dot(lm) + ai.dot(&(e.inv_inertia * am));
                        }
                    }
                }
                k[(i, m)] = sum;
                k[(m, i)] = sum;
            }
        }
        k
    }

    /// A row's speed at its joint's ends.
    fn row_speed(r: &JointRow, (a, b): &(EndState, EndState)) -> f64 {
        r.lin.dot(&(b.v - a.v)) + r.ang_a.dot(&a.w) + r.ang_b.dot(&b.w)
    }

    /// Adds a row's force (or impulse) `lambda` to the p rates (or momenta) at `dp`, whose first entry is the
    /// state's `offset`.
    fn push_row(&self, dp: &mut [f64], offset: usize, j: usize, r: &JointRow, lambda: f64) {
        let (l, cj) = (self.layout, &self.joints[j]);
        if let JointEnd::Body(i) = cj.a {
            add3(dp, l.bp(i) - offset, &(-r.lin * lambda));
            add3(dp, l.bl(i) - offset, &(r.ang_a * lambda));
        }
        if let JointEnd::Body(i) = cj.b {
            add3(dp, l.bp(i) - offset, &(r.lin * lambda));
            add3(dp, l.bl(i) - offset, &(r.ang_b * lambda));
        }
    }

    /// Adds the joints' forces to the p rates `dp` (accurate mode's right-hand side).
    pub(crate) fn add_joint_forces(&self, y: &[f64], dp: &mut [f64]) {
        if self.joints.is_empty() {
            return;
        }
        let (l, q) = (self.layout, self.layout.positions());
        let (rows, ends) = self.all_rows(y, true);
        for (j, r) in &rows {
            if let RowKind::Spring { stiffness, damping } = r.kind {
                let f = -stiffness * r.error - damping * Self::row_speed(r, &ends[*j]);
                self.push_row(dp, q, *j, r, f);
            }
        }
        // the rows solved for: holding rows, limits and ropes reached, motors
        let solved: Vec<(usize, JointRow)> = rows
            .into_iter()
            .filter(|(_, r)| match r.kind {
                RowKind::Equality | RowKind::Motor { .. } => true,
                RowKind::Lower => r.error <= 0.0,
                RowKind::Spring { .. } => false,
            })
            .collect();
        if solved.is_empty() {
            return;
        }
        // each end's acceleration under the forces so far (Euler's equations, L from the state)
        let accel = |e: JointEnd, s: &EndState, dp: &[f64]| match e {
            JointEnd::Body(i) => {
                let f = get3(dp, l.bp(i) - q);
                let tau = get3(dp, l.bl(i) - q);
                (f * s.inv_mass, s.inv_inertia * (tau - s.w.cross(&get3(y, l.bl(i)))))
            }
            JointEnd::Fixed(_) => (Vector3::zeros(), Vector3::zeros()),
        };
        let n = solved.len();
        let (mut rhs, mut bounds) = (DVector::zeros(n), Vec::with_capacity(n));
        for (k, (j, r)) in solved.iter().enumerate() {
            let cj = &self.joints[*j];
            let (aa, alpha_a) = accel(cj.a, &ends[*j].0, dp);
            let (ab, alpha_b) = accel(cj.b, &ends[*j].1, dp);
            let free = r.lin.dot(&(ab - aa)) + r.ang_a.dot(&alpha_a) + r.ang_b.dot(&alpha_b) + r.curvature;
            let speed = Self::row_speed(r, &ends[*j]);
            let (wanted, bound) = match r.kind {
                RowKind::Lower => (-2.0 * RATE * speed - RATE * RATE * r.error, (0.0, f64::INFINITY)),
                RowKind::Motor { speed: target, max_force } => (RATE * (target - speed), (-max_force, max_force)),
                _ => (0.0, (f64::NEG_INFINITY, f64::INFINITY)),
            };
            rhs[k] = wanted - free;
            bounds.push(bound);
        }
        let k = self.delassus(&solved, &ends);
        let lambda = bounded_solve(&k, &rhs, &bounds, &vec![true; n]);
        for ((j, r), &lam) in solved.iter().zip(lambda.iter()) {
            self.push_row(dp, q, *j, r, lam);
        }
    }

    /// Puts positions, then velocities, back on the joints (accurate mode, after an accepted step): at most four
    /// Gauss-Newton corrections in the mass metric while a holding row's error, or a limit's overshoot, exceeds
    /// `tolerance` (m or rad); then the velocity correction that removes every holding row's speed and every
    /// closing speed of a limit at its limit (pushing only). Returns whether y changed.
    pub(crate) fn project_joints(&self, y: &mut [f64], tolerance: f64) -> bool {
        if self.joints.is_empty() {
            return false;
        }
        let l = self.layout;
        let mut changed = false;
        let push_only = |r: &JointRow| {
            if r.kind == RowKind::Lower {
                (0.0, f64::INFINITY)
            } else {
                (f64::NEG_INFINITY, f64::INFINITY)
            }
        };
        for _ in 0..4 {
            let (rows, ends) = self.all_rows(y, false);
            let off: Vec<(usize, JointRow)> = rows
                .into_iter()
                .filter(|(_, r)| match r.kind {
                    RowKind::Equality => true,
                    RowKind::Lower => r.error < 0.0,
                    _ => false,
                })
                .collect();
            if off.iter().all(|(_, r)| r.error.abs() <= tolerance) {
                break;
            }
            let c = DVector::from_iterator(off.len(), off.iter().map(|(_, r)| -r.error));
            let bounds: Vec<(f64, f64)> = off.iter().map(|(_, r)| push_only(r)).collect();
            let delta = bounded_solve(&self.delassus(&off, &ends), &c, &bounds, &vec![true; off.len()]);
            for ((j, r), &d) in off.iter().zip(delta.iter()) {
                let cj = &self.joints[*j];
                for (end, lin, ang, s) in [(cj.a, -r.lin, r.ang_a, &ends[*j].0), (cj.b, r.lin, r.ang_b, &ends[*j].1)] {
                    if let JointEnd::Body(i) = end {
                        add3(y, l.bx(i), &(lin * (d * s.inv_mass)));
                        let turn = UnitQuaternion::from_scaled_axis(s.inv_inertia * ang * d);
                        let qn = turn * UnitQuaternion::new_normalize(get_quat(y, l.bq(i)));
                        set_quat(y, l.bq(i), &qn);
                    }
                }
            }
            changed = true;
        }
        let (rows, ends) = self.all_rows(y, false);
        let (mut held, mut speeds) = (Vec::new(), Vec::new());
        for (j, r) in rows {
            let speed = Self::row_speed(&r, &ends[j]);
            let keep = match r.kind {
                RowKind::Equality => true,
                RowKind::Lower => r.error <= tolerance && speed < 0.0,
                _ => false,
            };
            if keep {
                held.push((j, r));
                speeds.push(speed);
            }
        }
        if speeds.iter().all(|s| s.abs() <= tolerance) {
            return changed;
        }
        let bounds: Vec<(f64, f64)> = held.iter().map(|(_, r)| push_only(r)).collect();
        let k = self.delassus(&held, &ends);
        let mu = bounded_solve(&k, &(-DVector::from_vec(speeds)), &bounds, &vec![true; held.len()]);
        // impulses straight into the momenta (the state's P and L)
        for ((j, r), &m) in held.iter().zip(mu.iter()) {
            self.push_row(y, 0, *j, r, m);
        }
        true
    }
}

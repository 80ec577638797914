//! Accurate mode's joint solve, inside its equations of motion and after each accepted step. The right-hand side
//! gives the joints' forces: every holding row keeps its speed constant (K lambda = -(J a_free + J'v), K =
//! J M^-1 J^T), a limit or rope that is reached pushes (lambda >= 0) to stop its approach and pull it back
//! (J a >= -J'v - 2 a C' - a^2 C, a critically damped spring of rate `RATE`), a motor drives its speed towards its
//! target at `RATE` with at most its force; springs are plain forces. The rows are solved together, limits and
//! motors by tumble-contact's bounded active-set solve. After each accepted step the state is put back on the
//! joints: positions (holding rows, and limits passed), then velocities (holding rows, and limits closing at their
//! limit: an inelastic stop), each as the least change in the mass metric. The contact steps hold the same rows in
//! their convex programs (`bilateral_rows`).

use crate::model::joints::EndState;
use crate::model::layout::{add3, get3, get_quat, set_quat};
use crate::model::Model;
use crate::model::ResolvedBody;
use nalgebra::{DMatrix, UnitQuaternion, Vector3};
use tumble_contact::{delassus, BoundedSolve, JointRow, RowKind, RowPart};

/// Rate (1/s) at which a reached limit or rope is held and a motor reaches its speed: fast against motion worth
/// animating, slow enough that an explicit method's steps stay far above 1/RATE's stability bound.
const RATE: f64 = 100.0;

/// Rounds of the active set.
const ROUNDS: usize = 6;

/// Joint errors (m, rad) and speeds (m/s, rad/s) above this are projected away after a step.
pub(crate) const JOINT_DRIFT: f64 = 1e-12;

/// The rows' K = J M^-1 J^T (rows of `rows`, over the ends of their joints).
fn row_matrix(model: &Model, rows: &[(usize, JointRow)], ends: &[(EndState, EndState)]) -> DMatrix<f64> {
    let part = |end: ResolvedBody, e: &EndState, lin: Vector3<f64>, ang: Vector3<f64>| RowPart {
        body: end.dynamic(),
        inv_mass: e.inv_mass,
        lin,
        ang,
        weighted: e.inv_inertia * ang,
    };
    let parts: Vec<[RowPart; 2]> = rows
        .iter()
        .map(|(j, r)| {
            let (cj, (a, b)) = (&model.joints[*j], &ends[*j]);
            [part(cj.a, a, -r.lin, r.ang_a), part(cj.b, b, r.lin, r.ang_b)]
        })
        .collect();
    delassus(&parts)
}

/// The bounded solve of K x = want over every row, from zero.
fn solve(k: &DMatrix<f64>, want: &[f64], bounds: &[(f64, f64)]) -> Vec<f64> {
    let n = want.len();
    BoundedSolve { k, want, bounds, base: &vec![0.0; n], rounds: ROUNDS }.solve((0..n).collect(), None)
}

/// A row's speed at its joint's ends.
fn row_speed(r: &JointRow, (a, b): &(EndState, EndState)) -> f64 {
    r.speed(&a.v, &a.w, &b.v, &b.w)
}

/// Adds a row's force (or impulse) `lambda` to the p rates (or momenta) at `dp`, whose first entry is the state's
/// `offset`.
fn push_row(model: &Model, dp: &mut [f64], offset: usize, j: usize, r: &JointRow, lambda: f64) {
    let (l, cj) = (model.layout, &model.joints[j]);
    if let ResolvedBody::Dynamic(i) = cj.a {
        add3(dp, l.bp(i) - offset, &(-r.lin * lambda));
        add3(dp, l.bl(i) - offset, &(r.ang_a * lambda));
    }
    if let ResolvedBody::Dynamic(i) = cj.b {
        add3(dp, l.bp(i) - offset, &(r.lin * lambda));
        add3(dp, l.bl(i) - offset, &(r.ang_b * lambda));
    }
}

/// Push only for a limit or rope, either way for a holding row.
fn push_only(r: &JointRow) -> (f64, f64) {
    if r.kind == RowKind::Lower {
        (0.0, f64::INFINITY)
    } else {
        (f64::NEG_INFINITY, f64::INFINITY)
    }
}

/// Adds the joints' forces to the p rates `dp` (the right-hand side, after every other force).
pub(crate) fn add_joint_forces(model: &Model, y: &[f64], dp: &mut [f64]) {
    joint_forces(model, y, dp, |_, _, _, _| {});
}

/// Adds the joints' forces to the p rates `dp`, showing each row's force to `each` (its joint, the row, the
/// joint's ends, the force).
pub(crate) fn joint_forces(
    model: &Model,
    y: &[f64],
    dp: &mut [f64],
    mut each: impl FnMut(usize, &JointRow, &(EndState, EndState), f64),
) {
    if model.joints.is_empty() {
        return;
    }
    let (l, q) = (model.layout, model.layout.positions());
    let (rows, ends) = model.all_rows(y, true);
    for (j, r) in &rows {
        if let RowKind::Spring { stiffness, damping } = r.kind {
            let f = -stiffness * r.error - damping * row_speed(r, &ends[*j]);
            push_row(model, dp, q, *j, r, f);
            each(*j, r, &ends[*j], f);
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
    let accel = |e: ResolvedBody, s: &EndState, dp: &[f64]| match e {
        ResolvedBody::Dynamic(i) => {
            let f = get3(dp, l.bp(i) - q);
            let tau = get3(dp, l.bl(i) - q);
            (f * s.inv_mass, s.inv_inertia * (tau - s.w.cross(&get3(y, l.bl(i)))))
        }
        ResolvedBody::Fixed(_) => (Vector3::zeros(), Vector3::zeros()),
    };
    let n = solved.len();
    let (mut want, mut bounds) = (vec![0.0; n], Vec::with_capacity(n));
    for (k, (j, r)) in solved.iter().enumerate() {
        let cj = &model.joints[*j];
        let (aa, alpha_a) = accel(cj.a, &ends[*j].0, dp);
        let (ab, alpha_b) = accel(cj.b, &ends[*j].1, dp);
        let free = r.lin.dot(&(ab - aa)) + r.ang_a.dot(&alpha_a) + r.ang_b.dot(&alpha_b) + r.curvature;
        let speed = row_speed(r, &ends[*j]);
        let (wanted, bound) = match r.kind {
            RowKind::Lower => (-2.0 * RATE * speed - RATE * RATE * r.error, (0.0, f64::INFINITY)),
            RowKind::Motor { speed: target, max_force } => (RATE * (target - speed), (-max_force, max_force)),
            _ => (0.0, (f64::NEG_INFINITY, f64::INFINITY)),
        };
        want[k] = wanted - free;
        bounds.push(bound);
    }
    let lambda = solve(&row_matrix(model, &solved, &ends), &want, &bounds);
    for ((j, r), &lam) in solved.iter().zip(lambda.iter()) {
        push_row(model, dp, q, *j, r, lam);
        each(*j, r, &ends[*j], lam);
    }
}

/// Puts positions, then velocities, back on the joints (after an accepted step): at most four Gauss-Newton
/// corrections in the mass metric while a holding row's error, or a limit's overshoot, exceeds `tolerance` (m or
/// rad); then the velocity correction that removes every holding row's speed and every closing speed of a limit at
/// its limit (pushing only). Returns whether y changed.
pub(crate) fn project_joints(model: &Model, y: &mut [f64], tolerance: f64) -> bool {
    if model.joints.is_empty() {
        return false;
    }
    let l = model.layout;
    let mut changed = false;
    for _ in 0..4 {
        let (rows, ends) = model.all_rows(y, false);
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
        let c: Vec<f64> = off.iter().map(|(_, r)| -r.error).collect();
        let bounds: Vec<(f64, f64)> = off.iter().map(|(_, r)| push_only(r)).collect();
        let delta = solve(&row_matrix(model, &off, &ends), &c, &bounds);
        for ((j, r), &d) in off.iter().zip(delta.iter()) {
            let cj = &model.joints[*j];
            for (end, lin, ang, s) in [(cj.a, -r.lin, r.ang_a, &ends[*j].0), (cj.b, r.lin, r.ang_b, &ends[*j].1)] {
                if let ResolvedBody::Dynamic(i) = end {
                    add3(y, l.bx(i), &(lin * (d * s.inv_mass)));
                    let turn = UnitQuaternion::from_scaled_axis(s.inv_inertia * ang * d);
                    let qn = turn * UnitQuaternion::new_normalize(get_quat(y, l.bq(i)));
                    set_quat(y, l.bq(i), &qn);
                }
            }
        }
        changed = true;
    }
    let (rows, ends) = model.all_rows(y, false);
    let (mut held, mut speeds) = (Vec::new(), Vec::new());
    for (j, r) in rows {
        let speed = row_speed(&r, &ends[j]);
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
    let want: Vec<f64> = speeds.iter().map(|s| -s).collect();
    let mu = solve(&row_matrix(model, &held, &ends), &want, &bounds);
    // impulses straight into the momenta (the state's P and L)
    for ((j, r), &m) in held.iter().zip(mu.iter()) {
        push_row(model, y, 0, *j, r, m);
    }
    true
}

/// The joints' rows for a velocity step of h from y (the contact steps): holding rows J v = 0 at the step's end
/// (the position error is projected away after the step, `project_joints`: a velocity that pulls it back would
/// differ between a step and its two halves by the error itself, at any step size), limits and ropes J v >= what
/// closes them within the step, motors their speed within their force over h; springs are forces. A dynamic end is
/// its actor, a fixed end an extra fixed actor numbered from `first_extra` and returned. Each row comes with its
/// joint's index and B's anchor from B's centre (for the joint's load).
pub(crate) fn bilateral_rows(model: &Model, y: &[f64], h: f64, first_extra: usize) -> BilateralRows {
    use tumble_contact::BilateralKind;
    let l = model.layout;
    let (mut out, mut extra, mut owners) = (Vec::new(), Vec::new(), Vec::new());
    let mut scratch = Vec::new();
    for (k, cj) in model.holding_joints() {
        let mut index = |end: ResolvedBody| match end {
            ResolvedBody::Dynamic(j) => l.body_actor(j),
            ResolvedBody::Fixed(p) => {
                extra.push(tumble_contact::BodyState::fixed(nalgebra::Point3::from(p.translation.vector)));
                first_extra + extra.len() - 1
            }
        };
        let (a, b) = (index(cj.a), index(cj.b));
        let (ea, eb) = (model.end_state_of(y, cj.a), model.end_state_of(y, cj.b));
        let rb = eb.q * cj.anchor_b;
        scratch.clear();
        tumble_contact::joint_rows(&cj.joint, &cj.frame(&ea, &eb), &ea.x, &eb.x, None, &mut scratch);
        for r in &scratch {
            let (kind, speed) = match r.kind {
                RowKind::Equality => (BilateralKind::Equal, 0.0),
                // a limit may close within the step, and holds at it (its overshoot is projected away)
                RowKind::Lower => {
                    // only a limit the step can reach: one far from it would ask for a speed of its gap over h,
                    // which grows without bound as the steps shrink and swamps the program's scale
                    let closing = -r.speed(&ea.v, &ea.w, &eb.v, &eb.w);
                    if r.error > 2.0 * h * closing.max(0.0) {
                        continue;
                    }
                    (BilateralKind::AtLeast, if r.error > 0.0 { -r.error / h } else { 0.0 })
                }
                RowKind::Motor { speed, max_force } => (BilateralKind::Motor { max_impulse: max_force * h }, speed),
                RowKind::Spring { .. } => continue,
            };
            out.push(tumble_contact::BilateralRow { a, b, lin: r.lin, ang_a: r.ang_a, ang_b: r.ang_b, speed, kind });
            owners.push((k, rb));
        }
    }
    BilateralRows { rows: out, extra, owners }
}

/// The joints' rows of a velocity step, the fixed ends' extra actors, and each row's joint with B's anchor.
pub(crate) struct BilateralRows {
    pub rows: Vec<tumble_contact::BilateralRow>,
    pub extra: Vec<tumble_contact::BodyState>,
    pub owners: Vec<(usize, Vector3<f64>)>,
}

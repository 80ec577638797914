//! One island of the velocity step assembled for clarabel's interior point and read back (the reference the Newton
//! method is tested against, and the answer where it has none). Variables: the velocities of the
//! island's moving bodies (3 for a particle, 6 for a rigid body) and, with lagged friction, one epigraph variable
//! per frictional contact. Objective 1/2 v^T M v - (M v*)^T v (+ sum mu p_prev s). Rows per contact: Anitescu's cone
//! (J_n v + beta, mu J_t v) in SOC(3), or frictionless J_n v + beta >= 0, or lagged J_n v + beta >= 0 with
//! (s, J_t v) in SOC(3); then joint rows J v = speed (a zero cone).

use super::check::residual;
use super::island::{bias, moved_by_joints, row_layout, velocities_of, IslandSolution, Rows};
use super::problem::{BilateralKind, BilateralRow};
use super::settings::StepSettings;
use crate::body::BodyState;
use crate::contact::{tangents, Contact};
use crate::error::ContactError;
use crate::impulse::BodyVelocity;
use crate::jacobian::{rows, Row};
use crate::lcp::{clarabel_settings, usable, with_retries};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT, SupportedConeT, ZeroConeT};
use nalgebra::Vector3;

/// Triplets of the constraint matrix.
#[derive(Default)]
struct Sparse {
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
}

impl Sparse {
    fn push(&mut self, r: usize, c: usize, v: f64) {
        self.rows.push(r);
        self.cols.push(c);
        self.vals.push(v);
    }
}

/// The island's program for clarabel, solved (with retries at looser tolerances) and read back. `layout`: each
/// moving body's first unknown, the moving bodies, and the unknowns in all; `building`: the time already spent
/// building the island's programs.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_island(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    island: &[usize],
    bilateral: &[&BilateralRow],
    free: &[BodyVelocity],
    s: &StepSettings,
    (offset, members, n): (&[usize], &[usize], usize),
    mut building: f64,
) -> Result<IslandSolution, ContactError> {
    let clock = std::time::Instant::now();
    let (layout, vars) = row_layout(contacts, bounds, island, n);
    // P = M (upper triangle), q = -M v* (and the bounds on the epigraph variables).
    let (mut pi, mut pj, mut pv): (Vec<usize>, Vec<usize>, Vec<f64>) = (Vec::new(), Vec::new(), Vec::new());
    let mut q = vec![0.0; vars];
    for &k in members {
        let (b, o, v) = (&bodies[k], offset[k], &free[k]);
        let m = 1.0 / b.inv_mass;
        for d in 0..3 {
            pi.push(o + d);
            pj.push(o + d);
            pv.push(m);
            q[o + d] = -m * v.linear[d];
        }
        if b.rotates() {
            let iw = b.inertia * v.angular;
            for r in 0..3 {
                q[o + 3 + r] = -iw[r];
                for c in r..3 {
                    pi.push(o + 3 + r);
                    pj.push(o + 3 + c);
                    pv.push(b.inertia[(r, c)]);
                }
            }
        }
    }
    for rows in &layout {
        if let Rows::Lagged { s, bound } = *rows {
            q[s] = bound;
        }
    }
    // Constraints A x + s = b, s in the cones.
    let mut a = Sparse::default();
    let mut rhs: Vec<f64> = Vec::new();
    let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
    let put_row = |a: &mut Sparse, row: usize, scale: f64, pair: &[Row; 2], rhs: &mut Vec<f64>| {
        for r in pair {
            let b = &bodies[r.body];
            if !b.is_dynamic() {
                rhs[row] += scale * (r.lin.dot(&free[r.body].linear) + r.ang.dot(&free[r.body].angular));
                continue;
            }
            let o = offset[r.body];
            for d in 0..3 {
                a.push(row, o + d, -scale * r.lin[d]);
                if b.rotates() {
                    a.push(row, o + 3 + d, -scale * r.ang[d]);
                }
            }
        }
    };
    for (slot, &i) in island.iter().enumerate() {
        let c = &contacts[i];
        let nrm = c.normal.into_inner();
        let row0 = rhs.len();
        rhs.extend(std::iter::repeat_n(0.0, layout[slot].width()));
        rhs[row0] = bias(c, bodies, s);
        put_row(&mut a, row0, 1.0, &rows(c, bodies, &nrm), &mut rhs);
        let (t1, t2) = tangents(&nrm);
        match layout[slot] {
            Rows::Frictionless => cones.push(NonnegativeConeT(1)),
            Rows::Cone => {
                put_row(&mut a, row0 + 1, c.friction, &rows(c, bodies, &t1), &mut rhs);
                put_row(&mut a, row0 + 2, c.friction, &rows(c, bodies, &t2), &mut rhs);
                cones.push(SecondOrderConeT(3));
            }
            Rows::Lagged { s: var, .. } => {
                a.push(row0 + 1, var, -1.0);
                put_row(&mut a, row0 + 2, 1.0, &rows(c, bodies, &t1), &mut rhs);
                put_row(&mut a, row0 + 3, 1.0, &rows(c, bodies, &t2), &mut rhs);
                cones.push(NonnegativeConeT(1));
                cones.push(SecondOrderConeT(3));
            }
        }
    }
    // joint rows after the contacts': J v = speed (a zero cone), then J v >= speed (limits, ropes), then motors
    // (J v - speed within an epigraph variable t costing max_impulse t: their impulse within +-max_impulse)
    let mut joint_z: Vec<(usize, bool)> = vec![(0, false); bilateral.len()];
    let mut vars = vars;
    let mut motor_costs = Vec::new();
    for pass in 0..3 {
        let start = rhs.len();
        for (k, r) in bilateral.iter().enumerate() {
            let which = match r.kind {
                BilateralKind::Equal => 0,
                BilateralKind::AtLeast => 1,
                BilateralKind::Motor { .. } => 2,
            };
            if which != pass {
                continue;
            }
            let pair = [Row { body: r.a, lin: -r.lin, ang: r.ang_a }, Row { body: r.b, lin: r.lin, ang: r.ang_b }];
            let row = rhs.len();
            joint_z[k] = (row, pass == 2);
            if let BilateralKind::Motor { max_impulse } = r.kind {
                // t - (J v - speed) >= 0 and t + (J v - speed) >= 0
                let t = vars;
                vars += 1;
                motor_costs.push(max_impulse);
                rhs.push(r.speed);
                put_row(&mut a, row, -1.0, &pair, &mut rhs);
                a.push(row, t, -1.0);
                rhs.push(-r.speed);
                put_row(&mut a, row + 1, 1.0, &pair, &mut rhs);
                a.push(row + 1, t, -1.0);
            } else {
                rhs.push(-r.speed);
                put_row(&mut a, row, 1.0, &pair, &mut rhs);
            }
        }
        let n = rhs.len() - start;
        if n > 0 {
            cones.push(if pass == 0 { ZeroConeT(n) } else { NonnegativeConeT(n) });
        }
    }
    q.extend(motor_costs);
    let m = rhs.len();
    // clarabel's absolute tolerances assume data of order one: measure masses in units of the largest diagonal
    // entry of M (m_s) and velocities in units of the largest free or target velocity (v_s). With x = v_s x',
    // the problem 1/2 x'^T (P / m_s) x' + (q / (m_s v_s))^T x' s.t. A x' + s' = b / v_s has the same cones; the
    // original duals (impulses) are z = m_s v_s z'. (Particles of 2 g moving at centimetres per second otherwise
    // hit the absolute tolerances long before the answer is right.)
    let m_s = pv.iter().zip(pi.iter().zip(&pj)).filter(|(_, (i, j))| i == j).fold(0.0f64, |acc, (v, _)| acc.max(*v));
    let v_s = members
        .iter()
        .flat_map(|&k| [free[k].linear.norm(), free[k].angular.norm()])
        .chain(rhs.iter().map(|b| b.abs()))
        .fold(0.0f64, f64::max);
    let (m_s, v_s) = (if m_s > 0.0 { m_s } else { 1.0 }, if v_s > 0.0 { v_s } else { 1.0 });
    pv.iter_mut().for_each(|v| *v /= m_s);
    let q: Vec<f64> = q.iter().map(|v| v / (m_s * v_s)).collect();
    let rhs_scaled: Vec<f64> = rhs.iter().map(|b| b / v_s).collect();
    let p = CscMatrix::new_from_triplets(vars, vars, pi, pj, pv);
    let a = CscMatrix::new_from_triplets(m, vars, a.rows, a.cols, a.vals);
    let problem = "friction-step";
    building += clock.elapsed().as_secs_f64();
    let (solution, _, iterations) = with_retries(&s.solver, problem, |settings| {
        let mut solver = DefaultSolver::new(&p, &q, &a, &rhs_scaled, &cones, clarabel_settings(settings, problem)?)
            .map_err(|e| ContactError::Solver { problem, status: format!("{e:?}"), iterations: 0 })?;
        solver.solve();
        let sol = &solver.solution;
        usable(sol.status, sol.iterations, problem)?;
        let x: Vec<f64> = sol.x.iter().map(|v| v * v_s).collect();
        let z: Vec<f64> = sol.z.iter().map(|v| v * m_s * v_s).collect();
        let mut out = read_back(bodies, contacts, island, &layout, offset, members, &x, &z);
        // the joints' impulses (the zero cone's duals, pushing as J^T z) are judged as part of the free motion: the
        // contacts' conditions are checked against them
        out.joints = joint_z.iter().map(|&(row, motor)| if motor { z[row + 1] - z[row] } else { z[row] }).collect();
        let r = if bilateral.is_empty() {
            residual(bodies, contacts, island, &layout, free, &out, s)
        } else {
            residual(bodies, contacts, island, &layout, &moved_by_joints(bodies, bilateral, free, &out.joints), &out, s)
        };
        Ok((out, r, sol.iterations))
    })?;
    Ok(IslandSolution { iterations, building_seconds: building, ..solution })
}

/// Velocities from the primal solution, impulses from the duals.
#[allow(clippy::too_many_arguments)]
fn read_back(
    bodies: &[BodyState],
    contacts: &[Contact],
    island: &[usize],
    layout: &[Rows],
    offset: &[usize],
    members: &[usize],
    x: &[f64],
    z: &[f64],
) -> IslandSolution {
    let velocities = velocities_of(bodies, members, offset, x);
    let (mut normal, mut friction) = (Vec::new(), Vec::new());
    let mut row = 0;
    for (slot, &i) in island.iter().enumerate() {
        let c = &contacts[i];
        let (t1, t2) = tangents(&c.normal);
        normal.push(z[row].max(0.0));
        friction.push(match layout[slot] {
            Rows::Frictionless => Vector3::zeros(),
            Rows::Cone => (t1 * z[row + 1] + t2 * z[row + 2]) * c.friction,
            Rows::Lagged { .. } => t1 * z[row + 2] + t2 * z[row + 3],
        });
        row += layout[slot].width();
    }
    IslandSolution {
        velocities,
        normal,
        friction,
        iterations: 0,
        solved: true,
        newton: false,
        building_seconds: 0.0,
        joints: Vec::new(),
    }
}

//! One island of the time-stepping program, assembled for clarabel and read back. Variables: the velocities of the
//! island's moving bodies (3 for a particle, 6 for a rigid body) and, with lagged friction, one epigraph variable
//! per frictional contact. Objective 1/2 v^T M v - (M v*)^T v (+ sum mu p_prev s). Rows per contact: Anitescu's cone
//! (J_n v + beta, mu J_t v) in SOC(3), or frictionless J_n v + beta >= 0, or lagged J_n v + beta >= 0 with
//! (s, J_t v) in SOC(3); then joint rows J v = speed (a zero cone).

use crate::body::BodyState;
use crate::contact::{tangents, Contact};
use crate::error::ContactError;
use crate::friction::StepSettings;
use crate::impulse::BodyVelocity;
use crate::island_check::{residual, untouched};
use crate::jacobian::{rows, Row};
use crate::lcp::{usable, with_retries};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT, SupportedConeT, ZeroConeT};
use nalgebra::Vector3;

pub(crate) struct IslandSolution {
    pub velocities: Vec<(usize, BodyVelocity)>,
    pub normal: Vec<f64>,
    pub friction: Vec<Vector3<f64>>,
    pub iterations: u32,
    /// Whether a solver was called (an island no contact of which needs an impulse is answered without one).
    pub solved: bool,
    /// Whether the Newton method gave the answer (not clarabel).
    pub newton: bool,
    /// Wall time spent building the island's programs (s).
    pub building_seconds: f64,
    /// The impulse of each of the island's joint rows (in the order given; empty without).
    pub joints: Vec<f64>,
}

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

/// How a contact's rows are laid out.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Rows {
    /// One nonnegative row.
    Frictionless,
    /// Anitescu's SOC(3) on (normal, mu t1, mu t2).
    Cone,
    /// A nonnegative normal row, then SOC(3) on (s, t1, t2) with epigraph variable `s` and bound `bound`.
    Lagged { s: usize, bound: f64 },
}

impl Rows {
    fn width(self) -> usize {
        match self {
            Rows::Frictionless => 1,
            Rows::Cone => 3,
            Rows::Lagged { .. } => 4,
        }
    }
}

/// Each contact's rows (lagged friction's epigraph variables numbered from `first_var`), and the variables in all.
pub(crate) fn row_layout(
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    island: &[usize],
    first_var: usize,
) -> (Vec<Rows>, usize) {
    let mut vars = first_var;
    let layout = island
        .iter()
        .map(|&i| {
            let c = &contacts[i];
            match bounds {
                _ if c.friction == 0.0 => Rows::Frictionless,
                None => Rows::Cone,
                Some(b) if b[i] * c.friction > 0.0 => {
                    vars += 1;
                    Rows::Lagged { s: vars - 1, bound: b[i] * c.friction }
                }
                Some(_) => Rows::Frictionless,
            }
        })
        .collect();
    (layout, vars)
}

/// The constraint bias of a contact: speculative gap or penetration correction, and restitution.
pub(crate) fn bias(c: &Contact, bodies: &[BodyState], s: &StepSettings) -> f64 {
    let h = s.dt;
    let v_minus = c.relative_normal_velocity(bodies);
    let by_gap = if c.distance > 0.0 { c.distance / h } else { s.erp * c.distance / h };
    let closes_this_step = c.distance + h * v_minus <= 0.0;
    if c.restitution > 0.0 && v_minus < -s.bounce_threshold && closes_this_step {
        // The bounce at the step's start, then what the applied forces do to the normal velocity over the rest of
        // the step: a ball bouncing with e = 1 then keeps its energy to O(h^2) instead of gaining m g h v.
        let moved = |k: usize| {
            let f = crate::friction::free_velocity(&bodies[k], h);
            BodyState { velocity: f.linear, angular_velocity: f.angular, ..bodies[k] }
        };
        let (a, b) = (moved(c.a), moved(c.b));
        let v_free = c.normal.dot(&(b.point_velocity(&c.point) - a.point_velocity(&c.point)));
        by_gap.min(c.restitution * v_minus - (v_free - v_minus))
    } else {
        by_gap
    }
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_island(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    island: &[usize],
    bilateral: &[&crate::friction::BilateralRow],
    free: &[BodyVelocity],
    s: &StepSettings,
    warm: Option<&[Vector3<f64>]>,
) -> Result<IslandSolution, ContactError> {
    // Velocity variables: 3 per moving particle, 6 per moving rigid body.
    let mut offset = vec![usize::MAX; bodies.len()];
    let mut members = Vec::new();
    let mut n = 0;
    let ends = island.iter().flat_map(|&i| [contacts[i].a, contacts[i].b]);
    for k in ends.chain(bilateral.iter().flat_map(|r| [r.a, r.b])) {
        if bodies[k].is_dynamic() && offset[k] == usize::MAX {
            offset[k] = n;
            members.push(k);
            n += if bodies[k].rotates() { 6 } else { 3 };
        }
    }
    if bilateral.is_empty() {
        if let Some(untouched) = untouched(bodies, contacts, bounds, island, &members, free, s) {
            return Ok(untouched);
        }
    }
    // tumble's own solver first (lagged friction or none), its answer held to the same test as clarabel's
    let mut building = 0.0;
    let lagged_or_frictionless = bounds.is_some() || island.iter().all(|&i| contacts[i].friction == 0.0);
    if s.method == crate::friction::StepMethod::Newton && lagged_or_frictionless {
        let zeros = vec![0.0; contacts.len()];
        let b = bounds.unwrap_or(&zeros);
        let input = crate::newton_program::Island {
            bodies,
            contacts,
            bounds: b,
            island,
            bilateral,
            free,
            s,
            offset: &offset,
            members: &members,
            n,
        };
        let answer = crate::newton_island::solve_island_newton(&input, warm, &mut building);
        if let Some((out, joints)) = answer {
            let (layout, _) = row_layout(contacts, bounds, island, n);
            let moved = moved_by_joints(bodies, bilateral, free, &joints);
            if residual(bodies, contacts, island, &layout, &moved, &out, s) <= s.solver.complementarity_tolerance {
                return Ok(IslandSolution { building_seconds: building, joints, ..out });
            }
        }
    }
    let clock = std::time::Instant::now();
    let (layout, vars) = row_layout(contacts, bounds, island, n);
    // P = M (upper triangle), q = -M v* (and the bounds on the epigraph variables).
    let (mut pi, mut pj, mut pv): (Vec<usize>, Vec<usize>, Vec<f64>) = (Vec::new(), Vec::new(), Vec::new());
    let mut q = vec![0.0; vars];
    for &k in &members {
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
                crate::friction::BilateralKind::Equal => 0,
                crate::friction::BilateralKind::AtLeast => 1,
                crate::friction::BilateralKind::Motor { .. } => 2,
            };
            if which != pass {
                continue;
            }
            let pair = [
                crate::jacobian::Row { body: r.a, lin: -r.lin, ang: r.ang_a },
                crate::jacobian::Row { body: r.b, lin: r.lin, ang: r.ang_b },
            ];
            let row = rhs.len();
            joint_z[k] = (row, pass == 2);
            if let crate::friction::BilateralKind::Motor { max_impulse } = r.kind {
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
        let mut solver = DefaultSolver::new(&p, &q, &a, &rhs_scaled, &cones, settings.clarabel(problem)?)
            .map_err(|e| ContactError::Solver { problem, status: format!("{e:?}"), iterations: 0 })?;
        solver.solve();
        let sol = &solver.solution;
        usable(sol.status, sol.iterations, problem)?;
        let x: Vec<f64> = sol.x.iter().map(|v| v * v_s).collect();
        let z: Vec<f64> = sol.z.iter().map(|v| v * m_s * v_s).collect();
        let mut out = read_back(bodies, contacts, island, &layout, &offset, &members, &x, &z);
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

/// The free velocities with the joint rows' impulses applied (what the contacts' conditions are judged against).
fn moved_by_joints(
    bodies: &[BodyState],
    bilateral: &[&crate::friction::BilateralRow],
    free: &[BodyVelocity],
    impulses: &[f64],
) -> Vec<BodyVelocity> {
    let mut moved = free.to_vec();
    for (r, &p) in bilateral.iter().zip(impulses) {
        for (k, lin, ang) in [(r.a, -r.lin, r.ang_a), (r.b, r.lin, r.ang_b)] {
            let b = &bodies[k];
            if b.is_dynamic() {
                moved[k].linear += lin * (p * b.inv_mass);
                moved[k].angular += b.inv_inertia * ang * p;
            }
        }
    }
    moved
}

/// Each member's velocities read from the unknowns x (3 for a particle, 6 for a rigid body, from `offset`).
pub(crate) fn velocities_of(
    bodies: &[BodyState],
    members: &[usize],
    offset: &[usize],
    x: &[f64],
) -> Vec<(usize, BodyVelocity)> {
    members
        .iter()
        .map(|&k| {
            let o = offset[k];
            let linear = Vector3::new(x[o], x[o + 1], x[o + 2]);
            let angular =
                if bodies[k].rotates() { Vector3::new(x[o + 3], x[o + 4], x[o + 5]) } else { Vector3::zeros() };
            (k, BodyVelocity { linear, angular })
        })
        .collect()
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

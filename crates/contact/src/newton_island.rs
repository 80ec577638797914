//! One island of the velocity step solved by tumble's own method (the default; clarabel stays as the reference):
//! the method of multipliers on the island's impulses, each subproblem a smooth convex function of the velocities
//! minimised by Newton's method with an exact line search, after Drake's SAP (Castro et al. 2022) but converging
//! to the rigid program itself instead of a regularised one.
//!
//! The program (lagged friction): find impulses lambda in K (normal >= 0, friction in a disc of radius mu p_prev,
//! joint rows free, >= 0 or within a motor's bound) minimising 1/2 lambda^T A lambda + lambda^T (J v* + c), with
//! A = J M^-1 J^T; the velocities are v = v* + M^-1 J^T lambda. Proximal point on lambda (weight 1 / rho per
//! block, rho = `STIFFNESS` / A_ii) turns each outer iteration into: minimise over v
//! l(v) = 1/2 |v - v*|_M^2 - sum_i min_{l in K_i} [l . u_i + |l - lambda_k,i|^2 / (2 rho_i)], u = J v + c,
//! whose minimiser over l is the projection P_K(lambda_k - rho u) in closed form. l is convex and piecewise
//! quadratic, with gradient M (v - v*) - J^T P_K(..) and generalised Hessian M + J^T rho dP_K J (positive definite:
//! M is). The outer iteration stops when lambda no longer moves: then lambda = P_K(lambda - rho u), the exact
//! optimality conditions of the rigid program, so nothing of the proximal weight remains in the answer.

use crate::body::BodyState;
use crate::contact::{tangents, Contact};
use crate::friction::{BilateralKind, BilateralRow, StepSettings};
use crate::friction_island::{bias, IslandSolution};
use crate::impulse::BodyVelocity;
use crate::jacobian::{rows, Row};
use faer::linalg::solvers::Solve;
use nalgebra::{DVector, Matrix3, Vector3};

/// The proximal weight as a multiple of each block's own inverse effective mass: each outer iteration shrinks the
/// distance to the optimum by about 1 / (1 + STIFFNESS) along the block's own direction, while the Hessian's
/// condition grows by about that factor.
const STIFFNESS: f64 = 1e3;
/// The first outer iteration's weight, raised tenfold each iteration up to `STIFFNESS` (a continuation: a soft
/// first subproblem has few kinks for Newton's method to cross and finds most of the active set; each stiffer one
/// starts from the last's answer).
const FIRST_STIFFNESS: f64 = 1e2;
/// How far the proximal weight may be raised over `STIFFNESS` in slow iterations (the Hessian's condition grows
/// with it: at 1e6 it stays far from f64's limits for masses within 1e4 of each other).
const GROWTH_LIMIT: f64 = 1e6;
/// Most outer (multiplier) iterations before the island is handed to clarabel.
const MAX_OUTER: usize = 60;
/// Most Newton iterations of one subproblem.
const MAX_NEWTON: usize = 40;
/// The accuracy the answer is driven to, relative to the island's velocity scale (far inside what the step's
/// checks accept, so the closed-form tests keep their precision; Newton's last iterations converge quadratically,
/// so the margin costs about one iteration).
const RELATIVE: f64 = 1e-10;
/// Islands with more velocity unknowns than this go to clarabel (the dense factorisation, faer's Cholesky, is
/// O(n^3)).
pub(crate) const MAX_DOFS: usize = 600;

/// What set a block's impulse lies in.
#[derive(Clone, Copy)]
enum Set {
    /// One row, its impulse within [lo, hi].
    Interval { lo: f64, hi: f64 },
    /// Two rows, their impulse within a disc of this radius.
    Disc(f64),
}

/// One block of rows: its first row, its set and its proximal weight.
#[derive(Clone, Copy)]
struct Block {
    row: usize,
    set: Set,
    rho: f64,
    /// rho as a multiple of the block's inverse effective mass (`STIFFNESS`, raised where the iteration is slow).
    stiffness: f64,
}

impl Block {
    fn width(&self) -> usize {
        match self.set {
            Set::Interval { .. } => 1,
            Set::Disc(_) => 2,
        }
    }

    /// The projection of y onto the block's set (into `out`), and its derivative (1 x 1 or 2 x 2, row-major).
    fn project(&self, y: &[f64], out: &mut [f64]) -> [f64; 4] {
        match self.set {
            Set::Interval { lo, hi } => {
                out[0] = y[0].clamp(lo, hi);
                [if lo < y[0] && y[0] < hi { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0]
            }
            Set::Disc(r) => {
                let n = (y[0] * y[0] + y[1] * y[1]).sqrt();
                if n <= r {
                    out[..2].copy_from_slice(&y[..2]);
                    [1.0, 0.0, 0.0, 1.0]
                } else {
                    let (d0, d1, s) = (y[0] / n, y[1] / n, r / n);
                    out[0] = r * d0;
                    out[1] = r * d1;
                    [s * (1.0 - d0 * d0), -s * d0 * d1, -s * d0 * d1, s * (1.0 - d1 * d1)]
                }
            }
        }
    }
}

/// A Jacobian row over the island's unknowns: up to twelve (index, value) entries, and its constant.
#[derive(Clone, Default)]
struct SparseRow {
    entries: Vec<(usize, f64)>,
    c: f64,
}

impl SparseRow {
    fn dot(&self, v: &[f64]) -> f64 {
        self.entries.iter().map(|&(i, x)| x * v[i]).sum::<f64>()
    }
}

/// One body's block of the mass matrix: its first unknown, its mass, and its inertia and inverse for a rigid body.
struct MassBlock {
    at: usize,
    mass: f64,
    inertia: Option<(Matrix3<f64>, Matrix3<f64>)>,
}

/// The island as the Newton iteration sees it.
struct Program {
    /// The mass matrix over the unknowns, block by block.
    mass: Vec<MassBlock>,
    /// The free velocities v*.
    free: DVector<f64>,
    rows: Vec<SparseRow>,
    blocks: Vec<Block>,
}

/// What the island's rows are: each contact's normal row and (with a friction bound) its two tangent rows, then the
/// joint rows; the velocity unknowns numbered by `offset`.
#[allow(clippy::too_many_arguments)]
fn program(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: &[f64],
    island: &[usize],
    bilateral: &[&BilateralRow],
    free: &[BodyVelocity],
    s: &StepSettings,
    offset: &[usize],
    members: &[usize],
    n: usize,
) -> Program {
    let mut mass = Vec::with_capacity(members.len());
    let mut v_free = DVector::zeros(n);
    for &k in members {
        let (b, o) = (&bodies[k], offset[k]);
        for d in 0..3 {
            v_free[o + d] = free[k].linear[d];
        }
        if b.rotates() {
            for d in 0..3 {
                v_free[o + 3 + d] = free[k].angular[d];
            }
        }
        let inertia = b.rotates().then_some((b.inertia, b.inv_inertia));
        mass.push(MassBlock { at: o, mass: 1.0 / b.inv_mass, inertia });
    }
    let sparse = |parts: &[Row; 2], c: f64| {
        let mut row = SparseRow { entries: Vec::with_capacity(12), c };
        for p in parts {
            let b = &bodies[p.body];
            if !b.is_dynamic() {
                row.c += p.lin.dot(&free[p.body].linear) + p.ang.dot(&free[p.body].angular);
                continue;
            }
            let o = offset[p.body];
            row.entries.extend((0..3).map(|d| (o + d, p.lin[d])));
            if b.rotates() {
                row.entries.extend((0..3).map(|d| (o + 3 + d, p.ang[d])));
            }
        }
        row
    };
    // A_ii: the row's inverse effective mass, for its proximal weight
    let diagonal = |r: &SparseRow| {
        let mut sum = 0.0;
        for &k in members {
            let (o, b) = (offset[k], &bodies[k]);
            let part = |d: usize| r.entries.iter().filter(|(i, _)| *i == o + d).map(|e| e.1).sum::<f64>();
            let lin = Vector3::new(part(0), part(1), part(2));
            sum += lin.norm_squared() * b.inv_mass;
            if b.rotates() {
                let ang = Vector3::new(part(3), part(4), part(5));
                sum += ang.dot(&(b.inv_inertia * ang));
            }
        }
        sum.max(f64::MIN_POSITIVE)
    };
    let (mut out_rows, mut blocks) = (Vec::new(), Vec::new());
    for &i in island {
        let c = &contacts[i];
        let nrm = c.normal.into_inner();
        let normal = sparse(&rows(c, bodies, &nrm), bias(c, bodies, s));
        let rho = FIRST_STIFFNESS / diagonal(&normal);
        blocks.push(Block {
            row: out_rows.len(),
            set: Set::Interval { lo: 0.0, hi: f64::INFINITY },
            rho,
            stiffness: FIRST_STIFFNESS,
        });
        out_rows.push(normal);
        let radius = c.friction * bounds[i];
        if radius > 0.0 {
            let (t1, t2) = tangents(&nrm);
            let (r1, r2) = (sparse(&rows(c, bodies, &t1), 0.0), sparse(&rows(c, bodies, &t2), 0.0));
            let rho = 2.0 * FIRST_STIFFNESS / (diagonal(&r1) + diagonal(&r2));
            blocks.push(Block { row: out_rows.len(), set: Set::Disc(radius), rho, stiffness: FIRST_STIFFNESS });
            out_rows.extend([r1, r2]);
        }
    }
    for r in bilateral {
        let parts = [Row { body: r.a, lin: -r.lin, ang: r.ang_a }, Row { body: r.b, lin: r.lin, ang: r.ang_b }];
        let row = sparse(&parts, -r.speed);
        let (lo, hi) = match r.kind {
            BilateralKind::Equal => (f64::NEG_INFINITY, f64::INFINITY),
            BilateralKind::AtLeast => (0.0, f64::INFINITY),
            BilateralKind::Motor { max_impulse } => (-max_impulse, max_impulse),
        };
        let rho = FIRST_STIFFNESS / diagonal(&row);
        blocks.push(Block { row: out_rows.len(), set: Set::Interval { lo, hi }, rho, stiffness: FIRST_STIFFNESS });
        out_rows.push(row);
    }
    Program { mass, free: v_free, rows: out_rows, blocks }
}

impl Program {
    /// M x (inverse: M^-1 x).
    fn mass_times(&self, x: &DVector<f64>, inverse: bool) -> DVector<f64> {
        let mut out = DVector::zeros(x.len());
        for b in &self.mass {
            let o = b.at;
            let m = if inverse { 1.0 / b.mass } else { b.mass };
            for d in 0..3 {
                out[o + d] = m * x[o + d];
            }
            if let Some((i, inv)) = &b.inertia {
                let w = Vector3::new(x[o + 3], x[o + 4], x[o + 5]);
                let r = if inverse { inv * w } else { i * w };
                out.fixed_rows_mut::<3>(o + 3).copy_from(&r);
            }
        }
        out
    }

    /// u = J v + c.
    fn row_velocities(&self, v: &[f64]) -> Vec<f64> {
        self.rows.iter().map(|r| r.dot(v) + r.c).collect()
    }

    /// The subproblem's impulses P_K(lambda_k - rho u) at row velocities u, and each block's derivative.
    fn impulses(&self, prior: &[f64], u: &[f64], out: &mut [f64], derivatives: Option<&mut Vec<[f64; 4]>>) {
        let mut y = [0.0; 2];
        let mut ds = derivatives;
        for b in &self.blocks {
            let w = b.width();
            for k in 0..w {
                y[k] = prior[b.row + k] - b.rho * u[b.row + k];
            }
            let d = b.project(&y[..w], &mut out[b.row..b.row + w]);
            if let Some(ds) = ds.as_deref_mut() {
                ds.push(d);
            }
        }
    }

    /// J^T lambda over the unknowns.
    fn spread(&self, lambda: &[f64]) -> DVector<f64> {
        let mut out = DVector::zeros(self.free.len());
        for (r, l) in self.rows.iter().zip(lambda) {
            for &(i, x) in &r.entries {
                out[i] += x * l;
            }
        }
        out
    }

    /// The Hessian M + J^T rho dP J (its lower triangle) in `h`.
    fn hessian(&self, derivatives: &[[f64; 4]], h: &mut faer::Mat<f64>) {
        h.fill(0.0);
        for b in &self.mass {
            for d in 0..3 {
                h[(b.at + d, b.at + d)] = b.mass;
            }
            if let Some((i, _)) = &b.inertia {
                for r in 0..3 {
                    for c in 0..3 {
                        h[(b.at + 3 + r, b.at + 3 + c)] = i[(r, c)];
                    }
                }
            }
        }
        for (b, d) in self.blocks.iter().zip(derivatives) {
            let w = b.width();
            for p in 0..w {
                for q in 0..w {
                    let g = b.rho * d[p * 2 + q];
                    if g == 0.0 {
                        continue;
                    }
                    for &(i, x) in &self.rows[b.row + p].entries {
                        for &(j, y) in &self.rows[b.row + q].entries {
                            if i >= j {
                                h[(i, j)] += g * x * y;
                            }
                        }
                    }
                }
            }
        }
    }

    /// The slope of the subproblem along dv at v + alpha dv (and its second derivative), given u(v) and J dv.
    fn slope(
        &self,
        prior: &[f64],
        v: &DVector<f64>,
        dv: &DVector<f64>,
        du: (&[f64], &[f64]),
        alpha: f64,
    ) -> (f64, f64) {
        let (u0, jdv) = du;
        let u: Vec<f64> = u0.iter().zip(jdv).map(|(a, b)| a + alpha * b).collect();
        let mut lambda = vec![0.0; u.len()];
        let mut ds = Vec::with_capacity(self.blocks.len());
        self.impulses(prior, &u, &mut lambda, Some(&mut ds));
        let moved = v + dv * alpha - &self.free;
        let mdv = self.mass_times(dv, false);
        let mut first = mdv.dot(&moved) - jdv.iter().zip(&lambda).map(|(a, b)| a * b).sum::<f64>();
        let mut second = mdv.dot(dv);
        for (b, d) in self.blocks.iter().zip(&ds) {
            let w = b.width();
            for p in 0..w {
                for q in 0..w {
                    second += b.rho * d[p * 2 + q] * jdv[b.row + p] * jdv[b.row + q];
                }
            }
        }
        first = if first.is_finite() { first } else { f64::NAN };
        (first, second)
    }

    /// The exact minimiser of the subproblem along dv within (0, 1], by safeguarded Newton on the slope (convex and
    /// piecewise quadratic, so Newton is exact within a piece).
    fn line_search(&self, prior: &[f64], v: &DVector<f64>, dv: &DVector<f64>, u0: &[f64]) -> f64 {
        let jdv: Vec<f64> = self.rows.iter().map(|r| r.dot(dv.as_slice())).collect();
        let du = (u0, &jdv[..]);
        let (f0, _) = self.slope(prior, v, dv, du, 0.0);
        let (f1, _) = self.slope(prior, v, dv, du, 1.0);
        if !(f0 < 0.0) || f1 <= 0.0 {
            return 1.0;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        let mut alpha = 1.0;
        for _ in 0..50 {
            let (f, df) = self.slope(prior, v, dv, du, alpha);
            if f.abs() <= 1e-12 * f0.abs() {
                break;
            }
            if f < 0.0 {
                lo = alpha;
            } else {
                hi = alpha;
            }
            let newton = alpha - f / df;
            alpha = if df > 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
            if hi - lo <= 1e-14 {
                break;
            }
        }
        alpha
    }
}

/// The island's answer by the multiplier method, or `None` when it did not converge within its iteration limits
/// (the caller then asks clarabel), with the joint rows' impulses. The iteration starts from the `warm` impulses
/// (one world vector per contact, on B), or from each contact's lagged normal impulse.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_island_newton(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: &[f64],
    island: &[usize],
    bilateral: &[&BilateralRow],
    free: &[BodyVelocity],
    s: &StepSettings,
    offset: &[usize],
    members: &[usize],
    n: usize,
    warm: Option<&[Vector3<f64>]>,
) -> Option<(IslandSolution, Vec<f64>)> {
    if n == 0 || n > MAX_DOFS {
        return None;
    }
    let mut p = program(bodies, contacts, bounds, island, bilateral, free, s, offset, members, n);
    // the velocity scale the accuracy is measured on (the step's own, the free speeds and the rows' constants)
    let scale = p
        .free
        .iter()
        .map(|x| x.abs())
        .chain(p.rows.iter().map(|r| r.c.abs()))
        .fold(s.velocity_scale, f64::max)
        .max(f64::MIN_POSITIVE);
    let tolerance = RELATIVE * scale;
    // first impulses: each contact's given impulse (within its set), or its lagged normal impulse
    let mut lambda = vec![0.0; p.rows.len()];
    let mut block = 0;
    for &i in island {
        let c = &contacts[i];
        let b = p.blocks[block];
        lambda[b.row] = warm.map_or(bounds[i], |w| c.normal.dot(&w[i]).max(0.0));
        block += 1;
        if c.friction * bounds[i] > 0.0 {
            let b = p.blocks[block];
            if let (Some(w), Set::Disc(r)) = (warm, b.set) {
                let (t1, t2) = tangents(&c.normal);
                let (x, y) = (t1.dot(&w[i]), t2.dot(&w[i]));
                let shrink = (r / (x * x + y * y).sqrt().max(f64::MIN_POSITIVE)).min(1.0);
                lambda[b.row] = x * shrink;
                lambda[b.row + 1] = y * shrink;
            }
            block += 1;
        }
    }
    let mut v = &p.free + spread_scaled(&p, &lambda);
    let mut iterations = 0u32;
    let mut hessian = faer::Mat::<f64>::zeros(n, n);
    let mut converged = false;
    let mut last_moved = f64::INFINITY;
    for _ in 0..MAX_OUTER {
        let prior = lambda.clone();
        for _ in 0..MAX_NEWTON {
            iterations += 1;
            let u = p.row_velocities(v.as_slice());
            let mut ds = Vec::with_capacity(p.blocks.len());
            p.impulses(&prior, &u, &mut lambda, Some(&mut ds));
            let gradient = p.mass_times(&(&v - &p.free), false) - p.spread(&lambda);
            p.hessian(&ds, &mut hessian);
            let llt = hessian.llt(faer::Side::Lower).ok()?;
            let mut dv = faer::Col::<f64>::from_fn(n, |i| -gradient[i]);
            llt.solve_in_place(dv.as_mat_mut());
            let dv = DVector::from_fn(n, |i, _| dv[i]);
            let alpha = p.line_search(&prior, &v, &dv, &u);
            let step = &dv * alpha;
            v += &step;
            if !v.iter().all(|x| x.is_finite()) {
                return None;
            }
            if largest_speed(&p, members, offset, &step) <= tolerance {
                break;
            }
        }
        let u = p.row_velocities(v.as_slice());
        p.impulses(&prior, &u, &mut lambda, None);
        // the rows' velocity violation the last multiplier update measured: (lambda - prior) / rho
        let moved = p
            .blocks
            .iter()
            .flat_map(|b| (0..b.width()).map(move |k| (b.row + k, b.rho)))
            .fold(0.0f64, |m, (r, rho)| m.max((lambda[r] - prior[r]).abs() / rho));
        if moved <= tolerance {
            converged = true;
            break;
        }
        // an outer iteration that did not gain a digit: directions of the impulses far softer than their blocks'
        // own (a light body under a heavy one), which a stiffer proximal weight reaches faster
        let soft = p.blocks.iter().any(|b| b.stiffness < STIFFNESS);
        if soft || moved > 0.1 * last_moved {
            let most = if soft { STIFFNESS } else { STIFFNESS * GROWTH_LIMIT };
            for b in &mut p.blocks {
                let raised = (b.stiffness * 10.0).min(most);
                b.rho *= raised / b.stiffness;
                b.stiffness = raised;
            }
        }
        last_moved = moved;
    }
    if !converged {
        return None;
    }
    // velocities from the final impulses (the exact momentum balance), impulses read per contact
    let v = &p.free + spread_scaled(&p, &lambda);
    let velocities = members
        .iter()
        .map(|&k| {
            let o = offset[k];
            let linear = Vector3::new(v[o], v[o + 1], v[o + 2]);
            let angular =
                if bodies[k].rotates() { Vector3::new(v[o + 3], v[o + 4], v[o + 5]) } else { Vector3::zeros() };
            (k, BodyVelocity { linear, angular })
        })
        .collect();
    let (mut normal, mut friction) = (Vec::new(), Vec::new());
    let mut block = 0;
    for &i in island {
        let c = &contacts[i];
        let b = p.blocks[block];
        normal.push(lambda[b.row].max(0.0));
        block += 1;
        if c.friction * bounds[i] > 0.0 {
            let (t1, t2) = tangents(&c.normal);
            let r = p.blocks[block].row;
            friction.push(t1 * lambda[r] + t2 * lambda[r + 1]);
            block += 1;
        } else {
            friction.push(Vector3::zeros());
        }
    }
    let joints = p.blocks[block..].iter().map(|b| lambda[b.row]).collect();
    Some((IslandSolution { velocities, normal, friction, iterations, solved: true, newton: true }, joints))
}

/// M^-1 J^T lambda.
fn spread_scaled(p: &Program, lambda: &[f64]) -> DVector<f64> {
    p.mass_times(&p.spread(lambda), true)
}

/// The largest speed a velocity change gives a row (what any contact point or joint sees) or a body's centre.
fn largest_speed(p: &Program, members: &[usize], offset: &[usize], dv: &DVector<f64>) -> f64 {
    let rows = p.rows.iter().map(|r| r.dot(dv.as_slice()).abs()).fold(0.0f64, f64::max);
    let linear = members
        .iter()
        .map(|&k| Vector3::new(dv[offset[k]], dv[offset[k] + 1], dv[offset[k] + 2]).norm())
        .fold(0.0f64, f64::max);
    rows.max(linear)
}

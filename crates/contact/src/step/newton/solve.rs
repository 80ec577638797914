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

use super::hessian::Hessian;
use super::program::{program, Island, Program, Set};
use crate::contact::tangents;
use crate::step::island::{velocities_of, IslandSolution};
use nalgebra::{DVector, Vector3};

/// The proximal weight as a multiple of each block's own inverse effective mass: each outer iteration shrinks the
/// distance to the optimum by about 1 / (1 + STIFFNESS) along the block's own direction, while the Hessian's
/// condition grows by about that factor.
const STIFFNESS: f64 = 1e3;
/// How far the proximal weight may be raised over `STIFFNESS` in slow iterations (the Hessian's condition grows
/// with it: at 1e6 it stays far from f64's limits for masses within 1e4 of each other).
const GROWTH_LIMIT: f64 = 1e6;
/// Most outer (multiplier) iterations before the island is handed to clarabel.
const MAX_OUTER: usize = 60;
/// Most Newton iterations of one subproblem.
const MAX_NEWTON: usize = 40;
/// The accuracy each subproblem is solved to, relative to the island's velocity scale (Newton's last iterations
/// converge quadratically, so the margin costs about one iteration; subproblems solved more loosely slowed the
/// multiplier iteration: measured on the 20-cube pile, 0.01 times the last outer change took 60 Newton iterations a
/// program of its largest island against 41). The multiplier iteration stops at this accuracy too, or at the
/// caller's (`StepSettings::velocity_scale` times `SolverSettings::complementarity_tolerance`, the accuracy
/// clarabel's answers are checked to) where that is looser.
const RELATIVE: f64 = 1e-10;
/// Islands with more velocity unknowns than this go to clarabel (the Hessian is assembled in a dense square of
/// n^2 entries each Newton iteration, and its factorisation's cost grows with the fill).
pub(crate) const MAX_DOFS: usize = 600;

/// The island's answer by the multiplier method, or `None` when it did not converge within its iteration limits
/// (the caller then asks clarabel), with the joint rows' impulses. The iteration starts from the `warm` impulses
/// (one world vector per contact, on B), or from each contact's lagged normal impulse. The time spent building the
/// program (its rows and the Hessian's structure) is added to `building`.
pub(crate) fn solve_island_newton(
    input: &Island<'_>,
    warm: Option<&[Vector3<f64>]>,
    building: &mut f64,
) -> Option<(IslandSolution, Vec<f64>)> {
    let Island { bodies, contacts, bounds, island, s, offset, members, n, .. } = *input;
    if n == 0 || n > MAX_DOFS {
        return None;
    }
    let clock = std::time::Instant::now();
    let mut p = program(input);
    let hessian = Hessian::new(&p);
    *building += clock.elapsed().as_secs_f64();
    let mut hessian = hessian?;
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
            hessian.assemble(&p, &ds);
            let dv = hessian.solve(&-gradient)?;
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
        if moved <= tolerance.max(s.solver.complementarity_tolerance * s.velocity_scale) {
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
    let velocities = velocities_of(bodies, members, offset, v.as_slice());
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
    let solution = IslandSolution {
        velocities,
        normal,
        friction,
        iterations,
        solved: true,
        newton: true,
        building_seconds: 0.0,
        joints: Vec::new(),
    };
    Some((solution, joints))
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

//! The linear complementarity problems of contact, solved as convex QPs with clarabel: find f >= 0 with
//! w = A f + q >= 0 and f . w = 0, A symmetric positive semidefinite, is the KKT system of
//! min 1/2 f^T A f + q^T f subject to f >= 0.

use crate::error::ContactError;
use crate::lcp_problem::{residual, Triplets};
use crate::polish::polish;
use crate::solver_settings::SolverSettings;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};

/// clarabel's settings for `s`.
pub(crate) fn clarabel_settings(
    s: &SolverSettings,
    problem: &'static str,
) -> Result<clarabel::solver::DefaultSettings<f64>, ContactError> {
    let t = s.tolerance;
    DefaultSettingsBuilder::default()
        .verbose(false)
        .max_iter(s.max_iterations)
        .tol_gap_abs(t)
        .tol_gap_rel(t)
        .tol_feas(t)
        .tol_ktratio(t.sqrt().min(1e-6))
        .iterative_refinement_enable(s.iterative_refinement)
        .build()
        .map_err(|e| ContactError::Solver { problem, status: format!("settings: {e}"), iterations: 0 })
}

/// A solved complementarity problem.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LcpSolution {
    pub f: Vec<f64>,
    pub w: Vec<f64>,
    pub iterations: u32,
    pub residual: f64,
}

/// Whether clarabel's answer may be used, subject to the caller's own residual check: a solution, or an iterate it
/// could not polish further. Infeasibility certificates and numerical failures are errors.
pub(crate) fn usable(status: SolverStatus, iterations: u32, problem: &'static str) -> Result<(), ContactError> {
    match status {
        SolverStatus::Solved
        | SolverStatus::AlmostSolved
        | SolverStatus::InsufficientProgress
        | SolverStatus::MaxIterations => Ok(()),
        other => Err(ContactError::Solver { problem, status: format!("{other:?}"), iterations }),
    }
}

/// Runs `attempt` at the requested tolerance and, when its answer misses `complementarity_tolerance`, again at
/// 1e3 and 1e6 times looser tolerances (never looser than 1e-6): on degenerate problems (redundant contacts, a
/// cone's edge) clarabel sometimes stalls short of a very tight tolerance with a poor iterate, where a looser one
/// converges cleanly. Iterations of all attempts are counted. Returns the first answer whose residual passes.
pub(crate) fn with_retries<T>(
    settings: &SolverSettings,
    problem: &'static str,
    mut attempt: impl FnMut(&SolverSettings) -> Result<(T, f64, u32), ContactError>,
) -> Result<(T, f64, u32), ContactError> {
    let mut iterations = 0;
    let mut worst = 0.0f64;
    let mut failure = None;
    // Without refinement, the first retry turns it on; then the tolerance loosens (for a solve that stalls).
    let again = if settings.iterative_refinement { None } else { Some(1.0) };
    for (k, scale) in [Some(1.0), again, Some(1e3), Some(1e6)].into_iter().flatten().enumerate() {
        let tolerance = (settings.tolerance * scale).min(1e-6).max(settings.tolerance);
        let s = SolverSettings { tolerance, iterative_refinement: settings.iterative_refinement || k > 0, ..*settings };
        match attempt(&s) {
            Ok((value, residual, its)) => {
                iterations += its;
                if residual <= settings.complementarity_tolerance {
                    return Ok((value, residual, iterations));
                }
                worst = worst.max(residual);
            }
            Err(e @ ContactError::Solver { .. }) => failure = Some(e),
            Err(e) => return Err(e),
        }
        if tolerance >= 1e-6 {
            break;
        }
    }
    match failure {
        Some(e) if worst == 0.0 => Err(e),
        _ => Err(ContactError::Inaccurate { problem, residual: worst, tolerance: settings.complementarity_tolerance }),
    }
}

/// Solves LCP(A, q) through clarabel, checking its status and the complementarity of the answer.
pub(crate) fn solve(
    a: &Triplets,
    q: &[f64],
    settings: &SolverSettings,
    problem: &'static str,
) -> Result<LcpSolution, ContactError> {
    let n = q.len();
    if n == 0 {
        return Ok(LcpSolution { f: vec![], w: vec![], iterations: 0, residual: 0.0 });
    }
    if n == 1 {
        // One contact: f = max(0, -q / a), no solver needed (0 iterations).
        let a11 = a.diagonal()[0];
        if !(a11 > 0.0) {
            return Err(ContactError::Solver {
                problem,
                status: format!("a 1x1 system with a = {a11}"),
                iterations: 0,
            });
        }
        let f = (-q[0] / a11).max(0.0);
        let w = a11 * f + q[0];
        return Ok(LcpSolution { f: vec![f], w: vec![w], iterations: 0, residual: 0.0 });
    }
    // Redundant contacts (a box's four corners) leave A singular and the split of the load among them undetermined
    // by the equations; the interior point ends near the centre of the set of solutions (the symmetric split for a
    // symmetric box, to about 1e-8).
    let diagonal = a.diagonal();
    // clarabel's absolute tolerances assume data of order one: scale A by its largest diagonal entry and q by its
    // largest entry (an impulse between bodies that barely move has q near 1e-5), f by the inverse.
    let a_scale = diagonal.iter().fold(0.0f64, |m, d| m.max(*d));
    let q_scale = q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(a_scale > 0.0) {
        return Err(ContactError::Solver { problem, status: "A has no positive diagonal".into(), iterations: 0 });
    }
    if q_scale == 0.0 {
        return Ok(LcpSolution { f: vec![0.0; n], w: vec![0.0; n], iterations: 0, residual: 0.0 });
    }
    let mut scaled = a.clone();
    scaled.vals.iter_mut().for_each(|v| *v /= a_scale);
    let p = CscMatrix::new_from_triplets(scaled.n, scaled.n, scaled.rows, scaled.cols, scaled.vals);
    let q_unit: Vec<f64> = q.iter().map(|v| v / q_scale).collect();
    // f >= 0 as -f + s = 0, s in the nonnegative cone.
    let neg_identity = CscMatrix::new(n, n, (0..=n).collect(), (0..n).collect(), vec![-1.0; n]);
    let cones = [NonnegativeConeT(n)];
    let ((f, w), interior, iterations) = with_retries(settings, problem, |s| {
        let mut solver =
            DefaultSolver::new(&p, &q_unit, &neg_identity, &vec![0.0; n], &cones, clarabel_settings(s, problem)?)
                .map_err(|e| ContactError::Solver { problem, status: format!("{e:?}"), iterations: 0 })?;
        solver.solve();
        let sol = &solver.solution;
        usable(sol.status, sol.iterations, problem)?;
        // Interior points stay strictly positive: clamp the last ~1e-12 of negative rounding.
        let f: Vec<f64> = sol.x.iter().map(|&v| (v * q_scale / a_scale).max(0.0)).collect();
        let af = a.mul(&f);
        let w: Vec<f64> = af.iter().zip(q).map(|(x, y)| x + y).collect();
        let r = residual(&f, &w, q, &diagonal);
        Ok(((f, w), r, sol.iterations))
    })?;
    let ((f, w), worst) = match polish(a, q, &f, &w) {
        Some((pf, pw)) => {
            let r = residual(&pf, &pw, q, &diagonal);
            ((pf, pw), r)
        }
        None => ((f, w), interior),
    };
    Ok(LcpSolution { f, w, iterations, residual: worst })
}

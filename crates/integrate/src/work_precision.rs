//! Work-precision measurement, as the ODE community does it: for every applicable method, a sweep of tolerances
//! (adaptive methods) or step sizes (fixed-step methods); error = final-time error against the reference in the
//! problem's norm; time = minimum over repeated runs after a warm-up; right-hand-side evaluations counted too.

use crate::error::OdeError;
use crate::method::Method;
use crate::problems::{Problem, ProblemKind};
use crate::settings::Settings;
use crate::solve::{solve, SaveAt};
use std::time::{Duration, Instant};

/// How a curve's parameter is swept.
#[derive(Clone, Debug, PartialEq)]
pub enum Sweep {
    /// Tolerances (rtol = tol, atol = tol x the problem's atol scale), or the per-step error of step doubling and
    /// euler-variable.
    Tolerances(Vec<f64>),
    /// Numbers of fixed steps over the interval (h = (t_end - t0) / N).
    Steps(Vec<usize>),
}

/// One curve of a work-precision diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Label: the method's public name, with `+doubling` when wrapped in step doubling.
    pub label: String,
    /// The method.
    pub method: Method,
    /// Whether the chapter's step doubling controls the step.
    pub doubling: bool,
    /// The parameter sweep.
    pub sweep: Sweep,
}

/// One measured point.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionRun {
    /// Problem name.
    pub problem: String,
    /// Curve label.
    pub method: String,
    /// Tolerance or step size h.
    pub param: f64,
    /// Final-time error in the problem's norm.
    pub error: f64,
    /// Minimum wall time over the repeats.
    pub seconds: f64,
    /// Right-hand-side evaluations of one run.
    pub rhs_evals: usize,
    /// Accepted steps of one run.
    pub steps: usize,
    /// Rejected steps of one run.
    pub rejected: usize,
}

/// The CSV header shared with the peer scripts (`benches/peers/`).
pub const CSV_HEADER: &str = "problem,method,param,error,seconds,rhs_evals,steps,rejected";

impl PrecisionRun {
    /// One CSV row in the order of [`CSV_HEADER`].
    pub fn csv_row(&self) -> String {
        format!(
            "{},{},{:e},{:e},{:e},{},{},{}",
            self.problem, self.method, self.param, self.error, self.seconds, self.rhs_evals, self.steps, self.rejected
        )
    }

    /// Parses a CSV row written by [`Run::csv_row`] or a peer script (an empty `rejected` reads as 0: scipy does
    /// not report rejected steps).
    pub fn parse_csv_row(line: &str) -> Option<PrecisionRun> {
        let f: Vec<&str> = line.trim().split(',').collect();
        if f.len() != 8 {
            return None;
        }
        Some(PrecisionRun {
            problem: f[0].to_string(),
            method: f[1].to_string(),
            param: f[2].parse().ok()?,
            error: f[3].parse().ok()?,
            seconds: f[4].parse().ok()?,
            rhs_evals: f[5].parse().ok()?,
            steps: f[6].parse().ok()?,
            rejected: if f[7].is_empty() { 0 } else { f[7].parse().ok()? },
        })
    }
}

fn tolerances(from: i32, to: i32) -> Vec<f64> {
    (from..=to).map(|k| 10f64.powi(-k)).collect()
}

fn steps(from: u32, to: u32) -> Vec<usize> {
    (from..=to).map(|k| 1usize << k).collect()
}

/// The curves that apply to a problem: every method, except that explicit ones are left out on stiff problems
/// (they would need millions to billions of steps) and the symplectic ones need a split whose force does not
/// depend on velocity.
pub fn curves(problem: &Problem) -> Vec<Curve> {
    let tol = |m: Method, from, to| Curve {
        label: m.name().to_string(),
        method: m,
        doubling: false,
        sweep: Sweep::Tolerances(tolerances(from, to)),
    };
    let fixed = |m: Method, from, to| Curve {
        label: m.name().to_string(),
        method: m,
        doubling: false,
        sweep: Sweep::Steps(steps(from, to)),
    };
    let doubled = |m: Method, from, to| Curve {
        label: format!("{}+doubling", m.name()),
        method: m,
        doubling: true,
        sweep: Sweep::Tolerances(tolerances(from, to)),
    };
    let mut v = vec![tol(Method::Rodas4, 3, 11), tol(Method::Radau5, 3, 12), fixed(Method::ImplicitEuler, 6, 18)];
    if problem.kind == ProblemKind::Stiff {
        v.push(doubled(Method::ImplicitEuler, 2, 8));
        return v;
    }
    v.extend([
        tol(Method::Dopri5, 3, 13),
        tol(Method::Dop853, 3, 14),
        doubled(Method::Rk4, 3, 11),
        tol(Method::EulerVariable, 3, 10),
        fixed(Method::Euler, 8, 20),
        fixed(Method::Midpoint, 7, 18),
        fixed(Method::Rk4, 6, 16),
        fixed(Method::Ab4, 6, 16),
        fixed(Method::Am4, 6, 16),
    ]);
    if problem.system().split().is_some_and(|s| !s.force_depends_on_velocity) {
        v.extend([fixed(Method::SymplecticEuler, 8, 20), fixed(Method::Verlet, 7, 18)]);
    }
    v
}

/// The settings for one point of a curve.
pub fn settings(problem: &Problem, curve: &Curve, param: f64) -> Settings {
    let h = |n: f64| (problem.t_end - problem.t0) / n;
    match (&curve.sweep, curve.doubling, curve.method) {
        (Sweep::Tolerances(_), true, m) => Settings::step_doubling(m, param, h(100.0)),
        (Sweep::Tolerances(_), false, Method::EulerVariable) => Settings::euler_variable(param),
        (Sweep::Tolerances(_), false, m) => Settings::tolerances(m, param, param * problem.atol_scale),
        (Sweep::Steps(_), _, m) => Settings::fixed(m, param),
    }
    .max_steps(5_000_000)
}

/// The reference final state: the published or closed-form one, or else Dormand-Prince at rtol = atol = 1e-14
/// (non-stiff) or Rodas4 at 1e-13 (stiff).
pub fn reference(problem: &Problem) -> Result<Vec<f64>, OdeError> {
    if let Some(r) = &problem.reference {
        return Ok(r.clone());
    }
    let settings = match problem.kind {
        ProblemKind::Stiff => Settings::tolerances(Method::Rodas4, 1e-13, 1e-13 * problem.atol_scale),
        _ => Settings::tolerances(Method::Dopri5, 1e-14, 1e-14 * problem.atol_scale),
    };
    let sol = solve(&mut problem.system(), &settings, problem.t0, &problem.y0, problem.t_end, &SaveAt::End)?;
    Ok(sol.final_state.as_slice().to_vec())
}

/// Runs one point: a warm-up run gives the error and the counts; then repeats until `budget` is spent (at least
/// 2, at most 50 more runs) and keeps the fastest.
pub fn measure(
    problem: &Problem,
    label: &str,
    settings: &Settings,
    param: f64,
    reference: &[f64],
    budget: Duration,
) -> Result<PrecisionRun, OdeError> {
    let run_once = || {
        let mut sys = problem.system();
        let start = Instant::now();
        let sol = solve(&mut sys, settings, problem.t0, &problem.y0, problem.t_end, &SaveAt::End)?;
        Ok::<_, OdeError>((start.elapsed().as_secs_f64(), sol))
    };
    let (first, sol) = run_once()?;
    let repeats = ((budget.as_secs_f64() / first.max(1e-9)) as usize).clamp(2, 50);
    let mut best = first;
    for _ in 0..repeats {
        best = best.min(run_once()?.0);
    }
    Ok(PrecisionRun {
        problem: problem.name.to_string(),
        method: label.to_string(),
        param,
        error: problem.error(sol.final_state.as_slice(), reference),
        seconds: best,
        rhs_evals: sol.report.rhs_evals,
        steps: sol.report.steps,
        rejected: sol.report.rejected,
    })
}

/// Every point of every applicable curve of a problem. Points that fail (a fixed step beyond a method's
/// stability, a step budget exceeded) or that have no accuracy at all (error > 1) are left out and reported
/// through `skipped`.
pub fn sweep_problem(
    problem: &Problem,
    budget: Duration,
    mut skipped: impl FnMut(&str, f64, String),
) -> Result<Vec<PrecisionRun>, OdeError> {
    let reference = reference(problem)?;
    let mut runs = Vec::new();
    for curve in curves(problem) {
        let params: Vec<f64> = match &curve.sweep {
            Sweep::Tolerances(t) => t.clone(),
            Sweep::Steps(n) => n.iter().map(|&n| (problem.t_end - problem.t0) / n as f64).collect(),
        };
        for param in params {
            let s = settings(problem, &curve, param);
            match measure(problem, &curve.label, &s, param, &reference, budget) {
                Ok(run) if run.error <= 1.0 => runs.push(run),
                Ok(run) => skipped(&curve.label, param, format!("error {:.2e} > 1", run.error)),
                Err(e) => skipped(&curve.label, param, e.to_string()),
            }
        }
    }
    Ok(runs)
}

/// The fastest time in which any curve of `runs` reaches an error of at most `error`, with its label. A curve
/// reaches it at every measured point with error <= `error`, and, between consecutive points of its sweep that
/// bracket `error`, at the time interpolated linearly in log(seconds) against log(error).
pub fn best_time_at(runs: &[PrecisionRun], error: f64) -> Option<(f64, String)> {
    let mut labels: Vec<&str> = runs.iter().map(|r| r.method.as_str()).collect();
    labels.sort();
    labels.dedup();
    let mut best: Option<(f64, String)> = None;
    let mut offer = |t: f64, label: &str| {
        if best.as_ref().is_none_or(|(bt, _)| t < *bt) {
            best = Some((t, label.to_string()));
        }
    };
    for label in labels {
        let curve: Vec<&PrecisionRun> = runs.iter().filter(|r| r.method == label && r.error > 0.0).collect();
        for r in curve.iter().filter(|r| r.error <= error) {
            offer(r.seconds, label);
        }
        for w in curve.windows(2) {
            let (a, b) = (w[0], w[1]);
            if (a.error - error) * (b.error - error) < 0.0 {
                let s = (error.ln() - a.error.ln()) / (b.error.ln() - a.error.ln());
                offer((a.seconds.ln() + s * (b.seconds.ln() - a.seconds.ln())).exp(), label);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(method: &str, error: f64, seconds: f64) -> PrecisionRun {
        PrecisionRun {
            problem: "p".into(),
            method: method.into(),
            param: 0.0,
            error,
            seconds,
            rhs_evals: 0,
            steps: 0,
            rejected: 0,
        }
    }

    /// Interpolation in log-log between bracketing points; points below the target count at their own time.
    #[test]
    fn best_time_interpolates_and_takes_the_fastest() {
        let runs = vec![run("a", 1e-2, 1.0), run("a", 1e-4, 100.0), run("b", 1e-6, 5.0)];
        let (t, label) = best_time_at(&runs, 1e-3).unwrap();
        assert_eq!(label, "b");
        assert!((t - 5.0).abs() < 1e-12);
        let (t, label) = best_time_at(&runs[..2], 1e-3).unwrap();
        assert_eq!(label, "a");
        assert!((t - 10.0).abs() < 1e-9, "halfway in log error is halfway in log time: {t}");
        assert!(best_time_at(&runs, 1e-7).is_none());
    }
}

//! Helpers shared by the integration tests: least-squares slopes and short solves.
#![allow(dead_code)]

use tumble_integrate::{solve, OdeError, OdeSystem, SaveAt, Settings, Solution};

/// Least-squares slope of log(y) against log(x).
pub fn loglog_slope(x: &[f64], y: &[f64]) -> f64 {
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let num: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let den: f64 = lx.iter().map(|a| (a - mx).powi(2)).sum();
    num / den
}

/// Final state of a solve from t0 = 0.
pub fn final_state(
    sys: &mut impl OdeSystem,
    settings: &Settings,
    y0: &[f64],
    t_end: f64,
) -> Result<Solution, OdeError> {
    solve(sys, settings, 0.0, y0, t_end, &SaveAt::End)
}

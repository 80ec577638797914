//! The one-call entry point: solve from t0 to t_end, saving states at chosen times.

use crate::error::OdeError;
use crate::integrator::Integrator;
use crate::report::Report;
use crate::settings::Settings;
use crate::system::OdeSystem;
use nalgebra::{DMatrix, DVector};

/// Which states a solve returns.
#[derive(Clone, Debug, PartialEq)]
pub enum SaveAt {
    /// Only the final state.
    End,
    /// These times (ascending, within [t0, t_end]).
    Times(Vec<f64>),
    /// t0, t0 + dt, t0 + 2 dt, ... and t_end.
    Every(f64),
}

/// The result of [`solve`].
#[derive(Clone, Debug)]
pub struct Solution {
    /// The output times.
    pub times: Vec<f64>,
    /// The states at those times, one column each (dim x times.len()).
    pub states: DMatrix<f64>,
    /// The state at t_end.
    pub final_state: DVector<f64>,
    /// What it cost, and the error estimate.
    pub report: Report,
}

impl SaveAt {
    fn times(&self, t0: f64, t_end: f64) -> Result<Vec<f64>, OdeError> {
        match self {
            SaveAt::End => Ok(vec![t_end]),
            SaveAt::Times(v) => Ok(v.clone()),
            SaveAt::Every(dt) => {
                if !(dt.is_finite() && *dt > 0.0) {
                    return Err(OdeError::invalid("save_at", format!("Every(dt) needs a finite dt > 0, got {dt}")));
                }
                let count = ((t_end - t0) / dt * (1.0 + 1e-12)).floor();
                if count > 1e8 {
                    return Err(OdeError::invalid("save_at", format!("Every({dt}) asks for {count:e} outputs")));
                }
                let mut v: Vec<f64> = (0..=count as usize).map(|k| t0 + k as f64 * dt).collect();
                match v.last_mut() {
                    Some(last) if (t_end - *last).abs() <= 1e-9 * dt => *last = t_end,
                    _ => v.push(t_end),
                }
                Ok(v)
            }
        }
    }
}

/// Solves y' = f(t, y), y(t0) = y0 on [t0, t_end] with the given settings, returning the saved states and the
/// report. `y0` is never modified; on error nothing is returned but the error.
pub fn solve<S: OdeSystem + ?Sized>(
    sys: &mut S,
    settings: &Settings,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    save_at: &SaveAt,
) -> Result<Solution, OdeError> {
    if !(t_end.is_finite() && t_end >= t0) {
        return Err(OdeError::invalid("t_end", format!("must be finite and >= t0 = {t0}, got {t_end}")));
    }
    let mut integrator = Integrator::new(sys, settings.clone(), t0, y0)?;
    let times = save_at.times(t0, t_end)?;
    let n = y0.len();
    let mut data = Vec::with_capacity(times.len() * n);
    integrator.advance_to(sys, t_end, &times, |_, _, y| data.extend_from_slice(y))?;
    Ok(Solution {
        states: DMatrix::from_vec(n, times.len(), data),
        times,
        final_state: DVector::from_column_slice(integrator.state()),
        report: integrator.report().clone(),
    })
}

//! A point of the solution (t, y) with its derivative f(t, y) evaluated at most once, and the error norms.

use crate::error::OdeError;
use crate::report::Report;
use crate::system::OdeSystem;
use std::sync::atomic::{AtomicU64, Ordering};

/// Where a point id's slot begins (the bits below count its rewrites).
pub(crate) const SLOT_SHIFT: u32 = 40;
const COUNT_MASK: u64 = (1 << SLOT_SHIFT) - 1;

/// Each point takes a distinct slot once; its id is (slot << 40) | count, and a rewrite only bumps the count,
/// so renewing costs no atomic operation while ids stay unique across all points (a copied or restored
/// integrator shares its points' ids with the original: caches compare ids only within one integrator).
pub(crate) static NEXT_SLOT: AtomicU64 = AtomicU64::new(1);

/// A solution point. `id` changes whenever the point is rewritten, so caches keyed by it (a Jacobian, a force)
/// are never reused for a different state.
#[derive(Clone, Debug)]
pub(crate) struct Point {
    pub t: f64,
    pub y: Vec<f64>,
    pub f: Vec<f64>,
    pub has_f: bool,
    pub id: u64,
}

impl Point {
    pub fn new(t: f64, y: &[f64]) -> Self {
        let slot = NEXT_SLOT.fetch_add(1, Ordering::Relaxed);
        Point { t, y: y.to_vec(), f: vec![0.0; y.len()], has_f: false, id: slot << SLOT_SHIFT }
    }

    /// Marks the point as rewritten at time `t` (its y is about to be, or has just been, written).
    #[inline]
    pub fn renew(&mut self, t: f64) {
        self.t = t;
        self.has_f = false;
        self.id = (self.id & !COUNT_MASK) | ((self.id + 1) & COUNT_MASK);
    }

    /// Evaluates f(t, y) once and checks it is finite.
    pub fn ensure_f<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, report: &mut Report) -> Result<(), OdeError> {
        if !self.has_f {
            eval(sys, self.t, &self.y, &mut self.f, report)?;
            if let Some(i) = self.f.iter().position(|v| !v.is_finite()) {
                return Err(OdeError::NonFinite { t: self.t, what: "derivative", index: i });
            }
            self.has_f = true;
        }
        Ok(())
    }
}

/// One counted right-hand-side evaluation, with the system's error mapped to [`OdeError::System`].
#[inline]
pub(crate) fn eval<S: OdeSystem + ?Sized>(
    sys: &mut S,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
    report: &mut Report,
) -> Result<(), OdeError> {
    report.rhs_evals += 1;
    sys.rhs(t, y, dy).map_err(|e| OdeError::System { t, message: e.message })
}

/// Weighted RMS norm of `e` with weights `atol + rtol max(|y0|, |y1|)` (Hairer's error norm).
#[inline]
pub(crate) fn weighted_rms(e: &[f64], y0: &[f64], y1: &[f64], rtol: f64, atol: f64) -> f64 {
    let mut sum = 0.0;
    for ((ei, a), b) in e.iter().zip(y0).zip(y1) {
        let sk = atol + rtol * a.abs().max(b.abs());
        let r = ei / sk;
        sum += r * r;
    }
    (sum / e.len().max(1) as f64).sqrt()
}

/// Max norm.
#[inline]
pub(crate) fn max_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// Euclidean norm.
#[inline]
pub(crate) fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

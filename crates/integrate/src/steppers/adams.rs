//! Adams multistep methods of order 4: Adams-Bashforth (explicit, one evaluation a step) and the Adams-Moulton
//! predictor-corrector in PECE form with Milne's error estimate. Both start, and restart whenever h changes,
//! with RK4 steps until three back values at spacing h exist.

use super::explicit_rk::{ExplicitRk, RK4};
use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{eval, max_norm, weighted_rms, Point};
use crate::system::OdeSystem;

/// Milne's estimate of the corrector's local error: AB4's error constant is 251/720, AM4's -19/720, so the
/// corrector's error is about -19/270 of (corrector - predictor).
const MILNE: f64 = 19.0 / 270.0;

#[derive(Clone)]
pub(crate) struct Adams {
    corrector: bool,
    /// f_{i-1}, f_{i-2}, f_{i-3}: derivatives at the previous accepted points, newest first.
    back: [Vec<f64>; 3],
    /// How many of `back` hold values at spacing `spacing`.
    valid: usize,
    spacing: f64,
    starter: ExplicitRk,
    predicted: Vec<f64>,
    fpred: Vec<f64>,
    err: Vec<f64>,
}

impl Adams {
    pub fn new(n: usize, corrector: bool) -> Self {
        Adams {
            corrector,
            back: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            valid: 0,
            spacing: 0.0,
            starter: ExplicitRk::new(&RK4, n),
            predicted: vec![0.0; n],
            fpred: vec![0.0; n],
            err: vec![0.0; n],
        }
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for Adams {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        from.ensure_f(sys, &mut ctx.report)?;
        if self.valid > 0 && (h - self.spacing).abs() > 1e-9 * h.abs() {
            self.valid = 0;
            ctx.report.restarts += 1;
        }
        if self.valid < 3 {
            self.spacing = h;
            self.starter.advance(sys, from, h, to, ctx)?;
            return Ok(Estimate::default());
        }
        let (f0, [f1, f2, f3]) = (&from.f, &self.back);
        let c = h / 24.0;
        for i in 0..f0.len() {
            self.predicted[i] = from.y[i] + c * (55.0 * f0[i] - 59.0 * f1[i] + 37.0 * f2[i] - 9.0 * f3[i]);
        }
        if !self.corrector {
            to.y.copy_from_slice(&self.predicted);
            return Ok(Estimate::default());
        }
        eval(sys, from.t + h, &self.predicted, &mut self.fpred, &mut ctx.report)?;
        for i in 0..f0.len() {
            to.y[i] = from.y[i] + c * (9.0 * self.fpred[i] + 19.0 * f0[i] - 5.0 * f1[i] + f2[i]);
            self.err[i] = MILNE * (to.y[i] - self.predicted[i]);
        }
        Ok(Estimate {
            scaled: Some(weighted_rms(&self.err, &from.y, &to.y, ctx.rtol, ctx.atol)),
            local: Some(max_norm(&self.err)),
            safety: None,
        })
    }

    fn accepted(&mut self, from: &Point, _to: &Point, _ctx: &mut Ctx) {
        self.back.rotate_right(1);
        self.back[0].copy_from_slice(&from.f);
        self.valid = (self.valid + 1).min(3);
    }

    fn reset(&mut self) {
        self.valid = 0;
    }
}

impl Remember for Adams {
    fn save(&self, out: &mut MemoryWriter) {
        self.back.iter().for_each(|b| out.numbers(b));
        out.count(self.valid as u64);
        out.number(self.spacing);
        self.starter.save(out);
        out.numbers(&self.predicted);
        out.numbers(&self.fpred);
        out.numbers(&self.err);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        for b in &mut self.back {
            input.numbers("back values", b)?;
        }
        let valid = input.count("valid back values")?;
        if valid > 3 {
            return Err(format!("`valid back values` is {valid}, at most 3"));
        }
        self.valid = valid as usize;
        self.spacing = input.number("spacing")?;
        self.starter.load(input)?;
        input.numbers("predicted", &mut self.predicted)?;
        input.numbers("fpred", &mut self.fpred)?;
        input.numbers("err", &mut self.err)
    }
}

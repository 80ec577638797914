//! Dormand-Prince 8(5,3): twelve stages of order 8 with first-same-as-last, and Hairer's error estimate that
//! blends the 5th- and 3rd-order differences: err = h ||e5||^2 / sqrt(||e5||^2 + 0.01 ||e3||^2).

use super::dop853_tableau::{A, B, C, E3, E5, STAGES};
use super::explicit_rk::combine;
use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{eval, Point};
use crate::system::OdeSystem;

#[derive(Clone)]
pub(crate) struct Dop853 {
    /// Stages 2..12 (stage 1 is the starting point's derivative).
    k: Vec<Vec<f64>>,
    stage: Vec<f64>,
}

impl Dop853 {
    pub fn new(n: usize) -> Self {
        Dop853 { k: vec![vec![0.0; n]; STAGES - 1], stage: vec![0.0; n] }
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for Dop853 {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        from.ensure_f(sys, &mut ctx.report)?;
        let n = from.y.len();
        let (y, f0) = (&from.y[..n], &from.f[..n]);
        for i in 1..STAGES {
            combine(&mut self.stage, y, h, A[i], f0, &self.k);
            eval(sys, from.t + C[i] * h, &self.stage, &mut self.k[i - 1], &mut ctx.report)?;
        }
        combine(&mut to.y, y, h, &B, f0, &self.k);
        let y1 = &to.y[..n];
        eval(sys, from.t + h, y1, &mut to.f, &mut ctx.report)?;
        to.has_f = true;
        let (rtol, atol) = (ctx.rtol, ctx.atol);
        let (mut s5, mut s3, mut emax) = (0.0, 0.0, 0.0_f64);
        for i in 0..n {
            let (mut e5, mut e3) = (E5[0] * f0[i] + E5[STAGES] * to.f[i], E3[0] * f0[i] + E3[STAGES] * to.f[i]);
            for j in 1..STAGES {
                e5 += E5[j] * self.k[j - 1][i];
                e3 += E3[j] * self.k[j - 1][i];
            }
            let sk = atol + rtol * y[i].abs().max(to.y[i].abs());
            s5 += (e5 / sk).powi(2);
            s3 += (e3 / sk).powi(2);
            emax = emax.max((h * e5).abs());
        }
        let deno = if s5 + 0.01 * s3 > 0.0 { s5 + 0.01 * s3 } else { 1.0 };
        let err = h.abs() * s5 / (deno * n as f64).sqrt();
        Ok(Estimate { scaled: Some(err), local: Some(emax), safety: None })
    }
}

impl Remember for Dop853 {
    fn save(&self, out: &mut MemoryWriter) {
        super::explicit_rk::save_stages(out, &self.k, &self.stage);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        super::explicit_rk::load_stages(input, &mut self.k, &mut self.stage)
    }
}

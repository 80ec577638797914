//! Dormand-Prince 5(4): seven stages with first-same-as-last, the embedded 4th-order error estimate and
//! Shampine's 4th-order continuous extension (the coefficients of Hairer's DOPRI5).

use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{eval, Point};
use crate::system::OdeSystem;

const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

#[derive(Clone)]
pub(crate) struct Dopri5 {
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    k5: Vec<f64>,
    k6: Vec<f64>,
    stage: Vec<f64>,
}

impl Dopri5 {
    pub fn new(n: usize) -> Self {
        let v = || vec![0.0; n];
        Dopri5 { k2: v(), k3: v(), k4: v(), k5: v(), k6: v(), stage: v() }
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for Dopri5 {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        from.ensure_f(sys, &mut ctx.report)?;
        let t = from.t;
        let n = from.y.len();
        // Re-slicing everything to length n lets the compiler drop the bounds checks in the stage loops.
        let (y, k1) = (&from.y[..n], &from.f[..n]);
        let r = &mut ctx.report;
        let Dopri5 { k2, k3, k4, k5, k6, stage } = self;
        let (k2, k3, k4, k5, k6, stage) =
            (&mut k2[..n], &mut k3[..n], &mut k4[..n], &mut k5[..n], &mut k6[..n], &mut stage[..n]);

        for i in 0..n {
            stage[i] = y[i] + h * A21 * k1[i];
        }
        eval(sys, t + C2 * h, stage, k2, r)?;
        for i in 0..n {
            stage[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        }
        eval(sys, t + C3 * h, stage, k3, r)?;
        for i in 0..n {
            stage[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
        }
        eval(sys, t + C4 * h, stage, k4, r)?;
        for i in 0..n {
            stage[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
        }
        eval(sys, t + C5 * h, stage, k5, r)?;
        for i in 0..n {
            stage[i] = y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
        }
        eval(sys, t + h, stage, k6, r)?;
        let y1 = &mut to.y[..n];
        for i in 0..n {
            y1[i] = y[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
        }
        // k7 = f(t + h, y_new) is the next step's k1 (first same as last).
        eval(sys, t + h, y1, &mut to.f, r)?;
        let k7 = &to.f[..n];
        to.has_f = true;
        // The embedded error h (b - b^) . k, its weighted RMS norm and its max norm, in one pass.
        let (rtol, atol) = (ctx.rtol, ctx.atol);
        let (mut sum, mut emax) = (0.0, 0.0_f64);
        for i in 0..n {
            let e = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            let sk = atol + rtol * y[i].abs().max(y1[i].abs());
            sum += (e / sk) * (e / sk);
            emax = emax.max(e.abs());
        }
        // A non-finite k7 makes the error NaN, which the driver rejects; `to` is then discarded.
        Ok(Estimate { scaled: Some((sum / n as f64).sqrt()), local: Some(emax), safety: None })
    }

    fn has_dense_output(&self) -> bool {
        true
    }

    fn dense(&self, from: &Point, to: &Point, theta: f64, out: &mut [f64]) {
        let h = to.t - from.t;
        let (y0, y1, k1, k7) = (&from.y, &to.y, &from.f, &to.f);
        let th1 = 1.0 - theta;
        for i in 0..out.len() {
            let ydiff = y1[i] - y0[i];
            let bspl = h * k1[i] - ydiff;
            let c4 = ydiff - h * k7[i] - bspl;
            let c5 =
                h * (D1 * k1[i] + D3 * self.k3[i] + D4 * self.k4[i] + D5 * self.k5[i] + D6 * self.k6[i] + D7 * k7[i]);
            out[i] = y0[i] + theta * (ydiff + th1 * (bspl + theta * (c4 + th1 * c5)));
        }
    }
}

impl Remember for Dopri5 {
    fn save(&self, out: &mut MemoryWriter) {
        for k in [&self.k2, &self.k3, &self.k4, &self.k5, &self.k6, &self.stage] {
            out.numbers(k);
        }
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        for k in [&mut self.k2, &mut self.k3, &mut self.k4, &mut self.k5, &mut self.k6, &mut self.stage] {
            input.numbers("dopri5 stage", k)?;
        }
        Ok(())
    }
}

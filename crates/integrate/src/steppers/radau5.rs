//! Radau IIA of order 5, after Hairer and Wanner's RADAU5: three-stage collocation, L-stable and stiffly accurate,
//! stage order 3 (so no order reduction on singularly perturbed problems such as Van der Pol). The stage equations
//! are solved by simplified Newton in variables that decouple them into one real n x n system and one complex
//! pair (factored as a real 2n x 2n system). The Jacobian is kept while Newton converges fast, the factors while h
//! stays. Internally the tolerances are sharpened to rtol' = 0.1 rtol^(2/3), atol' = rtol' atol / rtol, as RADAU5
//! does, because its error estimate is of lower order than the solution.

use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::factorization::{Factorization, Shift};
use crate::jacobian::Jacobian;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{eval, Point};
use crate::system::OdeSystem;

const SQ6: f64 = 2.449489742783178;
const C1: f64 = (4.0 - SQ6) / 10.0;
const C2: f64 = (4.0 + SQ6) / 10.0;
const C1M1: f64 = C1 - 1.0;
const C2M1: f64 = C2 - 1.0;
const C1MC2: f64 = C1 - C2;
/// Error-estimate weights (b^ - b) / gamma0 of the stage increments.
const DD1: f64 = -(13.0 + 7.0 * SQ6) / 3.0;
const DD2: f64 = (-13.0 + 7.0 * SQ6) / 3.0;
const DD3: f64 = -1.0 / 3.0;
/// Eigenvalues of the inverse Radau matrix: gamma and alpha +- i beta.
const GAMMA: f64 = 3.637834252744496;
const ALPHA: f64 = 2.681082873627752;
const BETA: f64 = 3.050430199247411;
/// T and T^-1 with T^-1 A^-1 T = diag(gamma, [[alpha, -beta], [beta, alpha]]).
const T: [[f64; 3]; 3] = [
    [9.1232394870892942792e-02, -0.14125529502095420843, -3.0029194105147424492e-02],
    [0.24171793270710701896, 0.20412935229379993199, 0.38294211275726193779],
    [0.96604818261509293619, 1.0, 0.0],
];
const TI: [[f64; 3]; 3] = [
    [4.3255798900631553510, 0.33919925181580986954, 0.54177053993587487119],
    [-4.1787185915519047273, -0.32768282076106238708, 0.47662355450055045196],
    [-0.50287263494578687595, 2.5719269498556054292, -0.59603920482822492497],
];
/// Newton iterations allowed per step.
const NIT: usize = 7;
/// Keep the Jacobian while Newton's contraction rate stays below this.
const THET: f64 = 0.001;

#[derive(Clone)]
pub(crate) struct Radau5 {
    jac: Jacobian,
    real: Factorization,
    complex: Factorization,
    rtol: f64,
    atol: f64,
    fnewt: f64,
    /// Stage increments Z_i = Y_i - y and their transforms W = T^-1 Z.
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    f: [Vec<f64>; 3],
    /// Divided differences of the last accepted step's collocation polynomial.
    cont: [Vec<f64>; 3],
    h_old: Option<f64>,
    /// Reciprocal error weights 1 / (atol' + rtol' |y|) of the current step.
    scal: Vec<f64>,
    stage: Vec<f64>,
    pair: Vec<f64>,
    err: Vec<f64>,
    faccon: f64,
    theta: f64,
    first: bool,
    rejected_last: bool,
    retry: f64,
}

impl Radau5 {
    pub fn new<S: OdeSystem + ?Sized>(sys: &S, rtol: f64, atol: f64) -> Result<Self, OdeError> {
        let n = sys.dim();
        let jac = Jacobian::new(sys)?;
        let (rt, at) = if rtol > 0.0 {
            let rt = 0.1 * rtol.powf(2.0 / 3.0);
            (rt, rt * atol / rtol)
        } else {
            (0.0, 0.1 * atol.powf(2.0 / 3.0))
        };
        let v = || vec![0.0; n];
        Ok(Radau5 {
            real: Factorization::new(&jac, Shift::Real)?,
            complex: Factorization::new(&jac, Shift::Complex)?,
            jac,
            rtol: rt,
            atol: at,
            fnewt: (10.0 * f64::EPSILON / rt.max(1e-300)).max(0.03f64.min(rt.max(at).sqrt())),
            z: [v(), v(), v()],
            w: [v(), v(), v()],
            f: [v(), v(), v()],
            cont: [v(), v(), v()],
            h_old: None,
            scal: v(),
            stage: v(),
            pair: vec![0.0; 2 * n],
            err: v(),
            faccon: 1.0,
            theta: THET,
            first: true,
            rejected_last: false,
            retry: 0.5,
        })
    }

    /// Weighted RMS norm (`scal` holds the reciprocal weights 1 / (atol' + rtol' |y|)).
    fn rms(&self, v: &[f64]) -> f64 {
        let s: f64 = v.iter().zip(&self.scal).map(|(x, w)| (x * w) * (x * w)).sum();
        (s / v.len() as f64).sqrt()
    }

    /// Newton's starting stages: the last collocation polynomial extrapolated, or zero.
    fn start_stages(&mut self, h: f64) {
        let n = self.stage.len();
        match self.h_old {
            Some(h_old) if !self.first => {
                let c3q = h / h_old;
                let cq = [C1 * c3q, C2 * c3q, c3q];
                for i in 0..n {
                    let (a1, a2, a3) = (self.cont[0][i], self.cont[1][i], self.cont[2][i]);
                    for (k, &q) in cq.iter().enumerate() {
                        self.z[k][i] = q * (a1 + (q - C2M1) * (a2 + (q - C1M1) * a3));
                    }
                }
            }
            _ => self.z.iter_mut().for_each(|z| z.fill(0.0)),
        }
        for i in 0..n {
            let (z1, z2, z3) = (self.z[0][i], self.z[1][i], self.z[2][i]);
            for r in 0..3 {
                self.w[r][i] = TI[r][0] * z1 + TI[r][1] * z2 + TI[r][2] * z3;
            }
        }
    }

    /// Simplified Newton on the transformed stage equations. On failure sets `retry` to the factor by which h
    /// should shrink.
    fn newton<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        from: &Point,
        h: f64,
        ctx: &mut Ctx,
    ) -> Result<usize, OdeError> {
        let n = self.stage.len();
        let (fac1, alphn, betan) = (GAMMA / h, ALPHA / h, BETA / h);
        self.faccon = self.faccon.max(f64::EPSILON).powf(0.8);
        self.theta = THET;
        let (mut dynold, mut thqold) = (0.0, 0.0);
        let fail = |t, iterations, residual| OdeError::NewtonFailure { t, h, iterations, residual };
        for newt in 1..=NIT {
            ctx.report.newton_iterations += 1;
            for (k, c) in [C1, C2, 1.0].into_iter().enumerate() {
                for ((s, y), z) in self.stage.iter_mut().zip(&from.y).zip(&self.z[k]) {
                    *s = y + z;
                }
                eval(sys, from.t + c * h, &self.stage, &mut self.f[k], &mut ctx.report)?;
            }
            // Right-hand sides of the decoupled systems: T^-1 F - (Lambda / h) W.
            {
                let (f1, f2, f3) = (&self.f[0][..n], &self.f[1][..n], &self.f[2][..n]);
                let (w1, w2, w3) = (&self.w[0][..n], &self.w[1][..n], &self.w[2][..n]);
                let (re, im) = self.pair.split_at_mut(n);
                let (r1, re, im) = (&mut self.err[..n], &mut re[..n], &mut im[..n]);
                for i in 0..n {
                    let (a1, a2, a3) = (f1[i], f2[i], f3[i]);
                    let g1 = TI[0][0] * a1 + TI[0][1] * a2 + TI[0][2] * a3;
                    let g2 = TI[1][0] * a1 + TI[1][1] * a2 + TI[1][2] * a3;
                    let g3 = TI[2][0] * a1 + TI[2][1] * a2 + TI[2][2] * a3;
                    r1[i] = g1 - fac1 * w1[i];
                    re[i] = g2 - (alphn * w2[i] - betan * w3[i]);
                    im[i] = g3 - (betan * w2[i] + alphn * w3[i]);
                }
            }
            self.real.solve(&mut self.err, &mut ctx.report);
            self.complex.solve(&mut self.pair, &mut ctx.report);
            let dyno = {
                let (re, im) = self.pair.split_at(n);
                let (r1, re, im, w) = (&self.err[..n], &re[..n], &im[..n], &self.scal[..n]);
                let mut sum = 0.0;
                for i in 0..n {
                    sum += (r1[i] * r1[i] + re[i] * re[i] + im[i] * im[i]) * (w[i] * w[i]);
                }
                (sum / (3 * n) as f64).sqrt()
            };
            if !dyno.is_finite() {
                self.retry = 0.5;
                for (k, c) in [C1, C2, 1.0].into_iter().enumerate() {
                    if let Some(i) = self.f[k].iter().position(|v| !v.is_finite()) {
                        return Err(OdeError::NonFinite { t: from.t + c * h, what: "derivative", index: i });
                    }
                }
                return Err(fail(from.t, newt, dyno));
            }
            if newt > 1 && newt < NIT {
                let thq = dyno / dynold;
                self.theta = if newt == 2 { thq } else { (thq * thqold).sqrt() };
                thqold = thq;
                if self.theta < 0.99 {
                    self.faccon = self.theta / (1.0 - self.theta);
                    let dyth = self.faccon * dyno * self.theta.powi((NIT - 1 - newt) as i32) / self.fnewt;
                    if dyth >= 1.0 {
                        // Convergence too slow to finish in time: retry with a step it can finish.
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        self.retry = 0.8 * qnewt.powf(-1.0 / (4.0 + (NIT - 1 - newt) as f64));
                        return Err(fail(from.t, newt, dyno));
                    }
                } else {
                    self.retry = 0.5;
                    return Err(fail(from.t, newt, dyno));
                }
            }
            dynold = dyno.max(f64::EPSILON);
            {
                let (re, im) = self.pair.split_at(n);
                let (d1, d2, d3) = (&self.err[..n], &re[..n], &im[..n]);
                let [w1, w2, w3] = &mut self.w;
                let [z1, z2, z3] = &mut self.z;
                let (w1, w2, w3) = (&mut w1[..n], &mut w2[..n], &mut w3[..n]);
                let (z1, z2, z3) = (&mut z1[..n], &mut z2[..n], &mut z3[..n]);
                for i in 0..n {
                    let (a, b, c) = (w1[i] + d1[i], w2[i] + d2[i], w3[i] + d3[i]);
                    w1[i] = a;
                    w2[i] = b;
                    w3[i] = c;
                    z1[i] = T[0][0] * a + T[0][1] * b + T[0][2] * c;
                    z2[i] = T[1][0] * a + T[1][1] * b + T[1][2] * c;
                    z3[i] = T[2][0] * a + T[2][1] * b + T[2][2] * c;
                }
            }
            if self.faccon * dyno <= self.fnewt {
                return Ok(newt);
            }
        }
        self.retry = 0.5;
        Err(fail(from.t, NIT, f64::NAN))
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for Radau5 {
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
        for (s, y) in self.scal.iter_mut().zip(&from.y) {
            *s = 1.0 / (self.atol + self.rtol * y.abs());
        }
        let stale_ok = !self.first && !self.rejected_last && self.theta <= THET && self.jac.is_evaluated();
        if !self.jac.is_at(from) && !stale_ok {
            self.jac.update(sys, from, &mut ctx.report)?;
        }
        self.retry = 0.5;
        self.real.factor(&self.jac, GAMMA / h, 0.0, from.t, h, &mut ctx.report)?;
        self.complex.factor(&self.jac, ALPHA / h, BETA / h, from.t, h, &mut ctx.report)?;
        self.start_stages(h);
        let newt = self.newton(sys, from, h, ctx)?;

        // Error estimate: (gamma/h I - J)^-1 (f(y) + (dd . Z) / h), re-evaluated once at y + err after a
        // rejection or on the first step (the first form overestimates for very stiff components).
        for i in 0..n {
            self.stage[i] = (DD1 * self.z[0][i] + DD2 * self.z[1][i] + DD3 * self.z[2][i]) / h;
            self.err[i] = from.f[i] + self.stage[i];
        }
        self.real.solve(&mut self.err, &mut ctx.report);
        let mut err = self.rms(&self.err).max(1e-10);
        if err >= 1.0 && (self.first || self.rejected_last) {
            for i in 0..n {
                self.pair[i] = from.y[i] + self.err[i];
            }
            let (probe, f1) = self.pair.split_at_mut(n);
            eval(sys, from.t, probe, &mut f1[..n], &mut ctx.report)?;
            for i in 0..n {
                self.err[i] = f1[i] + self.stage[i];
            }
            self.real.solve(&mut self.err, &mut ctx.report);
            err = self.rms(&self.err).max(1e-10);
        }
        for i in 0..n {
            to.y[i] = from.y[i] + self.z[2][i];
        }
        let local = self.err.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        // Fewer Newton iterations allow a bolder step (RADAU5's fac = min(safe, cfac / (newt + 2 nit))).
        let safety = (0.9f64).min(0.9 * (1 + 2 * NIT) as f64 / (newt + 2 * NIT) as f64);
        Ok(Estimate { scaled: Some(err), local: Some(local), safety: Some(safety) })
    }

    fn accepted(&mut self, from: &Point, to: &Point, _ctx: &mut Ctx) {
        // Newton divided differences of the collocation polynomial through (0, y), (c1, Y1), (c2, Y2), (1, Y3),
        // written relative to the end of the step (s = theta - 1).
        for i in 0..self.stage.len() {
            let (z1, z2, z3) = (self.z[0][i], self.z[1][i], self.z[2][i]);
            let c0 = (z2 - z3) / C2M1;
            let ak = (z1 - z2) / C1MC2;
            let acont3 = (ak - z1 / C1) / C2;
            let c1 = (ak - c0) / C1M1;
            self.cont[0][i] = c0;
            self.cont[1][i] = c1;
            self.cont[2][i] = c1 - acont3;
        }
        self.h_old = Some(to.t - from.t);
        self.first = false;
        self.rejected_last = false;
    }

    fn rejected(&mut self) {
        self.rejected_last = true;
    }

    fn retry_factor(&self) -> Option<f64> {
        Some(self.retry)
    }

    fn prefer_step(&self, h: f64, proposal: f64) -> f64 {
        // Keep h (and so the factors) when Newton converged fast and the controller asks for under 20% more.
        let q = proposal / h;
        if self.theta <= THET && (1.0..=1.2).contains(&q) {
            h
        } else {
            proposal
        }
    }

    fn reset(&mut self) {
        self.jac.invalidate();
        self.real.invalidate();
        self.complex.invalidate();
        self.h_old = None;
        self.first = true;
        self.faccon = 1.0;
        self.theta = THET;
    }

    fn has_dense_output(&self) -> bool {
        true
    }

    fn dense(&self, _from: &Point, to: &Point, theta: f64, out: &mut [f64]) {
        let s = theta - 1.0;
        for i in 0..out.len() {
            out[i] = to.y[i] + s * (self.cont[0][i] + (s - C2M1) * (self.cont[1][i] + (s - C1M1) * self.cont[2][i]));
        }
    }
}

impl Remember for Radau5 {
    fn save(&self, out: &mut MemoryWriter) {
        self.jac.save(out);
        for v in self.z.iter().chain(&self.w).chain(&self.f).chain(&self.cont) {
            out.numbers(v);
        }
        out.maybe(self.h_old);
        for v in [&self.scal, &self.stage, &self.pair, &self.err] {
            out.numbers(v);
        }
        for x in [self.faccon, self.theta, self.retry] {
            out.number(x);
        }
        out.flag(self.first);
        out.flag(self.rejected_last);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        self.jac.load(input)?;
        self.real.invalidate();
        self.complex.invalidate();
        for v in self.z.iter_mut().chain(&mut self.w).chain(&mut self.f).chain(&mut self.cont) {
            input.numbers("radau5 stage", v)?;
        }
        self.h_old = input.maybe("h_old")?;
        for v in [&mut self.scal, &mut self.stage, &mut self.pair, &mut self.err] {
            input.numbers("radau5 work", v)?;
        }
        self.faccon = input.number("faccon")?;
        self.theta = input.number("theta")?;
        self.retry = input.number("retry")?;
        self.first = input.flag("first")?;
        self.rejected_last = input.flag("rejected_last")?;
        Ok(())
    }
}

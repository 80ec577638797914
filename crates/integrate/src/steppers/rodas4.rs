//! Rodas4 (Hairer and Wanner): a six-stage, L-stable, stiffly accurate Rosenbrock method of order 4 with an
//! embedded order-3 estimate and a 3rd-order dense output. The linearised implicit Euler step is the one-stage
//! member of this family. Coefficients are those of Hairer's RODAS (METH = 1).

use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::factorization::{Factorization, Shift};
use crate::jacobian::Jacobian;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{eval, max_norm, weighted_rms, Point};
use crate::system::OdeSystem;

const GAMMA: f64 = 0.25;
const C2: f64 = 0.386;
const C3: f64 = 0.21;
const C4: f64 = 0.63;
const D1: f64 = 0.25;
const D2: f64 = -0.1043;
const D3: f64 = 0.1035;
const D4: f64 = -0.03620000000000023;
const A21: f64 = 1.544;
const A31: f64 = 0.9466785280815826;
const A32: f64 = 0.2557011698983284;
const A41: f64 = 3.314825187068521;
const A42: f64 = 2.896124015972201;
const A43: f64 = 0.9986419139977817;
const A51: f64 = 1.221224509226641;
const A52: f64 = 6.019134481288629;
const A53: f64 = 12.53708332932087;
const A54: f64 = -0.687886036105895;
const C21: f64 = -5.6688;
const C31: f64 = -2.430093356833875;
const C32: f64 = -0.2063599157091915;
const C41: f64 = -0.1073529058151375;
const C42: f64 = -9.594562251023355;
const C43: f64 = -20.47028614809616;
const C51: f64 = 7.496443313967647;
const C52: f64 = -10.24680431464352;
const C53: f64 = -33.99990352819905;
const C54: f64 = 11.7089089320616;
const C61: f64 = 8.083246795921522;
const C62: f64 = -7.981132988064893;
const C63: f64 = -31.52159432874371;
const C64: f64 = 16.31930543123136;
const C65: f64 = -6.058818238834054;
const H21: f64 = 10.12623508344586;
const H22: f64 = -7.487995877610167;
const H23: f64 = -34.80091861555747;
const H24: f64 = -7.992771707568823;
const H25: f64 = 1.025137723295662;
const H31: f64 = -0.6762803392801253;
const H32: f64 = 6.087714651680015;
const H33: f64 = 16.43084320892478;
const H34: f64 = 24.76722511418386;
const H35: f64 = -6.594389125716872;

#[derive(Clone)]
pub(crate) struct Rodas4 {
    jac: Jacobian,
    matrix: Factorization,
    autonomous: bool,
    /// df/dt at the point `fx_point` (zero for autonomous systems).
    fx: Vec<f64>,
    fx_point: Option<u64>,
    k: [Vec<f64>; 6],
    stage: Vec<f64>,
}

impl Rodas4 {
    pub fn new<S: OdeSystem + ?Sized>(sys: &S) -> Result<Self, OdeError> {
        let n = sys.dim();
        let jac = Jacobian::new(sys)?;
        Ok(Rodas4 {
            matrix: Factorization::new(&jac, Shift::Real)?,
            jac,
            autonomous: sys.is_autonomous(),
            fx: vec![0.0; n],
            fx_point: None,
            k: std::array::from_fn(|_| vec![0.0; n]),
            stage: vec![0.0; n],
        })
    }
}

/// out = y + sum a_j k_j.
fn stage_point(out: &mut [f64], y: &[f64], coef: &[f64], k: &[Vec<f64>]) {
    out.copy_from_slice(y);
    for (a, kj) in coef.iter().zip(k) {
        for (o, v) in out.iter_mut().zip(kj) {
            *o += a * v;
        }
    }
}

/// ki += sum (c_j / h) k_j + hd fx, for the stage being formed (`k[..coef.len()]` are the earlier stages).
fn add_coupling(ki: &mut [f64], coef: &[f64], k: &[Vec<f64>], h: f64, hd: f64, fx: &[f64]) {
    for (c, kj) in coef.iter().zip(k) {
        let c = c / h;
        for (o, v) in ki.iter_mut().zip(kj) {
            *o += c * v;
        }
    }
    if hd != 0.0 {
        for (o, v) in ki.iter_mut().zip(fx) {
            *o += hd * v;
        }
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for Rodas4 {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        from.ensure_f(sys, &mut ctx.report)?;
        self.jac.update(sys, from, &mut ctx.report)?;
        let t = from.t;
        if !self.autonomous && self.fx_point != Some(from.id) {
            let delta = (f64::EPSILON * t.abs().max(1e-5)).sqrt();
            eval(sys, t + delta, &from.y, &mut self.stage, &mut ctx.report)?;
            for ((fx, f1), f0) in self.fx.iter_mut().zip(&self.stage).zip(&from.f) {
                *fx = (f1 - f0) / delta;
            }
            self.fx_point = Some(from.id);
        }
        self.matrix.factor(&self.jac, 1.0 / (h * GAMMA), 0.0, t, h, &mut ctx.report)?;
        let r = &mut ctx.report;
        let (y, fx) = (&from.y[..], &self.fx[..]);
        let Rodas4 { matrix, k, stage, .. } = self;

        // Stage 1.
        for i in 0..y.len() {
            k[0][i] = from.f[i] + h * D1 * fx[i];
        }
        matrix.solve(&mut k[0], r);
        // Stages 2-4 at t + c_i h.
        let stages: [(f64, &[f64], &[f64], f64); 3] = [
            (C2, &[A21], &[C21], D2),
            (C3, &[A31, A32], &[C31, C32], D3),
            (C4, &[A41, A42, A43], &[C41, C42, C43], D4),
        ];
        for (s, (c, a, cc, d)) in stages.iter().enumerate() {
            let i = s + 1;
            stage_point(stage, y, a, &k[..i]);
            let (done, rest) = k.split_at_mut(i);
            eval(sys, t + c * h, stage, &mut rest[0], r)?;
            add_coupling(&mut rest[0], cc, done, h, h * d, fx);
            matrix.solve(&mut rest[0], r);
        }
        // Stage 5 at t + h.
        stage_point(stage, y, &[A51, A52, A53, A54], &k[..4]);
        {
            let (done, rest) = k.split_at_mut(4);
            eval(sys, t + h, stage, &mut rest[0], r)?;
            add_coupling(&mut rest[0], &[C51, C52, C53, C54], done, h, 0.0, fx);
            matrix.solve(&mut rest[0], r);
        }
        // Stage 6: the embedded solution is stage + k5; the solution adds k6, which is also the error estimate.
        for (s, k5) in stage.iter_mut().zip(&k[4]) {
            *s += k5;
        }
        {
            let (done, rest) = k.split_at_mut(5);
            eval(sys, t + h, stage, &mut rest[0], r)?;
            add_coupling(&mut rest[0], &[C61, C62, C63, C64, C65], done, h, 0.0, fx);
            matrix.solve(&mut rest[0], r);
        }
        for i in 0..y.len() {
            to.y[i] = stage[i] + k[5][i];
        }
        Ok(Estimate {
            scaled: Some(weighted_rms(&k[5], y, &to.y, ctx.rtol, ctx.atol)),
            local: Some(max_norm(&k[5])),
            safety: None,
        })
    }

    fn reset(&mut self) {
        self.jac.invalidate();
        self.matrix.invalidate();
        self.fx_point = None;
    }

    fn has_dense_output(&self) -> bool {
        true
    }

    fn dense(&self, from: &Point, to: &Point, theta: f64, out: &mut [f64]) {
        let k = &self.k;
        let th1 = 1.0 - theta;
        for i in 0..out.len() {
            let d1 = H21 * k[0][i] + H22 * k[1][i] + H23 * k[2][i] + H24 * k[3][i] + H25 * k[4][i];
            let d2 = H31 * k[0][i] + H32 * k[1][i] + H33 * k[2][i] + H34 * k[3][i] + H35 * k[4][i];
            out[i] = th1 * from.y[i] + theta * (to.y[i] + th1 * (d1 + theta * d2));
        }
    }
}

impl Remember for Rodas4 {
    fn save(&self, out: &mut MemoryWriter) {
        self.jac.save(out);
        out.numbers(&self.fx);
        out.id(self.fx_point);
        self.k.iter().for_each(|k| out.numbers(k));
        out.numbers(&self.stage);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        self.jac.load(input)?;
        self.matrix.invalidate();
        input.numbers("df/dt", &mut self.fx)?;
        self.fx_point = input.id("df/dt point")?;
        for k in &mut self.k {
            input.numbers("rodas4 stage", k)?;
        }
        input.numbers("rodas4 stage state", &mut self.stage)
    }
}

//! Explicit Runge-Kutta methods from their Butcher tableaux (Euler, midpoint, RK4), and the chapter's
//! variable-step Euler.

use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{eval, norm2, Point};
use crate::system::OdeSystem;

/// An explicit Butcher tableau: stage i uses `a[i]` (length i), the solution uses `b`.
#[derive(Clone)]
pub(crate) struct Tableau {
    pub a: &'static [&'static [f64]],
    pub b: &'static [f64],
    pub c: &'static [f64],
}

/// X' = X + h f(X, t).
pub(crate) const EULER: Tableau = Tableau { a: &[&[]], b: &[1.0], c: &[0.0] };

/// X' = X + h f(X + h/2 f(X, t), t + h/2). (The chapter evaluates the middle stage at t; for non-autonomous
/// systems the midpoint rule needs t + h/2.)
pub(crate) const MIDPOINT: Tableau = Tableau { a: &[&[], &[0.5]], b: &[0.0, 1.0], c: &[0.0, 0.5] };

/// Classical RK4. The chapter prints K4 = h f(X + K3/2, t + h); the correct stage is K4 = h f(X + K3, t + h).
pub(crate) const RK4: Tableau = Tableau {
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    c: &[0.0, 0.5, 0.5, 1.0],
};

/// y + h sum_j coef[j] k_j, where k_0 is `f0` and k_j (j >= 1) is `ks[j - 1]`; zero coefficients are skipped.
pub(crate) fn combine(out: &mut [f64], y: &[f64], h: f64, coef: &[f64], f0: &[f64], ks: &[Vec<f64>]) {
    out.copy_from_slice(y);
    for (j, &a) in coef.iter().enumerate() {
        if a == 0.0 {
            continue;
        }
        let k = if j == 0 { f0 } else { &ks[j - 1] };
        let ha = h * a;
        for (o, kv) in out.iter_mut().zip(k) {
            *o += ha * kv;
        }
    }
}

/// An explicit Runge-Kutta method given by its tableau.
#[derive(Clone)]
pub(crate) struct ExplicitRk {
    tableau: &'static Tableau,
    k: Vec<Vec<f64>>,
    stage: Vec<f64>,
}

impl ExplicitRk {
    pub fn new(tableau: &'static Tableau, n: usize) -> Self {
        let stages = tableau.b.len();
        ExplicitRk { tableau, k: vec![vec![0.0; n]; stages - 1], stage: vec![0.0; n] }
    }

    /// The step itself, shared with the multistep starter.
    pub fn advance<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<(), OdeError> {
        from.ensure_f(sys, &mut ctx.report)?;
        let tab = self.tableau;
        for i in 1..tab.b.len() {
            combine(&mut self.stage, &from.y, h, tab.a[i], &from.f, &self.k);
            eval(sys, from.t + tab.c[i] * h, &self.stage, &mut self.k[i - 1], &mut ctx.report)?;
        }
        combine(&mut to.y, &from.y, h, tab.b, &from.f, &self.k);
        Ok(())
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for ExplicitRk {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        self.advance(sys, from, h, to, ctx)?;
        Ok(Estimate::default())
    }
}

/// The chapter's improved (variable-step) Euler: each step is an Euler step of length
/// h = sqrt(2 eps / ||df/dt||_2), where the total derivative df/dt = (df/dX) f + df/dt is the directional
/// difference quotient (f(t + d, X + d f) - f(t, X)) / d: one extra evaluation a step, no Jacobian.
#[derive(Clone)]
pub(crate) struct EulerVariable {
    tolerance: f64,
    dfdt_norm: f64,
    probe: Vec<f64>,
    fprobe: Vec<f64>,
}

impl EulerVariable {
    pub fn new(n: usize, tolerance: f64) -> Self {
        EulerVariable { tolerance, dfdt_norm: 0.0, probe: vec![0.0; n], fprobe: vec![0.0; n] }
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for EulerVariable {
    fn own_step(&mut self, sys: &mut S, from: &mut Point, ctx: &mut Ctx) -> Result<Option<f64>, OdeError> {
        from.ensure_f(sys, &mut ctx.report)?;
        let ymax = from.y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let fmax = from.f.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let d = f64::EPSILON.sqrt() * (1.0 + ymax) / fmax.max(1.0);
        for ((p, y), f) in self.probe.iter_mut().zip(&from.y).zip(&from.f) {
            *p = y + d * f;
        }
        eval(sys, from.t + d, &self.probe, &mut self.fprobe, &mut ctx.report)?;
        for (g, f) in self.fprobe.iter_mut().zip(&from.f) {
            *g = (*g - f) / d;
        }
        self.dfdt_norm = norm2(&self.fprobe);
        if !self.dfdt_norm.is_finite() {
            return Err(OdeError::NonFinite { t: from.t, what: "derivative df/dt", index: 0 });
        }
        Ok(Some(if self.dfdt_norm > 0.0 { (2.0 * self.tolerance / self.dfdt_norm).sqrt() } else { f64::INFINITY }))
    }

    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        from.ensure_f(sys, &mut ctx.report)?;
        for ((o, y), f) in to.y.iter_mut().zip(&from.y).zip(&from.f) {
            *o = y + h * f;
        }
        Ok(Estimate { scaled: None, local: Some(0.5 * h * h * self.dfdt_norm), safety: None })
    }
}

/// Writes a Runge-Kutta method's stage derivatives and stage state (shared with dop853).
pub(crate) fn save_stages(out: &mut MemoryWriter, k: &[Vec<f64>], stage: &[f64]) {
    k.iter().for_each(|k| out.numbers(k));
    out.numbers(stage);
}

/// Reads back what `save_stages` wrote.
pub(crate) fn load_stages(input: &mut MemoryReader, k: &mut [Vec<f64>], stage: &mut [f64]) -> Result<(), String> {
    for k in k {
        input.numbers("rk stage", k)?;
    }
    input.numbers("rk stage state", stage)
}

impl Remember for ExplicitRk {
    fn save(&self, out: &mut MemoryWriter) {
        save_stages(out, &self.k, &self.stage);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        load_stages(input, &mut self.k, &mut self.stage)
    }
}

impl Remember for EulerVariable {
    fn save(&self, out: &mut MemoryWriter) {
        out.number(self.dfdt_norm);
        out.numbers(&self.probe);
        out.numbers(&self.fprobe);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        self.dfdt_norm = input.number("dfdt_norm")?;
        input.numbers("probe", &mut self.probe)?;
        input.numbers("fprobe", &mut self.fprobe)
    }
}

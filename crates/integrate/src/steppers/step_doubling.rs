//! The chapter's step-size control by step doubling around any one-step method of order n: one step of h and two
//! of h/2 from the same point; e = ||X(t+h) - X(two steps of h/2)||_2; the two half steps are kept.

use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::{max_norm, Point};
use crate::system::OdeSystem;

#[derive(Clone)]
pub(crate) struct StepDoubling<T> {
    inner: T,
    tolerance: f64,
    /// Richardson factor 2^n - 1: the half-step solution's error is about e / (2^n - 1).
    richardson: f64,
    full: Point,
    mid: Point,
    diff: Vec<f64>,
}

impl<T> StepDoubling<T> {
    pub fn new(inner: T, n: usize, tolerance: f64, order: u32) -> Self {
        let zero = vec![0.0; n];
        StepDoubling {
            inner,
            tolerance,
            richardson: 2f64.powi(order as i32) - 1.0,
            full: Point::new(0.0, &zero),
            mid: Point::new(0.0, &zero),
            diff: zero,
        }
    }
}

impl<S: OdeSystem + ?Sized, T: Stepper<S> + Clone + Send + 'static> Stepper<S> for StepDoubling<T> {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        self.full.renew(from.t + h);
        self.inner.step(sys, from, h, &mut self.full, ctx)?;
        self.mid.renew(from.t + 0.5 * h);
        self.inner.step(sys, from, 0.5 * h, &mut self.mid, ctx)?;
        self.inner.accepted(from, &self.mid, ctx);
        self.inner.step(sys, &mut self.mid, 0.5 * h, to, ctx)?;
        self.inner.accepted(&self.mid, to, ctx);
        let mut e2 = 0.0;
        for ((d, a), b) in self.diff.iter_mut().zip(&to.y).zip(&self.full.y) {
            *d = a - b;
            e2 += *d * *d;
        }
        let e = e2.sqrt();
        Ok(Estimate {
            scaled: Some(e / self.tolerance),
            local: Some(max_norm(&self.diff) / self.richardson),
            safety: None,
        })
    }

    fn reset(&mut self) {
        self.inner.reset();
    }

    fn rejected(&mut self) {
        self.inner.rejected();
    }

    fn retry_factor(&self) -> Option<f64> {
        self.inner.retry_factor()
    }
}

impl<T: Remember> Remember for StepDoubling<T> {
    fn save(&self, out: &mut MemoryWriter) {
        self.inner.save(out);
        out.point(&self.full);
        out.point(&self.mid);
        out.numbers(&self.diff);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        self.inner.load(input)?;
        input.point("full step", &mut self.full)?;
        input.point("half step", &mut self.mid)?;
        input.numbers("difference", &mut self.diff)
    }
}

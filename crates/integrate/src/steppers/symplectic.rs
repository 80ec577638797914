//! Symplectic methods for split systems y = (q, p): symplectic Euler (kick p with the force at (q, p), then
//! drift q with the new p) and velocity Verlet (half kick, drift, half kick). Both preserve a modified energy,
//! so energy errors stay bounded over long runs instead of drifting. When the force depends on velocity
//! (damping), Verlet's closing half kick is evaluated at a predicted velocity, which keeps it second order.

use super::{Ctx, Estimate, Remember, Stepper};
use crate::error::OdeError;
use crate::memory::{MemoryReader, MemoryWriter};
use crate::point::Point;
use crate::system::{OdeSystem, Split};

#[derive(Clone)]
pub(crate) struct Symplectic {
    verlet: bool,
    split: Split,
    force: Vec<f64>,
    rate: Vec<f64>,
    p_half: Vec<f64>,
    /// The point whose force `force` holds (Verlet, force independent of velocity).
    force_point: Option<u64>,
}

impl Symplectic {
    pub fn new(n: usize, split: Split, verlet: bool) -> Self {
        Symplectic {
            verlet,
            split,
            force: vec![0.0; n - split.positions],
            rate: vec![0.0; split.positions],
            p_half: vec![0.0; n - split.positions],
            force_point: None,
        }
    }

    fn force<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, t: f64, y: &[f64], ctx: &mut Ctx) -> Result<(), OdeError> {
        ctx.report.rhs_evals += 1;
        sys.velocity_rate(t, y, &mut self.force).map_err(|e| OdeError::System { t, message: e.message })
    }

    fn drift<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, t: f64, y: &mut [f64], h: f64) -> Result<(), OdeError> {
        sys.position_rate(t, y, &mut self.rate).map_err(|e| OdeError::System { t, message: e.message })?;
        for (q, r) in y[..self.split.positions].iter_mut().zip(&self.rate) {
            *q += h * r;
        }
        Ok(())
    }

    fn kick(&self, y: &mut [f64], h: f64) {
        for (p, f) in y[self.split.positions..].iter_mut().zip(&self.force) {
            *p += h * f;
        }
    }
}

impl<S: OdeSystem + ?Sized> Stepper<S> for Symplectic {
    fn step(
        &mut self,
        sys: &mut S,
        from: &mut Point,
        h: f64,
        to: &mut Point,
        ctx: &mut Ctx,
    ) -> Result<Estimate, OdeError> {
        let t = from.t;
        to.y.copy_from_slice(&from.y);
        if !self.verlet {
            self.force(sys, t, &from.y, ctx)?;
            self.kick(&mut to.y, h);
            self.drift(sys, t, &mut to.y, h)?;
            return Ok(Estimate::default());
        }
        if self.force_point != Some(from.id) {
            self.force(sys, t, &from.y, ctx)?;
        }
        self.kick(&mut to.y, 0.5 * h);
        self.drift(sys, t + 0.5 * h, &mut to.y, h)?;
        self.force(sys, t + h, &to.y, ctx)?;
        if self.split.force_depends_on_velocity {
            // Predict p_new with the force at (q_new, p_half), then kick with the force at the prediction.
            let k = self.split.positions;
            self.p_half.copy_from_slice(&to.y[k..]);
            self.kick(&mut to.y, 0.5 * h);
            self.force(sys, t + h, &to.y, ctx)?;
            to.y[k..].copy_from_slice(&self.p_half);
        }
        self.kick(&mut to.y, 0.5 * h);
        // The force just evaluated at (q_new, p_half) is the force at (q_new, p_new) when it ignores velocity.
        self.force_point = if self.split.force_depends_on_velocity { None } else { Some(to.id) };
        Ok(Estimate::default())
    }

    fn reset(&mut self) {
        self.force_point = None;
    }
}

impl Remember for Symplectic {
    fn save(&self, out: &mut MemoryWriter) {
        out.numbers(&self.force);
        out.numbers(&self.rate);
        out.numbers(&self.p_half);
        out.id(self.force_point);
    }

    fn load(&mut self, input: &mut MemoryReader) -> Result<(), String> {
        input.numbers("force", &mut self.force)?;
        input.numbers("rate", &mut self.rate)?;
        input.numbers("p_half", &mut self.p_half)?;
        self.force_point = input.id("force point")?;
        Ok(())
    }
}

//! The driver's side of events (`events.rs`): the step just accepted shown to a detector, and ended at the time of
//! an event it reports.

use super::Integrator;
use crate::error::OdeError;
use crate::events::StepView;
use crate::settings::StepControl;
use crate::system::OdeSystem;

/// The driver's side of events: showing the step just accepted to a detector, and ending it at an event.
impl<S: OdeSystem + ?Sized> Integrator<S> {
    /// The step just accepted (cur -> next), for a detector or an interpolation.
    pub(crate) fn view<'a>(&'a mut self, sys: &'a mut S) -> StepView<'a, S> {
        let dense =
            self.stepper.has_dense_output() && !matches!(self.settings.control, StepControl::StepDoubling { .. });
        StepView { sys, stepper: &mut *self.stepper, ctx: &mut self.ctx, from: &self.cur, to: &self.next, dense }
    }

    /// Shows the step just accepted (cur -> next) to `detect`; returns the event time it reports, within the step.
    pub(crate) fn detect(
        &mut self,
        sys: &mut S,
        detect: &mut impl FnMut(&mut StepView<'_, S>) -> Result<Option<f64>, OdeError>,
    ) -> Result<Option<f64>, OdeError> {
        let (t0, t1) = (self.cur.t, self.next.t);
        Ok(detect(&mut self.view(sys))?.map(|tc| tc.clamp(t0, t1)))
    }

    /// Ends the step just accepted at tc: cur becomes the state there and the method's histories are dropped.
    pub(crate) fn cut_at(&mut self, sys: &mut S, tc: f64) -> Result<(), OdeError> {
        // The step taken is the one that ends at the event: the log shows that one (none if it ends where it began).
        let start = self.cur.t;
        if let Some(log) = &mut self.step_log {
            log.pop();
            if tc > start {
                log.push((tc, tc - start));
            }
        }
        if tc < self.next.t {
            let y = self.view(sys).state_at(tc)?;
            self.next.y.copy_from_slice(&y);
            self.next.renew(tc);
        }
        std::mem::swap(&mut self.cur, &mut self.next);
        self.stepper.reset();
        Ok(())
    }
}

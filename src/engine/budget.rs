//! One call's step budget: every step an engine takes or rejects on behalf of a user's call (`step` or `run`,
//! across all of a run's chunks; a contact step of accurate mode counts each convex program it solves) is charged to
//! it, and the call ends in a clear error when it is spent. Only counts decide, never the clock, so the outcome is
//! the same on every machine. (A call's cost cannot be told from its start: a pile dropped and then left to rest
//! for a minute spends nearly all of its work in its first second, so the budget does not judge a call's pace.)
//! The budget also carries the call's control: charges tell it how far the call has come (at most every 50 ms of
//! wall time, so that a control that takes Python's lock costs nothing; the clock decides only when it is asked,
//! never what is computed), and a control that answers false (Ctrl-C in Python) stops the call, which the world
//! then puts back as it was. The pace is watched through `Watch` (the world's `Pace`, `world/pace.rs`, is one),
//! so that the budget knows nothing of the world.

use crate::control::Control;
use std::time::{Duration, Instant};
use tumble_integrate::OdeError;

/// Least wall time between two calls of the control from within the work.
const TELL_EVERY: Duration = Duration::from_millis(50);

/// What watches a call's pace for its budget (the world's `Pace`, `world/pace.rs`): told the fraction of the call
/// done at every tell, it gives the one line for the control when one is due.
pub(crate) trait Watch {
    /// The line, once, when `fraction` done after the time taken so far projects a slow call.
    fn watch(&mut self, fraction: f64) -> Option<String>;

    /// Whether the line was given.
    fn given(&self) -> bool;
}

/// The step budget of one call over its span [t0, t_end], with the call's control.
pub(crate) struct Budget<'c> {
    limit: usize,
    spent: usize,
    t0: f64,
    t_end: f64,
    /// Told the fraction of the span done; false stops the call.
    control: Option<&'c mut dyn Control>,
    /// The call's pace, watched at every tell (`world/pace.rs`).
    pace: Option<Box<dyn Watch + 'c>>,
    /// The largest fraction told so far (what the control sees never goes back).
    shown: f64,
    /// Whether the control stopped the call.
    pub stopped: bool,
    /// When the control was last told.
    told: Instant,
}

impl<'c> Budget<'c> {
    /// A budget of `limit` steps for a call from t0 to t_end.
    pub fn new(limit: usize, t0: f64, t_end: f64) -> Budget<'c> {
        Budget {
            limit: limit.max(1),
            spent: 0,
            t0,
            t_end,
            control: None,
            pace: None,
            shown: 0.0,
            stopped: false,
            told: Instant::now(),
        }
    }

    /// The same, telling `control` how far the call has come at every charge.
    pub fn with_control(mut self, control: &'c mut dyn Control) -> Budget<'c> {
        self.control = Some(control);
        self
    }

    /// The same, watching the call's pace and giving the control its line when one is due.
    pub fn with_pace(mut self, pace: Option<impl Watch + 'c>) -> Budget<'c> {
        self.pace = pace.map(|p| Box::new(p) as Box<dyn Watch + 'c>);
        self
    }

    /// Whether the pace's line was given.
    pub fn hinted(&self) -> bool {
        self.pace.as_ref().is_some_and(|p| p.given())
    }

    /// Tells the control that `fraction` of the call is done; false (and `stopped`) if it stops the call.
    pub fn tell(&mut self, fraction: f64) -> bool {
        self.shown = self.shown.max(fraction.clamp(0.0, 1.0));
        self.told = Instant::now();
        let go_on = self.control.as_mut().is_none_or(|c| c.go_on(self.shown));
        self.stopped |= !go_on;
        if let (Some(pace), Some(control)) = (self.pace.as_mut(), self.control.as_mut()) {
            if let Some(line) = pace.watch(self.shown) {
                control.hint(&line);
            }
        }
        go_on
    }

    /// The fraction of the call's span done at time t.
    pub fn fraction(&self, t: f64) -> f64 {
        ((t - self.t0) / (self.t_end - self.t0)).clamp(0.0, 1.0)
    }

    /// The budget, as `max_steps` names it in errors.
    pub fn limit(&self) -> usize {
        self.limit
    }

    /// Steps still allowed.
    pub fn left(&self) -> usize {
        self.limit.saturating_sub(self.spent)
    }

    /// Charges `steps` taken by time t: an error once the budget is spent, or when the control stops the call.
    pub fn charge(&mut self, steps: usize, t: f64) -> Result<(), OdeError> {
        self.spent = self.spent.saturating_add(steps);
        if self.spent > self.limit {
            return Err(OdeError::TooManySteps { t, max_steps: self.limit });
        }
        let fraction = self.fraction(t);
        if self.control.is_some() && self.told.elapsed() >= TELL_EVERY && !self.tell(fraction) {
            return Err(OdeError::System { t, message: "stopped by the call's control".into() });
        }
        Ok(())
    }
}

/// An integrator that ran out of the steps left names the call's whole budget.
pub(crate) fn over_budget(e: OdeError, budget: &Budget) -> OdeError {
    match e {
        OdeError::TooManySteps { t, .. } => OdeError::TooManySteps { t, max_steps: budget.limit() },
        e => e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spent_budget_is_an_error_naming_it() {
        let mut b = Budget::new(100, 0.0, 1.0);
        assert!(b.charge(60, 0.9).is_ok());
        assert_eq!(b.left(), 40);
        assert!(b.charge(40, 0.95).is_ok());
        assert!(matches!(b.charge(1, 0.96), Err(OdeError::TooManySteps { max_steps: 100, .. })));
    }

    #[test]
    fn the_control_hears_the_fraction_done_never_going_back_and_can_stop_the_call() {
        let mut heard = Vec::new();
        let mut control = |f: f64| {
            heard.push(f);
            f < 0.5
        };
        {
            let mut b = Budget::new(1000, 1.0, 3.0).with_control(&mut control);
            std::thread::sleep(TELL_EVERY);
            assert!(b.charge(1, 1.5).is_ok());
            assert!(b.tell(0.2), "a smaller fraction is told as the largest so far");
            std::thread::sleep(TELL_EVERY);
            assert!(b.charge(1, 2.5).is_err(), "the control stopped the call at 75%");
            assert!(b.stopped);
        }
        assert_eq!(heard, vec![0.25, 0.25, 0.75]);
    }
}

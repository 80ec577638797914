//! One call's step budget: every step an engine takes or rejects on behalf of a user's call (`step` or `run`,
//! across all of a run's chunks; a contact step of accurate mode counts each convex program it solves) is charged to
//! it. The call ends in a clear error when the budget is spent, or earlier when its pace says it would need many
//! budgets: a call that a scene makes hopeless (contact steps of 1e-7 s over a span of a second) then fails in
//! seconds instead of minutes. Only counts decide, never the clock, so the outcome is the same on every machine.

use tumble_integrate::OdeError;

/// How far past the budget a call's pace must point before it is stopped early: far enough that a call whose work
/// comes in a burst at its start (a pile's first impacts, before it settles) is not stopped on its burst's pace
/// unless that burst alone is a tenth of the budget in under a thirtieth of the span.
const PROJECTION_FACTOR: f64 = 3.0;
/// The share of the budget spent before the pace is judged (a pace from a few steps says little). A pile of 1 mm
/// bodies hit at 1 m/s (contact steps of 1e-7 s, 30 solves each) asked for 0.25 s is stopped here after 20 s
/// instead of after the whole budget's 200 s.
const JUDGED_AFTER: f64 = 0.1;

/// The step budget of one call over its span [t0, t_end].
#[derive(Clone, Debug)]
pub(crate) struct Budget {
    limit: usize,
    spent: usize,
    t0: f64,
    t_end: f64,
}

impl Budget {
    /// A budget of `limit` steps for a call from t0 to t_end.
    pub fn new(limit: usize, t0: f64, t_end: f64) -> Budget {
        Budget { limit: limit.max(1), spent: 0, t0, t_end }
    }

    /// The budget, as `max_steps` names it in errors.
    pub fn limit(&self) -> usize {
        self.limit
    }

    /// Steps still allowed.
    pub fn left(&self) -> usize {
        self.limit.saturating_sub(self.spent)
    }

    /// Charges `steps` taken by time t: an error once the budget is spent, or once a tenth of it is spent and the
    /// pace so far points past three budgets for the whole span.
    pub fn charge(&mut self, steps: usize, t: f64) -> Result<(), OdeError> {
        self.spent = self.spent.saturating_add(steps);
        if self.spent > self.limit {
            return Err(OdeError::TooManySteps { t, max_steps: self.limit });
        }
        if (self.spent as f64) < JUDGED_AFTER * self.limit as f64 {
            return Ok(());
        }
        let fraction = ((t - self.t0) / (self.t_end - self.t0)).clamp(0.0, 1.0);
        let projected = if fraction > 0.0 { self.spent as f64 / fraction } else { f64::INFINITY };
        if projected > PROJECTION_FACTOR * self.limit as f64 {
            return Err(OdeError::OverBudget { t, max_steps: self.limit, spent: self.spent, fraction, projected });
        }
        Ok(())
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
    fn a_hopeless_pace_stops_early_and_a_burst_does_not() {
        // 10% of the budget for 3% of the span: a pace of 3.3 budgets.
        let mut hopeless = Budget::new(1000, 0.0, 1.0);
        assert!(hopeless.charge(99, 0.03).is_ok(), "not judged before 10% of the budget");
        let err = hopeless.charge(1, 0.03).unwrap_err();
        assert!(matches!(err, OdeError::OverBudget { spent: 100, .. }), "{err:?}");
        assert!(err.to_string().contains("max_steps = 1000"), "{err}");
        // The same work for 4% of the span is a pace of 2.5 budgets: allowed to go on.
        let mut burst = Budget::new(1000, 0.0, 1.0);
        assert!(burst.charge(100, 0.04).is_ok());
    }
}

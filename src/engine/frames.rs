//! The cursor over a call's frame times that both engines record frames with: which frames a time has reached, and
//! which fall inside a step, under one time slack.

/// The frame times of one advance (`saves`, increasing) and how many have been recorded.
pub(crate) struct FrameCursor<'a> {
    saves: &'a [f64],
    next: usize,
    slack: f64,
}

impl<'a> FrameCursor<'a> {
    /// The cursor over `saves` for an advance that ends at `t_end`: a time within 1e-12 of the larger of |t_end| and
    /// 1 s of a frame's reaches it (a step that lands an ulp short of a frame still records it).
    pub fn new(saves: &'a [f64], t_end: f64) -> Self {
        FrameCursor { saves, next: 0, slack: 1e-12 * t_end.abs().max(1.0) }
    }

    /// The time slack: how close a time must come to a frame to reach it.
    pub fn slack(&self) -> f64 {
        self.slack
    }

    /// The frames recorded so far.
    pub fn delivered(&self) -> usize {
        self.next
    }

    /// The next frame's time if time `t` has reached it; the caller records it, then calls `advance`.
    pub fn reached(&self, t: f64) -> Option<f64> {
        self.saves.get(self.next).copied().filter(|&s| s <= t + self.slack)
    }

    /// The next frame's time if it falls before time `t` by more than the slack (inside a step that ends at t).
    pub fn inside(&self, t: f64) -> Option<f64> {
        self.saves.get(self.next).copied().filter(|&s| s < t - self.slack)
    }

    /// Passes the next frame (recorded or not).
    pub fn advance(&mut self) {
        self.next = (self.next + 1).min(self.saves.len());
    }

    /// The frames not yet recorded.
    pub fn rest(&self) -> &'a [f64] {
        &self.saves[self.next..]
    }

    /// Passes `n` frames that another loop recorded (the integrator's dense output).
    pub fn skip(&mut self, n: usize) {
        self.next = (self.next + n).min(self.saves.len());
    }

    /// Passes every frame time `t` has reached; how many.
    pub fn pass_reached(&mut self, t: f64) -> usize {
        let start = self.next;
        while self.reached(t).is_some() {
            self.advance();
        }
        self.next - start
    }
}

#[cfg(test)]
mod tests {
    use super::FrameCursor;

    #[test]
    fn frames_are_reached_within_the_slack_and_inside_a_step_only_before_it() {
        let saves = [0.0, 0.5, 1.0 - 1e-13, 1.5];
        let mut c = FrameCursor::new(&saves, 2.0);
        assert_eq!(c.slack(), 2e-12);
        assert_eq!(c.reached(0.0), Some(0.0));
        c.advance();
        // 0.5 is inside a step ending at 0.75, and not reached at 0.25
        assert_eq!(c.inside(0.75), Some(0.5));
        assert_eq!(c.reached(0.25), None);
        assert_eq!(c.inside(0.5), None, "a frame at a step's end is the step's state, not an interpolation");
        c.advance();
        // a step ending an ulp-sized hair after 1 - 1e-13 reaches that frame; one ending at 1 - 1e-11 does not
        assert_eq!(c.reached(1.0 - 1e-11), None);
        assert_eq!(c.pass_reached(1.0), 1);
        assert_eq!(c.delivered(), 3);
        assert_eq!(c.pass_reached(5.0), 1);
        c.advance();
        assert_eq!((c.delivered(), c.reached(9.0), c.inside(9.0)), (4, None, None));
    }
}

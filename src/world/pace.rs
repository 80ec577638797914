//! A long call's pace: the wall time it projects for the span it simulates, and, when accurate mode projects more
//! than ten times the simulated time, the one line (once a world) that says so and names fast mode with its time
//! measured on a copy. Never a switch: the call goes on as asked.

use super::World;
use crate::control::Quiet;
use crate::engine::Watch;
use crate::mode::Mode;
use crate::options::DEFAULT_DT;
use std::time::Instant;

/// Projected wall time past this many times the simulated time is slow enough to say so.
pub(crate) const SLOW: f64 = 10.0;
/// Wall time a call has taken before its projection is trusted (s): a call shorter than this needs no hint.
const WATCH_AFTER: f64 = 2.0;
/// Simulated time of fast mode's sample on a copy (s).
const SAMPLE: f64 = 0.25;

/// The pace of one call of accurate mode (the world as the call found it, its span).
pub(crate) struct Pace<'w> {
    world: &'w World,
    span: f64,
    start: Instant,
    /// Whether the line was given.
    given: bool,
}

impl<'w> Pace<'w> {
    /// The pace of a call over `span` of `world`; None where no line can be due (fast mode, or already said).
    pub fn new(world: &'w World, span: f64) -> Option<Pace<'w>> {
        (matches!(world.mode, Mode::Accurate(_)) && !world.hinted).then(|| Pace {
            world,
            span,
            start: Instant::now(),
            given: false,
        })
    }
}

impl Watch for Pace<'_> {
    /// The line, once, when `fraction` done after the time taken so far projects past `SLOW` times the span.
    fn watch(&mut self, fraction: f64) -> Option<String> {
        if self.given {
            return None;
        }
        let projected = projected_if_slow(self.start.elapsed().as_secs_f64(), fraction, self.span)?;
        self.given = true;
        Some(slow_line(projected, self.span, fast_estimate(self.world, self.span)))
    }

    fn given(&self) -> bool {
        self.given
    }
}

/// The projected wall time of a call over `span` that took `elapsed` s for `fraction` of it, if it is past `SLOW`
/// times the span and the call has run long enough (`WATCH_AFTER`) for the projection to be trusted.
pub(crate) fn projected_if_slow(elapsed: f64, fraction: f64, span: f64) -> Option<f64> {
    if elapsed < WATCH_AFTER || fraction <= 0.0 {
        return None;
    }
    let projected = elapsed / fraction.min(1.0);
    (projected > SLOW * span).then_some(projected)
}

/// The line for a call projected at `projected` s of wall time for `span` s simulated, with fast mode's estimate.
pub(crate) fn slow_line(projected: f64, span: f64, fast: Option<f64>) -> String {
    let fast = match fast {
        Some(s) => {
            format!("fast mode (mode \"fast\", steps of 1/240 s) would take about {} (timed on a copy)", seconds(s))
        }
        None => "fast mode (mode \"fast\") cannot run this world as it is".into(),
    };
    format!(
        "accurate mode projects about {projected:.0} s for these {span} s simulated ({:.0} times), its contact steps \
         as short as the fastest contact of each touching island needs; {fast}, at looser accuracy. Carrying on.",
        projected / span
    )
}

/// A wall time as a person reads it: two significant figures below ten seconds, whole seconds above.
fn seconds(s: f64) -> String {
    if s >= 10.0 {
        format!("{s:.0} s")
    } else if s >= 1.0 {
        format!("{s:.1} s")
    } else {
        format!("{s:.2} s")
    }
}

/// Fast mode's wall time for `span` of `world` from where it is: a copy in fast mode at its default step, timed over
/// its first `SAMPLE` s (or the span, if shorter) and scaled to the span. None if fast mode cannot run the world.
pub(crate) fn fast_estimate(world: &World, span: f64) -> Option<f64> {
    let mut copy = world.clone();
    copy.engine = None;
    copy.set_mode(Mode::fast(DEFAULT_DT)).ok()?;
    let sample = (SAMPLE.min(span) / DEFAULT_DT).ceil().max(1.0) * DEFAULT_DT;
    let clock = Instant::now();
    copy.step_with(sample, Quiet(|_| true)).ok()?;
    Some(clock.elapsed().as_secs_f64() * span / sample)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_call_is_slow_past_ten_times_its_span_once_it_has_run_two_seconds() {
        // 3 s for a tenth of 2 s simulated projects 30 s: 15 times
        assert_eq!(projected_if_slow(3.0, 0.1, 2.0), Some(30.0));
        // 3 s for half of it projects 6 s: 3 times, not slow
        assert_eq!(projected_if_slow(3.0, 0.5, 2.0), None);
        // a projection from less than two seconds of work is not trusted, however slow
        assert_eq!(projected_if_slow(1.9, 1e-3, 2.0), None);
        // nothing done yet: no projection
        assert_eq!(projected_if_slow(5.0, 0.0, 2.0), None);
        // at exactly ten times it is not past
        assert_eq!(projected_if_slow(2.0, 0.1, 2.0), None);
    }

    #[test]
    fn the_line_names_fast_mode_and_its_time_or_says_it_cannot_run() {
        let line = slow_line(412.0, 10.0, Some(1.94));
        assert!(line.contains("about 412 s for these 10 s simulated (41 times)"), "{line}");
        assert!(line.contains("fast mode (mode \"fast\", steps of 1/240 s) would take about 1.9 s"), "{line}");
        assert!(!line.contains('\n'), "one line: {line}");
        assert!(slow_line(412.0, 10.0, None).contains("cannot run this world"));
        assert!(slow_line(412.0, 10.0, Some(0.043)).contains("would take about 0.04 s"));
        assert!(slow_line(412.0, 10.0, Some(37.4)).contains("would take about 37 s"));
    }

    #[test]
    fn fast_modes_estimate_is_timed_on_a_copy_and_leaves_the_world_alone() {
        let mut w = World::new();
        w.add_ground(0.0, crate::Material::default()).unwrap();
        let b = w
            .add_body(
                crate::RigidBodyBuilder::from_shape(crate::Shape::sphere(0.1).unwrap(), 1000.0)
                    .position(nalgebra::Vector3::new(0.0, 0.0, 1.0)),
            )
            .unwrap();
        let before = (w.time(), w.body(b).unwrap().position);
        let estimate = fast_estimate(&w, 10.0).expect("fast mode runs a ball");
        assert!(estimate.is_finite() && estimate > 0.0, "{estimate}");
        assert_eq!((w.time(), w.body(b).unwrap().position), before);
        assert_eq!(w.mode().name(), "accurate");
    }
}

//! The judgement of a contact step from its error estimates alone (numbers in, a verdict out: no model, no solve):
//! keep it, take it again shorter, or take it again to end just before a sliding contact's stop; the next step's
//! size; and, once the energy guard has chosen the state kept, whether that state's own error still holds.

/// The share of the tolerance a sliding contact's stop may cut short inside a step before the step is cut at it.
const STOP_SHARE: f64 = 0.1;
/// The earliest stop located, as a fraction of the step: earlier ones are left to the error control.
const STOP_EARLIEST: f64 = 0.01;

/// What a doubled step measured (`touching.rs`), in metres.
#[derive(Clone, Copy, Debug)]
pub(super) struct Estimates {
    /// The step's size (s).
    pub h: f64,
    /// The contact tolerance (m).
    pub tolerance: f64,
    /// The halves' estimate: their difference from the whole step, the slip a stop cut short and the sinking
    /// charged to the step, the largest.
    pub halves: f64,
    /// How the halves' difference changed since the last step (|d - (h / h_last)^2 d_last|), where the step is
    /// smooth (the extrapolation used, the same contacts pushing, no stop) and the last step left a difference.
    pub change: Option<f64>,
    /// How deep the extrapolated state sinks a contact (charged where the extrapolation's estimate governs).
    pub sink_extrapolated: f64,
    /// The slip a sliding contact's stop cut short (m) and the earliest stop's place in the step (0 to 1).
    pub stop: f64,
    pub stop_at: f64,
    /// Whether this try was already cut to end at a stop (one try a step).
    pub located: bool,
}

/// A contact step's verdict.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Verdict {
    /// Take the step again, this long (its estimate is past the tolerance).
    Retry(f64),
    /// Take it again to end just before the stop, this long.
    Locate(f64),
    /// Keep it: its error (m) and the factor for the next step's size.
    Keep { error: f64, grow: f64 },
}

/// The verdict on a step from its estimates: the extrapolated state's estimate governs a smooth step (its change,
/// no more than the halves', and its sinking), the halves' any other; the step is taken again when that is past the
/// tolerance, or to end just before a stop that cut short more than `STOP_SHARE` of the tolerance. The next step
/// grows by 0.9 (tol / err)^(1/order), order 3 after a smooth step and 2 otherwise, within 0.2 to 2.
pub(super) fn judge(e: &Estimates) -> Verdict {
    let error = e.change.map_or(e.halves, |c| c.min(e.halves).max(e.sink_extrapolated));
    let ratio = error / e.tolerance;
    let order = if e.change.is_some() { 3.0 } else { 2.0 };
    let grow = (0.9 * ratio.max(1e-300).powf(-1.0 / order)).clamp(0.2, 2.0);
    let locating = !e.located && e.stop > STOP_SHARE * e.tolerance && (STOP_EARLIEST..1.0).contains(&e.stop_at);
    if locating {
        Verdict::Locate(e.h * (1.0 - 1e-3) * e.stop_at)
    } else if ratio > 1.0 || ratio.is_nan() {
        Verdict::Retry(e.h * grow.min(0.5))
    } else {
        Verdict::Keep { error, grow }
    }
}

/// Where the energy guard refused the extrapolation, the halves are kept with their own estimate `kept`: a shorter
/// step (0.9 (tol / err)^(1/2) of it, within 0.2 to 0.5) when that is past the tolerance, else none.
pub(super) fn judge_kept(h: f64, tolerance: f64, kept: f64) -> Option<f64> {
    (kept > tolerance).then(|| h * (0.9 * (tolerance / kept).sqrt()).clamp(0.2, 0.5))
}

/// The next step's size after a step of `h` kept with growth `grow`: at most `max_step`; a step cut short by the end
/// of the advance or a limit (`clipped`) keeps the size proposed before it (`proposed`) if that was longer.
pub(super) fn next_step(h: f64, grow: f64, max_step: f64, clipped: bool, proposed: f64) -> f64 {
    let next = (h * grow).min(max_step);
    if clipped {
        next.max(proposed)
    } else {
        next
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn estimates() -> Estimates {
        Estimates {
            h: 1e-2,
            tolerance: 1e-4,
            halves: 5e-5,
            change: None,
            sink_extrapolated: 0.0,
            stop: 0.0,
            stop_at: 1.0,
            located: false,
        }
    }

    #[test]
    fn a_step_within_the_tolerance_is_kept_and_grows_by_the_halves_order() {
        // halves at half the tolerance, order 2: 0.9 * 2^(1/2)
        let Verdict::Keep { error, grow } = judge(&estimates()) else { panic!() };
        assert_eq!(error, 5e-5);
        assert!((grow - 0.9 * 2f64.sqrt()).abs() < 1e-15, "{grow}");
    }

    #[test]
    fn a_smooth_step_is_judged_by_its_change_to_third_order_but_never_by_more_than_its_halves() {
        let smooth = Estimates { change: Some(1e-6), ..estimates() };
        let Verdict::Keep { error, grow } = judge(&smooth) else { panic!() };
        assert_eq!(error, 1e-6);
        // 0.9 * 100^(1/3) = 4.18, held to 2
        assert_eq!(grow, 2.0);
        // the change larger than the halves' estimate: the halves' governs
        let Verdict::Keep { error, .. } = judge(&Estimates { change: Some(8e-5), ..estimates() }) else { panic!() };
        assert_eq!(error, 5e-5);
        // the extrapolation's sinking is charged
        let sunk = Estimates { change: Some(1e-6), sink_extrapolated: 2e-5, ..estimates() };
        assert!(matches!(judge(&sunk), Verdict::Keep { error, .. } if error == 2e-5));
    }

    #[test]
    fn a_step_past_the_tolerance_is_retried_at_most_half_as_long() {
        // 4 times the tolerance: 0.9 / 2 = 0.45 of the step
        let v = judge(&Estimates { halves: 4e-4, ..estimates() });
        assert!(matches!(v, Verdict::Retry(h) if (h - 0.45e-2).abs() < 1e-16), "{v:?}");
        // just past it: the growth 0.9 (1.01)^(-1/2) held to half
        assert_eq!(judge(&Estimates { halves: 1.01e-4, ..estimates() }), Verdict::Retry(0.5e-2));
        // far past it: a fifth
        assert_eq!(judge(&Estimates { halves: 1.0, ..estimates() }), Verdict::Retry(0.2e-2));
        // an estimate that is not a number is never kept
        assert!(matches!(judge(&Estimates { halves: f64::NAN, ..estimates() }), Verdict::Retry(_)));
    }

    #[test]
    fn a_stop_that_cut_short_a_tenth_of_the_tolerance_is_located_once() {
        let stop = Estimates { stop: 2e-5, stop_at: 0.4, ..estimates() };
        assert_eq!(judge(&stop), Verdict::Locate(1e-2 * (1.0 - 1e-3) * 0.4));
        // already cut once: judged by its estimate
        assert!(matches!(judge(&Estimates { located: true, ..stop }), Verdict::Keep { .. }));
        // too small, or too early in the step, to locate
        assert!(matches!(judge(&Estimates { stop: 5e-6, ..stop }), Verdict::Keep { .. }));
        assert!(matches!(judge(&Estimates { stop_at: 0.005, ..stop }), Verdict::Keep { .. }));
    }

    #[test]
    fn the_halves_kept_past_the_tolerance_are_retried_and_the_next_step_respects_its_bounds() {
        assert_eq!(judge_kept(1.0, 1e-4, 5e-5), None);
        // 9 times the tolerance: 0.9 / 3 = 0.3
        assert!((judge_kept(1.0, 1e-4, 9e-4).unwrap() - 0.3).abs() < 1e-15);
        assert_eq!(judge_kept(1.0, 1e-4, 1.01e-4), Some(0.5));
        assert_eq!(judge_kept(1.0, 1e-4, 1.0), Some(0.2));
        assert_eq!(next_step(0.1, 2.0, 0.15, false, 1.0), 0.15);
        assert_eq!(next_step(0.1, 1.5, 1.0, false, 1.0), 0.15000000000000002);
        // a step clipped to an end keeps the longer size proposed before it
        assert_eq!(next_step(0.01, 1.5, 1.0, true, 0.2), 0.2);
    }
}

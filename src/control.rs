//! A long call's control: told how far the call has come (false stops it) and given the one line a slow accurate
//! run says about fast mode. Any `FnMut(f64) -> bool` is a control that prints that line to standard error.

/// What `World::step_with` and `World::run_with` tell as they work.
pub trait Control {
    /// `fraction` (0 to 1, never going back) of the call is done; false stops the call.
    fn go_on(&mut self, fraction: f64) -> bool;

    /// One line for the person waiting (at most once a world: accurate mode projecting more than ten times the
    /// simulated time, with fast mode's estimate). Printed to standard error unless the control shows it itself.
    fn hint(&mut self, line: &str) {
        eprintln!("tumble: {line}");
    }

    /// Whether the call it stopped keeps its work (an interrupt: a run's frames kept and the world at the last of
    /// them; the default) rather than failing (the world back as the call found it, the frames kept on the error
    /// only): asked once `go_on` has said false.
    fn keeps_work(&self) -> bool {
        true
    }
}

impl<F: FnMut(f64) -> bool> Control for F {
    fn go_on(&mut self, fraction: f64) -> bool {
        self(fraction)
    }
}

/// A control that keeps quiet: the call goes on while `go_on` says so, and hints are dropped (copies run by the
/// batch, whose person cannot act on each one).
pub(crate) struct Quiet<F: FnMut(f64) -> bool>(pub F);

impl<F: FnMut(f64) -> bool> Control for Quiet<F> {
    fn go_on(&mut self, fraction: f64) -> bool {
        (self.0)(fraction)
    }

    fn hint(&mut self, _line: &str) {}
}

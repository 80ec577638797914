//! Batches: many copies of one world run from many states on a thread pool (rayon). Each copy is the world as it
//! is (its engine's memory included) set to one state and run; copies share nothing that their arithmetic reads,
//! and each is deterministic, so the runs are the same bit for bit as the same copies run one after another, on
//! any number of threads.

use crate::control::Quiet;
use crate::error::WorldError;
use crate::limits;
use crate::run::Run;
use crate::world::{World, WorldState};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// How often the calling thread calls the control while a batch runs.
const TICK: std::time::Duration = std::time::Duration::from_millis(20);

/// How a batch runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RolloutSettings {
    /// Simulated time each copy runs (s).
    pub duration: f64,
    /// Time between recorded frames (s).
    pub frame_interval: f64,
    /// Threads of the pool: 0 uses one per core. Each copy's own contact solves then run on its thread alone.
    pub threads: usize,
}

/// Runs a copy of `world` from each of `states` for `settings.duration`, on `settings.threads` threads, and returns
/// the runs in the order of `states`. `control(fraction of copies done)` is called on the calling thread every
/// 20 ms or so while the copies run; returning false stops the batch within a copy's step or chunk of frames, with
/// [`WorldError::Interrupted`]. A copy
/// that fails fails the batch with its error (said with its index); `world` itself never changes. Force callbacks
/// are shared by the copies and called from several threads: they must not keep state.
pub fn rollout(
    world: &World,
    states: &[WorldState],
    settings: RolloutSettings,
    mut control: impl FnMut(f64) -> bool,
) -> Result<Vec<Run>, WorldError> {
    limits::positive("duration", settings.duration, limits::TIME, "s")?;
    limits::positive("frame_interval", settings.frame_interval, limits::TIME, "s")?;
    if settings.threads > 1024 {
        return Err(WorldError::invalid("threads", format!("must be at most 1024, got {}", settings.threads)));
    }
    // every state is checked against the world before any copy runs
    let mut checker = world.clone();
    for (k, s) in states.iter().enumerate() {
        checker.set_state(s).map_err(|e| at(k, e))?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.threads)
        .build()
        .map_err(|e| WorldError::invalid("threads", e.to_string()))?;
    let (done, stop) = (AtomicUsize::new(0), AtomicBool::new(false));
    // the world is not `Sync` (its integrator's parts are only `Send`): each copy is cloned under a lock
    let template = Mutex::new(world.clone());
    let one = |k: usize, s: &WorldState| -> Result<Run, WorldError> {
        if stop.load(Ordering::Relaxed) {
            return Err(WorldError::Interrupted);
        }
        let mut copy = template.lock().unwrap_or_else(|e| e.into_inner()).clone();
        copy.set_threads(1)?;
        copy.set_state(s)?;
        let run = copy
            .run_with(settings.duration, settings.frame_interval, Quiet(|_| !stop.load(Ordering::Relaxed)))
            .map_err(|e| at(k, e))?;
        done.fetch_add(1, Ordering::Relaxed);
        Ok(run)
    };
    let runs: Vec<Result<Run, WorldError>> = std::thread::scope(|scope| {
        let (finished, wait) = std::sync::mpsc::channel::<()>();
        let batch = scope.spawn(move || {
            let runs = pool.install(|| states.par_iter().enumerate().map(|(k, s)| one(k, s)).collect());
            let _ = finished.send(());
            runs
        });
        let fraction = || done.load(Ordering::Relaxed) as f64 / states.len().max(1) as f64;
        // the calling thread answers to the control every 20 ms until the batch is done (or its thread ended)
        while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(TICK) {
            if !stop.load(Ordering::Relaxed) && !control(fraction()) {
                stop.store(true, Ordering::Relaxed);
            }
        }
        let runs = batch.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        if !stop.load(Ordering::Relaxed) {
            control(1.0); // the batch is done: this call only shows it
        }
        runs
    });
    if stop.load(Ordering::Relaxed) {
        return Err(WorldError::Interrupted);
    }
    runs.into_iter().collect()
}

/// A copy's error, said with its index.
fn at(k: usize, e: WorldError) -> WorldError {
    match e {
        WorldError::InvalidArgument { name, reason } => {
            WorldError::InvalidArgument { name, reason: format!("states[{k}]: {reason}") }
        }
        WorldError::Simulation(err) => {
            use tumble_integrate::OdeError::*;
            let t = match &err {
                NonFinite { t, .. } | Divergence { t, .. } | StepTooSmall { t, .. } | NewtonFailure { t, .. } => *t,
                SingularMatrix { t, .. } | LinearSolve { t, .. } | TooManySteps { t, .. } | System { t, .. } => *t,
                InvalidArgument { .. } | Unsupported { .. } => 0.0,
            };
            WorldError::Simulation(System { t, message: format!("copy {k} of the batch: {err}") })
        }
        other => other,
    }
}

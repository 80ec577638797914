//! Stepping a world: the engine built from the compiled model when the structure changed, and the one run loop
//! that every mode and both `step` and `run` go through: snapshot, advance in chunks (recording frames if asked,
//! reporting progress between chunks), book the report, and on failure restore the snapshot so the world is
//! exactly as it was.

use super::Pace;
use super::World;
use crate::control::Control;
use crate::engine::{Budget, Engine, EngineSpec};
use crate::error::WorldError;
use crate::limits;
use crate::model::Compiled;
use crate::model::ResolvedBody;
use crate::report::WorldReport;
use crate::run::Run;
use crate::spring::{BodyHandle, ParticleHandle};

/// Most frames a run may record.
const MAX_FRAMES: f64 = 1e7;
/// Most numbers a run may record (2 GB of frames).
const MAX_RECORDED: f64 = 2.5e8;

impl World {
    /// Drops the engine (the structure or a setting changed); its report is already in the totals.
    pub(crate) fn retire_engine(&mut self) {
        self.drop_engine();
        self.structure += 1;
    }

    /// Drops the engine and its memory, the structure unchanged: the next step starts afresh from the objects.
    pub(crate) fn drop_engine(&mut self) {
        self.engine = None;
        self.state_changed = false;
    }

    /// Whether the compiled world has colliders that can touch.
    pub(crate) fn has_contact(&self, compiled: &Compiled) -> bool {
        self.collider_set(compiled).is_some()
    }

    pub(crate) fn collider_set(&self, compiled: &Compiled) -> Option<crate::engine::collider_set::ColliderSet> {
        let mut collider_set = crate::engine::collider_set::ColliderSet::build(
            compiled.model.layout,
            &self.particles,
            &self.bodies,
            &compiled.handles.bodies,
            self.combine,
        )?;
        // bodies a joint joins directly do not collide with each other
        collider_set.set_joined(compiled.model.joined_pairs());
        Some(collider_set)
    }

    /// A new engine for the world as it is.
    fn build_engine(&self) -> Result<Box<dyn Engine>, WorldError> {
        let compiled = self.compile();
        let y = compiled.handles.pack(&self.particles, &self.bodies);
        // The divergence limit is relative to the state's own scale: its largest component, and the momenta that
        // gravity alone gives the bodies in a second (a kilometre-sized body's momentum is large from the start).
        let lift = 1.0 + self.gravity.norm();
        let momenta = compiled.model.bodies.iter().map(|b| (b.mass + b.inertia.amax()) * lift).fold(0.0f64, f64::max);
        let scale = y.iter().fold(1.0f64, |m, v| m.max(v.abs())).max(momenta);
        let spec = EngineSpec {
            mode: self.mode,
            settings: self.settings.clone().divergence_limit(self.divergence_factor * scale),
            collider_set: self.collider_set(&compiled),
            gravity: self.gravity.norm(),
            threads: self.threads,
        };
        crate::engine::build(spec, compiled, self.time, y)
    }

    /// The engine, built if the structure changed and given any state the user set.
    pub(crate) fn engine(&mut self) -> Result<&mut dyn Engine, WorldError> {
        let engine = match self.engine.take() {
            None => self.build_engine()?,
            Some(mut e) => {
                if self.state_changed {
                    let y = e.handles().pack(&self.particles, &self.bodies);
                    if let Err(err) = e.set_state(self.time, &y) {
                        self.engine = Some(e);
                        return Err(err);
                    }
                }
                e
            }
        };
        self.state_changed = false;
        Ok(self.engine.insert(engine).as_mut())
    }

    /// Moves the engine's report into the totals and returns it.
    fn book_report(&mut self) -> WorldReport {
        let r = match &mut self.engine {
            Some(e) => e.take_report(),
            None => WorldReport::new(self.settings.method.name()),
        };
        self.totals.merge(&r);
        r
    }

    /// Writes the engine's state into the particles and bodies.
    pub(crate) fn store_state(&mut self) {
        if let Some(e) = &self.engine {
            e.handles().unpack(e.state(), &mut self.particles, &mut self.bodies);
            for ((_, j), c) in self.joints.iter_mut().zip(&e.model().joints) {
                j.broken = c.broken;
            }
            self.time = e.time();
        }
    }

    /// Advances by `dt` (several internal steps if the method is adaptive; in fast mode a whole number of its
    /// steps, else an error naming `dt`). On error the world is unchanged.
    pub fn step(&mut self, dt: f64) -> Result<(), WorldError> {
        self.step_with(dt, |_| true)
    }

    /// [`step`](World::step), telling `control` the fraction done as the work goes (after each contact step,
    /// fast-mode step or stretch of integrator steps); when it answers false the call stops with
    /// [`WorldError::Interrupted`] and the world is as it was (a step records no frame to keep).
    pub fn step_with(&mut self, dt: f64, control: impl Control) -> Result<(), WorldError> {
        limits::positive("dt", dt, limits::TIME, "s")?;
        self.run_loop(dt, "dt", None, control).map(|_| ())
    }

    /// Runs for `duration`, recording a frame every `frame_interval` (and at the end).
    pub fn run(&mut self, duration: f64, frame_interval: f64) -> Result<Run, WorldError> {
        self.run_with(duration, frame_interval, |_| true)
    }

    /// [`run`](World::run), telling `control` the fraction done between chunks of about a hundredth of the frames
    /// and as the work goes within them (the fraction never goes back), and giving it the one line a slow accurate
    /// run says about fast mode ([`Control::hint`]). When it answers false the run stops with
    /// [`WorldError::Interrupted`]: the frames done are kept ([`take_failed_run`](World::take_failed_run) gives
    /// them, marked `interrupted`) and the world is at the last of them, so the next call carries on from there,
    /// unless the control says the stop keeps no work ([`Control::keeps_work`]). On any other error the world is as
    /// it was before the call. In fast mode `duration` must be a whole number of
    /// steps, and each frame is the state of the first step that reaches its time (frames closer than a step apart
    /// share it, and are recorded once).
    pub fn run_with(&mut self, duration: f64, frame_interval: f64, control: impl Control) -> Result<Run, WorldError> {
        limits::positive("duration", duration, limits::TIME, "s")?;
        limits::positive("frame_interval", frame_interval, limits::TIME, "s")?;
        let count = (duration / frame_interval * (1.0 + 1e-12)).floor();
        // Each frame holds 6 numbers a particle and 13 a body, plus energies and momenta.
        let per_frame = (6 * self.particles.len() + 13 * self.bodies.len() + 10) as f64;
        if count > MAX_FRAMES || (count + 1.0) * per_frame > MAX_RECORDED {
            return Err(WorldError::invalid(
                "frame_interval",
                format!(
                    "{count:e} frames of {per_frame} numbers are too many to record (at most {MAX_RECORDED:e} numbers)"
                ),
            ));
        }
        let run = self.run_loop(duration, "duration", Some(frame_interval), control)?;
        Ok(run.expect("frames were asked for"))
    }

    /// The run loop of every mode: advances by `span` (named `name` in errors), recording frames every
    /// `frame_interval` if given.
    fn run_loop(
        &mut self,
        span: f64,
        name: &'static str,
        frame_interval: Option<f64>,
        mut control: impl Control,
    ) -> Result<Option<Run>, WorldError> {
        self.failed_run = None;
        let mut run = frame_interval.map(|_| self.new_run());
        // what a failed call puts back: no engine if it built one, the state set since the last call if it gave one
        // (an engine's state is its own form of the world's, equal to it only to rounding)
        let (fresh, state_changed) = (self.engine.is_none(), self.state_changed);
        self.engine()?;
        // the engine is held apart for the call, so that the pace's fast-mode estimate can copy the world as the
        // call found it
        let mut engine = self.engine.take().expect("built above");
        let advanced = self.advance_engine(engine.as_mut(), span, name, frame_interval, &mut run, &mut control);
        self.engine = Some(engine);
        let outcome = match advanced {
            Ok((outcome, hinted)) => {
                self.hinted |= hinted;
                outcome
            }
            Err(err) => return Err(err),
        };
        let report = self.book_report();
        if let Err(err) = outcome {
            let kept = matches!(err, WorldError::Interrupted) && control.keeps_work();
            if fresh && !kept {
                self.engine = None;
            } else if let Some(e) = &mut self.engine {
                let t0 = e.time();
                e.rollback().map_err(|why| engine_fault(t0, why))?;
                self.state_changed = state_changed && !kept;
            }
            self.failed_run = run.map(|mut run| {
                run.report = report;
                if kept {
                    self.keep_to_last_frame(&mut run);
                }
                run
            });
            return Err(err);
        }
        self.store_state();
        self.stepped = true;
        Ok(run.map(|mut run| {
            run.report = report;
            run
        }))
    }

    /// Advances `e` (the world's engine, held apart) by `span`: the outcome of the chunks and whether the pace's
    /// line was given. An error before any step (a bad span) is the outer one, the engine untouched.
    #[allow(clippy::type_complexity)]
    fn advance_engine(
        &self,
        e: &mut dyn Engine,
        span: f64,
        name: &'static str,
        frame_interval: Option<f64>,
        run: &mut Option<Run>,
        control: &mut dyn Control,
    ) -> Result<(Result<(), WorldError>, bool), WorldError> {
        let t0 = e.time();
        let t_end = e.end_time(span, name)?;
        if !(t_end > t0 && t_end <= limits::TIME) {
            return Err(WorldError::invalid(
                name,
                format!(
                    "{span:e} s from t = {t0} ends at {t_end:e} s: time must advance and stay within {:e} s",
                    limits::TIME
                ),
            ));
        }
        let times = match frame_interval {
            Some(interval) => frame_times(t0, t_end, span, interval),
            None => Vec::new(),
        };
        e.checkpoint();
        // One step budget for the whole call, across its chunks (fast mode's calls are bounded by their step
        // count, checked above), carrying the call's control and watching its pace.
        let limit = if e.counts_its_steps() { usize::MAX } else { self.settings.max_steps };
        let mut budget = Budget::new(limit, t0, t_end).with_control(control).with_pace(Pace::new(self, span));
        // Pause about a hundred times to report progress; pausing does not shorten a step, so the run takes the
        // same steps as one call would.
        let chunk = times.len().div_ceil(100).max(1);
        let mut done = 0;
        // Engines count a time within this of their target as reached (an ulp or two of rounding in the steps
        // that land on it); so does this loop, or it would ask again forever.
        let slack = 1e-12 * t_end.abs().max(1.0);
        let clock = std::time::Instant::now();
        let outcome = loop {
            let pause = if times.is_empty() { t_end } else { times[(done + chunk).min(times.len()) - 1] };
            let before = e.time();
            match e.advance(t_end, pause, &times[done..], run.as_mut(), &mut budget) {
                Ok(0) if e.time() <= before && e.time() < t_end - slack => {
                    // An engine that neither moved nor delivered a frame would be asked again forever.
                    break Err(WorldError::Simulation(tumble_integrate::OdeError::System {
                        t: before,
                        message: format!("an advance to t = {t_end:e} made no progress (an engine fault)"),
                    }));
                }
                Ok(delivered) => done += delivered,
                Err(_) if budget.stopped => break Err(WorldError::Interrupted),
                Err(err) => break Err(err),
            }
            let finished = done >= times.len() && (!times.is_empty() || e.time() >= t_end - slack);
            let fraction = if times.is_empty() { budget.fraction(e.time()) } else { done as f64 / times.len() as f64 };
            if !budget.tell(fraction) {
                break Err(WorldError::Interrupted);
            }
            if finished {
                break Ok(());
            }
        };
        e.core_mut().report.wall_seconds += clock.elapsed().as_secs_f64();
        Ok((outcome, budget.hinted()))
    }

    /// The frames a run recorded before it failed (the world itself back where that run started) or was
    /// interrupted (the world at its last frame; the run marked `interrupted`), with the report of the steps it
    /// took; `None` once taken, or if the last run did not fail after recording.
    pub fn take_failed_run(&mut self) -> Option<Run> {
        self.failed_run.take()
    }

    /// An empty run of this world's particles and bodies (all bodies, static ones at their fixed poses).
    fn new_run(&self) -> Run {
        let c = self.compile();
        let sources: Vec<ResolvedBody> = self
            .bodies
            .iter()
            .map(|(h, b)| ResolvedBody::of(b, c.handles.bodies.iter().position(|&d| d == h)))
            .collect();
        let particles: Vec<ParticleHandle> = self.particles.iter().map(|(h, _)| h).collect();
        let bodies: Vec<BodyHandle> = self.bodies.iter().map(|(h, _)| h).collect();
        let mut run = Run::new(particles, bodies, sources, self.settings.method.name());
        run.joints = self.joints.iter().map(|(h, _)| h).collect();
        run
    }
}

/// An engine that cannot take back its own memory: a fault of the engine, said as a simulation error.
pub(crate) fn engine_fault(t: f64, why: String) -> WorldError {
    WorldError::Simulation(tumble_integrate::OdeError::System {
        t,
        message: format!("the engine could not take back its memory ({why}): an engine fault"),
    })
}

/// Frame times from t0 every `interval` over `span`, the last one at `t_end` (the end of the advance).
fn frame_times(t0: f64, t_end: f64, span: f64, interval: f64) -> Vec<f64> {
    let count = (span / interval * (1.0 + 1e-12)).floor() as usize;
    let mut times: Vec<f64> = (0..=count).map(|k| t0 + k as f64 * interval).filter(|&t| t < t_end).collect();
    match times.last_mut() {
        Some(last) if (t_end - *last).abs() <= 1e-9 * interval => *last = t_end,
        _ => times.push(t_end),
    }
    times
}

//! Accurate mode's advance with contact stages: the impact stage (unless a touching phase carries on from the last
//! call), then repeatedly contact steps while bodies touch, or the integrator to the next event (a joint that
//! breaks there let go of) and its impact stage; each event recorded, and a time that events cannot leave is an error.

use super::integration::within_budget;
use super::{breaking, clocks, detect, impact, mechanical_energy, touching, AccurateEngine, AccurateMemory, STUCK};
use crate::engine::budget::Budget;
use crate::engine::failure::failure;
use crate::engine::frames::FrameCursor;
use crate::error::WorldError;
use crate::run::Run;

impl AccurateEngine {
    /// Advances to `t_end` (pausing past `pause`) with the contact stages, recording frames with the penetration
    /// of the last impact stage and the events' times.
    pub(super) fn advance_with_contacts(
        &mut self,
        t_end: f64,
        pause: f64,
        saves: &[f64],
        mut run: Option<&mut Run>,
        budget: &mut Budget<'_>,
    ) -> Result<usize, WorldError> {
        let AccurateEngine { core, system, contacts, memory, .. } = self;
        let rules = contacts.as_mut().expect("the engine has contact stages");
        let AccurateMemory { integration, contact, broken, load_averages, .. } = memory;
        let (Some(integration), Some(contact)) = (integration.as_mut(), contact.as_mut()) else {
            return Err(failure(0.0, "contact stages without an integration".into()).into());
        };
        let energy = mechanical_energy(&system.model, contact.state_or(integration.live().state()));
        let integrator = integration.live_mut();
        let (threads, limit) = (core.threads, core.divergence_limit);
        let mut stages = rules.stages(contact, broken, load_averages, &mut core.report, threads, limit);
        integrator.log_steps(run.is_some());
        let result = (|| {
            // a touching phase carries on from the last call (so pausing, for frames or progress, changes nothing);
            // otherwise the contacts at the start are an event
            if stages.memory.touching.is_none() {
                impact::impact(&mut stages, system, integrator)?;
            }
            let (mut frames, mut stuck, mut last) = (FrameCursor::new(saves, t_end), 0, integrator.time());
            loop {
                if let Some(phase) = stages.memory.touching.as_mut() {
                    // the phase goes on from where it got to; the integrator's state is set only when it ends
                    let start = phase.at.take().unwrap_or_else(|| (integrator.time(), integrator.state().to_vec()));
                    let until = touching::Until { end: t_end, pause, own_clocks: Some(clocks::own_clocks) };
                    let end = touching::touching_steps(
                        &mut stages,
                        system,
                        start,
                        until,
                        &mut frames,
                        run.as_deref_mut(),
                        budget,
                    )?;
                    if end.touching {
                        if let Some(phase) = stages.memory.touching.as_mut() {
                            phase.at = Some((end.t, end.y));
                        }
                        return Ok(frames.delivered());
                    }
                    integrator.set_state(end.t, &end.y)?;
                    continue;
                }
                // The integrator's own budget restarts at every event: it gets what is left of the call's.
                let penetration = stages.memory.penetration;
                let adv = within_budget(integrator, budget, None, |integrator| {
                    // the resting contacts are lent to the equations of motion for the integration
                    system.resting = stages.memory.resting.take();
                    let adv = integrator.advance_with_events(
                        system,
                        t_end,
                        pause,
                        frames.rest(),
                        |m, t, y| {
                            if let Some(run) = run.as_deref_mut() {
                                run.record(&m.model, t, y, penetration, []);
                            }
                        },
                        |step| detect::detect(&mut stages, step),
                    );
                    stages.memory.resting = system.resting.take();
                    if let Some(run) = run.as_deref_mut() {
                        for (t, h) in integrator.take_step_log() {
                            run.log_step(t, h);
                        }
                    }
                    adv
                })?;
                frames.skip(adv.delivered);
                let Some(t) = adv.event else { return Ok(frames.delivered()) };
                if let Some(run) = run.as_deref_mut() {
                    run.contact_events.push(t);
                }
                stuck = if t > last { 0 } else { stuck + 1 };
                last = t;
                if stuck > STUCK {
                    return Err(failure(t, format!("{STUCK} contact events at one time: the contacts do not settle")));
                }
                // a joint that broke is let go of, and the integration restarts on the new equations
                let y = integrator.state().to_vec();
                let broke = breaking::break_overloaded(
                    system,
                    stages.broken,
                    stages.averages,
                    Some(&mut *stages.collider_set),
                    t,
                    &y,
                )?;
                if !broke.is_empty() {
                    integrator.set_state(t, &y)?;
                }
                if let Some(run) = run.as_deref_mut() {
                    broke.iter().for_each(|&k| run.break_joint(t, k));
                }
                impact::impact(&mut stages, system, integrator)?;
            }
        })();
        let end = stages.memory.state_or(integrator.state());
        stages.report.energy_change += mechanical_energy(&system.model, end) - energy;
        Ok(result?)
    }
}

//! Fast mode, third stage: the new velocities. With contacts, one conic program per island (tumble-contact), with
//! friction lagged on each contact's previous normal impulse (`warm_start.rs`; islands where a pair has just met
//! get a first pass for one) or Anitescu's cone; islands whose bounce would gain energy are solved again with less
//! restitution (`bounce_limiter.rs`). Without contacts, the free velocities.

use super::bounce_limiter::limit_bounce_energy;
use super::context::StepContext;
use super::solver::Solver;
use super::warm_start::known_impulses;
use crate::engine::failure::failure;
use crate::engine::found_contact::FoundContact;
use crate::engine::last_contacts::LastContact;
use crate::error::WorldError;
use crate::mode::{FastFriction, FastSolver};
use crate::plan::Stage;
use std::time::Instant;
use tumble_contact::{free_velocity, islands, BodyState, BodyVelocity, Contact, StepSettings};

/// The velocities after step h of the actors `states` with contacts `found`; remembers the normal impulses.
pub(super) fn solve_velocities(
    cx: &mut StepContext<'_>,
    states: &[BodyState],
    found: &[FoundContact],
    h: f64,
) -> Result<Vec<BodyVelocity>, WorldError> {
    if found.is_empty() {
        cx.memory.previous.clear();
        let free = StepSettings::new(h);
        return Ok(states.iter().map(|b| free_velocity(b, &free)).collect());
    }
    let clock = Instant::now();
    let contacts: Vec<Contact> = found.iter().map(|f| f.contact).collect();
    let FastSolver::Exact { erp, friction } = cx.settings.solver else {
        return Err(failure(cx.t, "the exact solver's stage without the exact solver".into()).into());
    };
    let mut settings = StepSettings {
        erp,
        bounce_threshold: cx.settings.bounce_threshold,
        threads: cx.threads,
        ..StepSettings::new(h)
    };
    settings.solver.iterative_refinement = false;
    let mut solver = Solver { states, settings, friction, t: cx.t, solves: 0 };
    let known = known_impulses(&cx.memory.previous, found);
    let mut previous: Vec<f64> = known.iter().map(|p| p.unwrap_or(0.0)).collect();
    let groups = islands(states, &contacts);
    if solver.friction == FastFriction::Lagged && known.iter().any(|p| p.is_none()) {
        let fresh: Vec<usize> =
            groups.iter().filter(|g| g.iter().any(|&i| known[i].is_none())).flatten().copied().collect();
        let sub: Vec<Contact> = fresh.iter().map(|&i| contacts[i]).collect();
        let sub_prev: Vec<f64> = fresh.iter().map(|&i| previous[i]).collect();
        let first = solver.solve(&sub, &sub_prev)?;
        for (&i, p) in fresh.iter().zip(&first.normal_impulses) {
            if known[i].is_none() {
                previous[i] = *p;
            }
        }
    }
    let mut out = solver.solve(&contacts, &previous)?;
    let gravity = cx.model.gravity;
    limit_bounce_energy(&mut solver, &contacts, &previous, &groups, gravity, &mut out)?;
    cx.report.islands += groups.len();
    cx.report.qp_solves += solver.solves;
    cx.report.stages.mark(Stage::ContactConeProgram);
    count_impulses(cx, states, &contacts, &out.normal_impulses);
    cx.memory.previous = found.iter().zip(&out.normal_impulses).map(|(f, &p)| (f.key, p)).collect();
    cx.memory.last_contacts = LastContact::from_found(found, out.normal_impulses.iter().copied(), h);
    cx.report.contact_seconds += clock.elapsed().as_secs_f64();
    Ok(out.velocities)
}

/// Books the contacts that pushed (a positive normal impulse) and, of those, the ones that closed faster than the
/// bounce threshold (collisions).
pub(super) fn count_impulses(cx: &mut StepContext<'_>, states: &[BodyState], contacts: &[Contact], impulses: &[f64]) {
    for (c, p) in contacts.iter().zip(impulses) {
        if *p > 0.0 {
            cx.report.impulses += 1;
            if c.relative_normal_velocity(states) < -cx.settings.bounce_threshold {
                cx.report.collisions += 1;
            }
        }
    }
}

//! One convex contact step of accurate mode: semi-implicit Euler in the velocities with every contact and its Coulomb
//! friction as one convex program per island (tumble-contact's velocity step), so a step always has an answer.
//! Contacts are speculative (pairs within the distance they can close in the step take part, with their gap as a
//! bound), so nothing passes through and new contacts stop at their gap. Friction is lagged: each contact's
//! friction impulse is bounded by mu times a normal impulse, and the step iterates that bound to its own normal
//! impulse (a fixed point to `ContactScales::lagged_tolerance`, at most `LAGGED_ITERATIONS` solves), so sliding
//! decelerates at mu g without the convex cone's hop and the answer does not depend on the previous step's forces
//! beyond the first guess.

use super::contact_stages::ContactStages;
use super::joint_forces::{bilateral_rows, project_joints, BilateralRows, JOINT_DRIFT};
use super::system::AccurateSystem;
use crate::engine::bounce_scale::{body_kinetic, largest_keeping_energy, moving_bodies};
use crate::engine::contact_reduction::reduce;
use crate::engine::failure::failure;
use crate::engine::found_contact::{ContactKey, FoundContact};
use crate::engine::semi_implicit::{update_positions, Form};
use crate::model::breaking::JointLoad;
use crate::model::{actor_poses, Model};
use crate::plan::Stage;
use nalgebra::Vector3;
use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;
use std::time::Instant;
use tumble_contact::{free_velocity, velocity_step, BodyState, Contact, ContactError, StepSettings, VelocityProblem};
use tumble_integrate::OdeError;

/// Most solves of one step's lagged-friction fixed point.
const LAGGED_ITERATIONS: usize = 3;
/// The programs' velocities are answered to this share of tol / h, a position error of this share of the tolerance
/// over the step: clarabel's answers are checked to it and the Newton method's multiplier iteration stops there
/// (`StepSettings::velocity_scale` times the solver's `complementarity_tolerance`). Measured: the 20-cube pile's 3 s
/// at the defaults took 5.5 s answered to 1e-10 of the island's speeds, 3.1 s at 1e-5 and 2.8 s at 1e-4; at 1e-4
/// the energy of bouncing and resting bodies rose by 2e-9 of its start between frames (the contact impulses
/// working on the closing speeds left), at 1e-5 by 2e-11.
pub(crate) const ANSWER_SHARE: f64 = 1e-5;

/// What one convex step gives.
pub(crate) struct ConvexStep {
    /// The state after the step.
    pub y: Vec<f64>,
    /// Each contact's normal force over the step (impulse / h), by key.
    pub forces: BTreeMap<ContactKey, f64>,
    /// The pairs of actors that pushed (a positive normal impulse at one of their contacts), in order: pairs, not
    /// points, since how a pair's redundant points (a box's four corners) share its push is not fixed by the
    /// program and may change from solve to solve.
    pub pressing: BTreeSet<(usize, usize)>,
    /// Each contact's whole force over the step (impulse / h, normal and friction, on B), by key: where the next
    /// solves start from.
    pub wrenches: BTreeMap<ContactKey, Vector3<f64>>,
    /// Each joint's load over the step (its rows' impulses / h; none without joints).
    pub joint_loads: Vec<JointLoad>,
    /// For the second of a step's two halves, the first half's `joint_loads` (`doubled_step`); empty otherwise.
    pub first_half_loads: Vec<JointLoad>,
}

/// The actors at state y with the applied forces of the equations of motion, and the forces' finiteness checked.
pub(crate) fn actors_with_forces(
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    t: f64,
    y: &[f64],
) -> Result<Vec<BodyState>, OdeError> {
    let mut dy = vec![0.0; y.len()];
    let kin = system.rates(t, y, &mut dy).map_err(|e| failure(t, e.to_string()))?;
    system.model.step_actors(&kin, t, y, &dy, statics, &[])
}

/// The contacts a step of h from state y may meet: pairs within the distance they can close in h (speed times h,
/// plus what the applied forces add, plus the contact distance), at most four points a pair and plane; and every
/// contact found before that reduction: the points a step does not hold (a rolling hull's vertex coming round, a
/// piece's corner) but whose sinking its error must see.
pub fn every_contact_in_reach(
    cx: &mut ContactStages<'_>,
    model: &Model,
    states: &[BodyState],
    y: &[f64],
    t: f64,
    h: f64,
) -> Result<(Vec<FoundContact>, Vec<FoundContact>), OdeError> {
    let clock = Instant::now();
    let statics = Arc::clone(&cx.collider_set.static_poses);
    let poses = actor_poses(model.layout, y, &statics);
    let mut reach = cx.collider_set.reach(states, h);
    for (r, s) in reach.iter_mut().zip(states) {
        *r += s.force.norm() * s.inv_mass * h * h;
    }
    let checks = cx.collider_set.checks;
    let every = cx.collider_set.find(&poses, &reach, cx.settings.contact_distance).map_err(|e| failure(t, e))?;
    let moving = |f: &FoundContact| states[f.contact.a].is_dynamic() || states[f.contact.b].is_dynamic();
    let found: Vec<FoundContact> = reduce(every.clone(), states).into_iter().filter(moving).collect();
    let every: Vec<FoundContact> = every.into_iter().filter(moving).collect();
    cx.report.collision_checks += cx.collider_set.checks - checks;
    cx.report.stages.mark(Stage::CollisionDetection);
    cx.report.collision_seconds += clock.elapsed().as_secs_f64();
    Ok((found, every))
}

/// One step of h from (t, y) with the actors `states` (from `actors_with_forces` at y) and the contacts
/// `found`; `lagged` holds normal forces the friction bound starts from (contacts without one get a
/// frictionless first pass), `warm` the forces the solves start from (a step's or its halves', by key). `None`
/// when no solver could answer to its tolerance (the caller tries a smaller step; the reason is kept in
/// `last_solver_error`).
#[allow(clippy::too_many_arguments)]
pub fn convex_step(
    cx: &mut ContactStages<'_>,
    model: &Model,
    states: &[BodyState],
    found: &[FoundContact],
    (lagged, warm): (&BTreeMap<ContactKey, f64>, &BTreeMap<ContactKey, Vector3<f64>>),
    t: f64,
    y: &[f64],
    h: f64,
) -> Result<Option<ConvexStep>, OdeError> {
    let mut next = y.to_vec();
    if found.is_empty() && model.joints.is_empty() {
        let free = StepSettings::new(h);
        let v: Vec<_> = states.iter().map(|b| free_velocity(b, &free)).collect();
        update_positions(model, &mut next, &v, h, Form::Momenta, |_| true);
        return Ok(Some(ConvexStep {
            y: next,
            forces: BTreeMap::new(),
            pressing: BTreeSet::new(),
            wrenches: BTreeMap::new(),
            joint_loads: Vec::new(),
            first_half_loads: Vec::new(),
        }));
    }
    let clock = Instant::now();
    let contacts: Vec<Contact> = found.iter().map(|f| f.contact).collect();
    // No Baumgarte push-out: its velocity (erp d / h) stays after the step and at small steps is large (0.2 m/s
    // for a micrometre at h = 1e-6 s), a gain of energy. Penetration comes only from linearising a turning
    // contact over one step, which the error control keeps within the tolerance.
    let mut settings = StepSettings {
        erp: 0.0,
        bounce_threshold: cx.memory.scales.resting_speed,
        threads: cx.threads,
        ..StepSettings::new(h)
    };
    // Answers are judged against the velocity that moves a body by the tolerance in the step (at least): a body
    // nearly at rest judged against g h alone made clarabel's retries fail at h = 1e-6 s.
    settings.velocity_scale = cx.memory.scales.tolerance / h;
    settings.solver = tumble_contact::SolverSettings { complementarity_tolerance: ANSWER_SHARE, ..*cx.solver };
    settings.method = match cx.settings.solver {
        crate::mode::AccurateSolver::Newton => tumble_contact::StepMethod::Newton,
        crate::mode::AccurateSolver::Clarabel => tumble_contact::StepMethod::Clarabel,
    };
    // joints: their rows held exactly in the same programs, fixed ends as extra fixed actors
    let BilateralRows { rows: bilateral, extra, owners } = bilateral_rows(model, y, h, states.len());
    let with_extra: Vec<BodyState>;
    let states = if extra.is_empty() {
        states
    } else {
        with_extra = states.iter().copied().chain(extra).collect();
        &with_extra[..]
    };
    let ask = Asked { states, bilateral: &bilateral, settings: &settings, found, lagged, warm, t };
    let mut tally = Tally::default();
    let Some(mut out) = lagged_answer(cx, &ask, &contacts, &mut tally)? else { return Ok(None) };
    // A bounce may put energy in (Newton's law with friction on a turning body, Kane's paradox; several corners at
    // once): its restitution is then scaled back to the largest share that keeps the energy.
    let threshold = settings.bounce_threshold;
    if contacts.iter().any(|c| c.restitution > 0.0 && c.relative_normal_velocity(states) < -threshold) {
        let members = moving_bodies(states, &contacts);
        let energy = |v: &[tumble_contact::BodyVelocity], dt: f64| step_energy(states, &members, v, dt);
        let start: Vec<_> = states
            .iter()
            .map(|b| tumble_contact::BodyVelocity { linear: b.velocity, angular: b.angular_velocity })
            .collect();
        let e0 = energy(&start, 0.0);
        // (1e-9 of it for the answers' accuracy and rounding: their allowance, `ANSWER_SHARE` of tol / h on the
        // velocities, times a bounce's impulse grows without bound as the steps shrink at an impact, and let a
        // bounce in a step of 4e-8 s gain 1e-3 J)
        let limit = e0 + 1e-9 * e0.abs();
        let full = energy(&out.velocities, h);
        if full > limit {
            let solve = |scale: f64| {
                let scaled: Vec<Contact> =
                    contacts.iter().map(|c| Contact { restitution: c.restitution * scale, ..*c }).collect();
                lagged_answer(cx, &ask, &scaled, &mut tally)
            };
            let kept = largest_keeping_energy(full, limit, solve, |o: &tumble_contact::VelocityStep| {
                energy(&o.velocities, h)
            })?;
            let Some(kept) = kept else { return Ok(None) };
            out = kept;
        }
    }
    let Tally { solves, work, building } = tally;
    cx.report.qp_solves += solves;
    cx.report.program_seconds += building;
    cx.report.islands += out.islands;
    *cx.solve_work += work;
    cx.report.stages.add(Stage::ContactConeProgram, solves.max(1));
    update_positions(model, &mut next, &out.velocities, h, Form::Momenta, |_| true);
    project_joints(model, &mut next, JOINT_DRIFT);
    let forces = found.iter().zip(&out.normal_impulses).map(|(f, p)| (f.key, p / h)).collect();
    let wrenches = found.iter().zip(impulse_vectors(&contacts, &out)).map(|(f, p)| (f.key, p / h)).collect();
    let pressing = found
        .iter()
        .zip(&out.normal_impulses)
        .filter(|(_, p)| **p > 0.0)
        .map(|(f, _)| (f.contact.a, f.contact.b))
        .collect();
    let mut joint_loads = vec![JointLoad::default(); if owners.is_empty() { 0 } else { model.joints.len() }];
    for ((r, (k, rb)), p) in bilateral.iter().zip(&owners).zip(&out.joint_impulses) {
        joint_loads[*k].add(&r.lin, &r.ang_b, rb, p / h);
    }
    cx.report.contact_seconds += clock.elapsed().as_secs_f64();
    Ok(Some(ConvexStep { y: next, forces, pressing, wrenches, joint_loads, first_half_loads: Vec::new() }))
}

/// What a step asks its programs (`lagged_answer`).
struct Asked<'a> {
    states: &'a [BodyState],
    bilateral: &'a [tumble_contact::BilateralRow],
    settings: &'a StepSettings,
    found: &'a [FoundContact],
    lagged: &'a BTreeMap<ContactKey, f64>,
    warm: &'a BTreeMap<ContactKey, Vector3<f64>>,
    t: f64,
}

/// The solves, their work units and their programs' building time, over every answer a step asked for.
#[derive(Default)]
struct Tally {
    solves: usize,
    work: usize,
    building: f64,
}

/// The answer of the step's programs with `contacts` (the asked ones, or with their restitution scaled), friction
/// lagged to its fixed point: each contact's friction bounded by mu times a normal impulse (the last step's force
/// times h to start), iterated to the answer's own normal impulses, judged pair by pair, until no pair's moved by
/// more than `lagged_tolerance` of the largest or `LAGGED_ITERATIONS` solves. `None` if a program had no answer.
fn lagged_answer(
    cx: &mut ContactStages<'_>,
    ask: &Asked<'_>,
    contacts: &[Contact],
    tally: &mut Tally,
) -> Result<Option<tumble_contact::VelocityStep>, OdeError> {
    let h = ask.settings.dt;
    let mut solve = |bounds: &[f64], start: &[Vector3<f64>], tally: &mut Tally| {
        let problem = VelocityProblem::new(ask.states, contacts).lagged(bounds).bilateral(ask.bilateral).warm(start);
        match velocity_step(&problem, ask.settings) {
            Ok(out) => {
                tally.solves += out.solver_calls;
                tally.work += out.solver_work;
                tally.building += out.building_seconds;
                Ok(Some(out))
            }
            Err(ContactError::InvalidArgument { name, reason }) => {
                Err(failure(ask.t, format!("contact step: invalid {name}: {reason}")))
            }
            Err(e) => {
                *cx.last_solver_error = e.to_string();
                Ok(None)
            }
        }
    };
    let mut bounds: Vec<f64> = ask.found.iter().map(|f| ask.lagged.get(&f.key).map_or(0.0, |p| p * h)).collect();
    let mut start: Vec<Vector3<f64>> = ask
        .found
        .iter()
        .zip(&bounds)
        .map(|(f, b)| ask.warm.get(&f.key).map_or(f.contact.normal.into_inner() * *b, |force| force * h))
        .collect();
    let Some(mut out) = solve(&bounds, &start, tally)? else { return Ok(None) };
    for _ in 1..LAGGED_ITERATIONS {
        // judged pair by pair: how a pair's redundant points (a box's four corners) share its push is not fixed by
        // the program and may wander from solve to solve, while their sum is
        let mut pairs: BTreeMap<(usize, usize), (f64, f64)> = BTreeMap::new();
        for ((c, b), p) in contacts.iter().zip(&bounds).zip(&out.normal_impulses) {
            let e = pairs.entry((c.a, c.b)).or_default();
            e.0 += b;
            e.1 += p;
        }
        let largest = pairs.values().fold(0.0f64, |m, (_, p)| m.max(*p));
        let moved = pairs.values().fold(0.0f64, |m, (b, p)| m.max((b - p).abs()));
        let frictional = contacts.iter().any(|c| c.friction > 0.0);
        if !frictional || moved <= cx.memory.scales.lagged_tolerance * largest {
            break;
        }
        bounds.clone_from(&out.normal_impulses);
        start = impulse_vectors(contacts, &out);
        let Some(next) = solve(&bounds, &start, tally)? else { return Ok(None) };
        out = next;
    }
    Ok(Some(out))
}

/// The mechanical energy of the bodies `members` after a step of `dt` at velocities v, counted from the step's
/// start: their kinetic energy less the work their applied forces would do over the step's displacement (gravity's
/// potential energy, for gravity).
fn step_energy(states: &[BodyState], members: &[usize], v: &[tumble_contact::BodyVelocity], dt: f64) -> f64 {
    members.iter().map(|&k| body_kinetic(&states[k], &v[k]) - states[k].force.dot(&(v[k].linear * dt))).sum()
}

/// Each contact's whole impulse (normal and friction, on B) of a velocity step.
fn impulse_vectors(contacts: &[Contact], out: &tumble_contact::VelocityStep) -> Vec<Vector3<f64>> {
    contacts
        .iter()
        .zip(out.normal_impulses.iter().zip(&out.friction_impulses))
        .map(|(c, (p, f))| c.normal.into_inner() * *p + f)
        .collect()
}

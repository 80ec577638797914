//! Fast mode, third stage with the soft solver: new velocities and poses from Catto's soft step (tumble-contact's
//! `soft_step`: substeps, soft contacts in hertz, Coulomb friction), each contact started from its impulses of the
//! last step (matched by feature key; a contact new to a pair that touched takes the pair's mean), and the
//! impulses kept for the next step. The substeps move the bodies themselves, so this stage also gives the poses.
//! Joints, springs and the particles' anchor pulls go in as the soft step's links: the springs are evaluated at
//! every substep (as forces evaluated once a step and spread over the substeps they were not symplectic: an
//! undamped spring gained energy at any step, and the cloth drape diverged).

use super::failure;
use super::solve_velocities::count_impulses;
use super::step::StepContext;
use crate::engine::found_contact::{pair_runs, ContactKey, FoundContact};
use crate::engine::last_contacts::LastContact;
use crate::error::WorldError;
use crate::mode::SoftSolver;
use crate::model::joints::JointEnd;
use crate::model::End;
use crate::plan::Stage;
use nalgebra::{Point3, Vector3};
use std::time::Instant;
use tumble_contact::{
    soft_step, BodyState, Contact, Joint, SoftImpulse, SoftProblem, SoftSettings, SoftSpring, SoftStep, SpringLaw,
};

/// Each contact's impulses from the last step: its own if it was there, else its pair's mean, else none.
/// `previous` is sorted by key (so a pair's contacts are neighbours, summed in key order).
fn warm_impulses(previous: &[(ContactKey, SoftImpulse)], found: &[FoundContact]) -> Vec<SoftImpulse> {
    found
        .iter()
        .map(|f| match previous.binary_search_by(|(k, _)| k.cmp(&f.key)) {
            Ok(k) => previous[k].1,
            Err(_) => {
                let start = previous.partition_point(|(k, _)| k.colliders < f.key.colliders);
                let pair = previous[start..].iter().take_while(|(k, _)| k.colliders == f.key.colliders);
                let (mut sum, mut n) = (SoftImpulse::default(), 0usize);
                for (_, p) in pair {
                    sum.normal += p.normal;
                    sum.tangent += p.tangent;
                    n += 1;
                }
                if n == 0 {
                    SoftImpulse::default()
                } else {
                    SoftImpulse { normal: sum.normal / n as f64, tangent: sum.tangent / n as f64 }
                }
            }
        })
        .collect()
}

/// The step's impulses by contact key, sorted (a key found twice keeps its last impulse).
fn by_key(found: &[FoundContact], impulses: &[SoftImpulse]) -> Vec<(ContactKey, SoftImpulse)> {
    let mut out: Vec<(ContactKey, SoftImpulse)> = found.iter().map(|f| f.key).zip(impulses.iter().copied()).collect();
    match pair_runs(&out, |e| e.0.colliders) {
        // pairs already in order (the scene gives them so): sort each pair's few contacts in place (stably)
        Some(runs) => runs.into_iter().for_each(|r| out[r].sort_by_key(|e| e.0)),
        None => out.sort_by_key(|e| e.0),
    }
    // keep the last of equal keys, as a map built in contact order would
    let mut kept: Vec<(ContactKey, SoftImpulse)> = Vec::with_capacity(out.len());
    for entry in out {
        match kept.last_mut() {
            Some(last) if last.0 == entry.0 => *last = entry,
            _ => kept.push(entry),
        }
    }
    kept
}

/// The soft step of h for the actors `states` with contacts `found`.
pub(super) fn soft_solve(
    cx: &mut StepContext<'_>,
    states: &[BodyState],
    found: &[FoundContact],
    h: f64,
    soft: SoftSolver,
) -> Result<SoftStep, WorldError> {
    let clock = Instant::now();
    let contacts: Vec<Contact> = found.iter().map(|f| f.contact).collect();
    let warm = warm_impulses(&cx.memory.warm, found);
    let settings = SoftSettings {
        substeps: soft.substeps,
        iterations: soft.iterations,
        contact_hertz: soft.contact_hertz,
        damping_ratio: soft.damping_ratio,
        max_push_out: soft.max_push_out,
        bounce_threshold: cx.settings.bounce_threshold,
        threads: cx.threads,
        ..SoftSettings::default()
    };
    let (actors, joints, springs) = links_at_start(cx, states);
    let actors = actors.as_deref().unwrap_or(states);
    let problem = SoftProblem::new(actors, &contacts, &warm).joints(&joints, &cx.memory.joint_warm).springs(&springs);
    let out = soft_step(&problem, h, &settings).map_err(|e| failure(cx.t, format!("contact solve: {e}")))?;
    cx.model.counters.spring_evaluations += springs.len() * settings.substeps;
    cx.memory.joint_warm.clone_from(&out.joint_impulses);
    if !joints.is_empty() {
        cx.report.stages.mark(Stage::Joints);
    }
    cx.memory.warm = by_key(found, &out.impulses);
    cx.memory.last_contacts = LastContact::from_found(found, out.normal_impulses.iter().copied(), h);
    if !found.is_empty() {
        cx.report.contact_residual = cx.report.contact_residual.max(out.residual);
        cx.report.islands += out.islands;
        cx.report.stages.mark(Stage::ContactSoftStep);
        count_impulses(cx, states, &contacts, &out.normal_impulses);
    }
    cx.report.contact_seconds += clock.elapsed().as_secs_f64();
    Ok(out)
}

/// The joints and springs where the bodies are at the step's start, for the soft step.
pub(super) type Links = (Option<Vec<BodyState>>, Vec<Joint>, Vec<SoftSpring>);

/// The joints, springs and anchor pulls where the bodies are at the step's start, for the soft step: a dynamic
/// end is its actor, a fixed end (the world, a static body, a fixed point, a particle's anchor) an extra fixed
/// actor at its pose, appended to the actors (returned when any). Springs that move nothing (both ends fixed or
/// asleep, or both on one body) are left out; the body kinematics are those of `applied_forces` (the step's
/// start).
pub(super) fn links_at_start(cx: &StepContext<'_>, states: &[BodyState]) -> Links {
    let model = &cx.model;
    let anchored = model.particles.iter().any(|p| p.stiffness != 0.0);
    if model.joints.is_empty() && model.springs.is_empty() && !anchored {
        return (None, Vec::new(), Vec::new());
    }
    let mut actors = states.to_vec();
    let l = model.layout;
    let mut fixed = |p: Point3<f64>| {
        actors.push(BodyState::fixed(p));
        actors.len() - 1
    };
    let mut joints = Vec::with_capacity(model.joints.len());
    for cj in &model.joints {
        let (ea, eb) = (model.end_state_of(&cx.memory.y, cj.a), model.end_state_of(&cx.memory.y, cj.b));
        let mut index = |end: JointEnd| match end {
            JointEnd::Body(j) => l.particles + j,
            JointEnd::Fixed(p) => fixed(Point3::from(p.translation.vector)),
        };
        let (a, b) = (index(cj.a), index(cj.b));
        joints.push(Joint { a, b, frame: cj.frame(&ea, &eb), ..cj.joint });
    }
    let actor = |end: End| match end {
        End::Particle(i) => Some(i),
        End::Body(j, _) => Some(l.particles + j),
        End::Point(_) => None,
    };
    let mut springs = Vec::with_capacity(model.springs.len());
    for s in &model.springs {
        let (a, b) = (actor(s.a), actor(s.b));
        let moves = |x: Option<usize>| x.is_some_and(|x| states[x].is_dynamic());
        if !(moves(a) || moves(b)) || (a.is_some() && a == b) {
            continue;
        }
        let mut place = |end: End| match end {
            End::Particle(i) => (i, Vector3::zeros()),
            End::Body(j, local) => (l.particles + j, model.kin[j].rot * local),
            End::Point(p) => (fixed(Point3::from(p)), Vector3::zeros()),
        };
        let ((a, ra), (b, rb)) = (place(s.a), place(s.b));
        springs.push(SoftSpring { a, b, ra, rb, law: s.law });
    }
    for (i, p) in model.particles.iter().enumerate() {
        if p.stiffness != 0.0 && states[i].is_dynamic() {
            let b = fixed(Point3::from(p.anchor));
            let zero = Vector3::zeros();
            let law = SpringLaw { stiffness: p.stiffness, damping: 0.0, rest_length: 0.0 };
            springs.push(SoftSpring { a: i, b, ra: zero, rb: zero, law });
        }
    }
    (Some(actors), joints, springs)
}

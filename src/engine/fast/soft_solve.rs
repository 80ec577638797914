//! Fast mode, third stage with the soft solver: new velocities and poses from Catto's soft step (tumble-contact's
//! `soft_solve`: substeps, soft contacts in hertz, Coulomb friction) over the contacts the engine keeps by collider
//! pair (`contact_pairs/`), each started from its impulses of the last step (matched by features; a contact new
//! to a pair that touched takes the pair's mean), its impulses kept in it for the next step. The substeps move the
//! bodies themselves, so this stage also gives the poses.
//! Joints, springs and the particles' anchor pulls go in as the soft step's links: the springs are evaluated at
//! every substep (as forces evaluated once a step and spread over the substeps they were not symplectic: an
//! undamped spring gained energy at any step, and the cloth drape diverged).

use super::context::StepContext;
use super::glued::{Balance, Glued, WeldLoads};
use crate::engine::failure::failure;
use crate::error::WorldError;
use crate::mode::SoftSolver;
use crate::model::ResolvedAttachment;
use crate::model::ResolvedBody;
use crate::plan::Stage;
use nalgebra::{Point3, Vector3};
use std::collections::BTreeMap;
use std::time::Instant;
use tumble_contact::{
    soft_solve as soft_solve_manifolds, BodyState, JointConstraint, JointImpulse, SoftLinks, SoftSettings, SoftSpring,
    SoftStep, SpringLaw,
};

/// What the soft step gives fast mode: its answer (each glued piece given its object's motion), the holding
/// joints it solved as rows (in the order of its joint impulses), each glued weld's impulse over the step, weighed
/// as a joint's, and for the welds of a struck object the same with the blow at its full weight (`glued.rs`).
pub(super) struct Solved {
    pub out: SoftStep,
    pub rows: Vec<usize>,
    pub glued: WeldLoads,
    pub glued_peaks: WeldLoads,
}

/// The soft step of h for the actors `states` with the contacts the engine keeps (`contact_pairs/`), their
/// impulses kept in them for the next step; glued objects solved as one body each (`glued.rs`).
pub(super) fn soft_solve(
    cx: &mut StepContext<'_>,
    states: &[BodyState],
    h: f64,
    soft: SoftSolver,
) -> Result<Solved, WorldError> {
    let clock = Instant::now();
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
    let (actors, mut joints, springs) = links_at_start(cx, states);
    let mut actors = actors.unwrap_or_else(|| states.to_vec());
    // the holding joints (a broken one is left out; a glued object's welds are its compound's), each started from
    // its last impulses
    let mut holding: Vec<usize> = cx.model.holding_joints().map(|(k, _)| k).collect();
    let glued = Glued::find(cx.model, states);
    let mut first = actors.len();
    if let Some(g) = &glued {
        // (links_at_start gives a joint a holding joint, in their order)
        let rows: Vec<bool> = holding.iter().map(|&k| !g.solves(cx.model, k)).collect();
        let mut kept = rows.iter();
        joints.retain(|_| *kept.next().expect("a flag a joint"));
        for (&k, _) in holding.iter().zip(&rows).filter(|(_, &row)| !row) {
            cx.memory.joint_warm[k] = JointImpulse::default();
        }
        holding = holding.iter().zip(&rows).filter(|(_, &row)| row).map(|(&k, _)| k).collect();
        first = g.actors(&mut actors);
    }
    let joint_warm: Vec<JointImpulse> = holding.iter().map(|&k| cx.memory.joint_warm[k]).collect();
    // each holding joint's break window: its impulses over the step weighed substep by substep
    let windows: Vec<f64> = holding.iter().map(|&k| cx.model.joints[k].breaking.map_or(0.0, |b| b.window)).collect();
    let mut manifolds = cx.memory.pairs.as_mut().map_or_else(Vec::new, |kept| kept.manifolds(states));
    let touching = !manifolds.is_empty();
    let remapped = glued.as_ref().map(|g| g.remap(&mut manifolds, first, &actors));
    let manifold_windows = remapped.as_ref().map_or(&[][..], |r| &r.windows[..]);
    let links =
        SoftLinks { joints: &joints, joint_warm: &joint_warm, springs: &springs, windows: &windows, manifold_windows };
    let solved = soft_solve_manifolds(&actors, &mut manifolds, &links, h, &settings);
    if let Some(r) = &remapped {
        Glued::restore(&mut manifolds, r);
    }
    drop(manifolds);
    let mut out = solved.map_err(|e| failure(cx.t, format!("contact solve: {e}")))?;
    let (mut loads, mut peaks) = (BTreeMap::new(), BTreeMap::new());
    if let (Some(g), Some(remapped)) = (&glued, &remapped) {
        let balance = Balance { states, out: &out, first, remapped, h, substeps: settings.substeps };
        (loads, peaks) = g.loads(cx.model, &cx.memory.y, &balance);
        g.spread(&mut out, states, first);
    }
    cx.tally.forces.spring_evaluations += springs.len() * settings.substeps;
    for (&k, impulse) in holding.iter().zip(&out.joint_impulses) {
        cx.memory.joint_warm[k] = *impulse;
    }
    if !joints.is_empty() {
        cx.report.stages.mark(Stage::Joints);
    }
    if touching {
        cx.report.contact_residual = cx.report.contact_residual.max(out.residual);
        cx.report.islands += out.islands;
        cx.report.program_seconds += out.prepare_seconds;
        cx.report.stages.mark(Stage::ContactSoftStep);
        cx.report.impulses += out.pushing;
        cx.report.collisions += out.collisions;
    }
    cx.report.contact_seconds += clock.elapsed().as_secs_f64();
    Ok(Solved { out, rows: holding, glued: loads, glued_peaks: peaks })
}

/// The joints and springs where the bodies are at the step's start, for the soft step.
pub(super) type Links = (Option<Vec<BodyState>>, Vec<JointConstraint>, Vec<SoftSpring>);

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
    for (_, cj) in model.holding_joints() {
        let (ea, eb) = (model.end_state_of(&cx.memory.y, cj.a), model.end_state_of(&cx.memory.y, cj.b));
        let mut index = |end: ResolvedBody| match end {
            ResolvedBody::Dynamic(j) => l.body_actor(j),
            ResolvedBody::Fixed(p) => fixed(Point3::from(p.translation.vector)),
        };
        let (a, b) = (index(cj.a), index(cj.b));
        joints.push(JointConstraint { a, b, frame: cj.frame(&ea, &eb), ..cj.joint });
    }
    let mut springs = Vec::with_capacity(model.springs.len());
    for s in &model.springs {
        let (a, b) = (s.a.actor(l), s.b.actor(l));
        let moves = |x: Option<usize>| x.is_some_and(|x| states[x].is_dynamic());
        if !(moves(a) || moves(b)) || (a.is_some() && a == b) {
            continue;
        }
        let mut place = |end: ResolvedAttachment| match end {
            ResolvedAttachment::Particle(i) => (i, Vector3::zeros()),
            ResolvedAttachment::Body(j, local) => (l.body_actor(j), cx.kin[j].rot * local),
            ResolvedAttachment::Point(p) => (fixed(Point3::from(p)), Vector3::zeros()),
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

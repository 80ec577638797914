//! Glued objects in fast mode's soft step: the pieces a cluster of holding welds binds (`JointBuilder::cluster`,
//! the glue of `World::add_fractured`) move as one rigid body while the welds hold, as the production tools move a
//! glued object. The step solves one compound body for them (their mass, centre and inertia together, their
//! contacts on it), and the pieces take its motion exactly; no weld rows are solved. Each weld's load is then
//! found from what moves the pieces: the welds give each piece what its share of the object's motion needs (its
//! mass times its acceleration as part of the rigid object, turning included) less its applied forces and
//! contacts; of the welds' wrenches that give every piece that, the one with the least elastic energy in the glue
//! (each bond a spring as stiff as its face is large: a loop of welds shares its load as layers of glue would),
//! solved by conjugate gradients (`glued_loads.rs`). The contacts' impulses come from the soft step weighed
//! substep by substep by the glue's window (`SoftLinks::manifold_windows`), so an impact counts at the substep it
//! lands in. A weld that breaks frees its pieces to the rows again where the cluster falls apart.
//!
//! A cluster is solved so when every piece moves (awake, dynamic), no other joint or spring holds one of them, and
//! its breakable welds share one window (the object's forces and contacts are weighed by it); otherwise its welds
//! are rows as any joint's. A contact between two glued objects is weighed by B's object's window, so two objects
//! glued with different windows that touch each other judge A's welds by B's weights.

use super::glued_parts::{Compound, WeldArm};
use crate::model::breaking::JointLoad;
use crate::model::Model;
use crate::model::ResolvedBody;
use nalgebra::{Matrix3, Point3, Vector3};
use std::collections::BTreeMap;
use tumble_contact::{BodyState, BodyVelocity, JointKind, SoftManifold};

/// The clusters solved as bodies this step, and which compound each actor is in.
pub(super) struct Glued {
    pub compounds: Vec<Compound>,
    of_actor: BTreeMap<usize, usize>,
}

/// Whether holding joint `k` is a weld of a cluster between two bodies.
fn is_glue(model: &Model, k: usize) -> bool {
    let j = &model.joints[k];
    !j.broken
        && j.cluster
        && j.joint.kind == JointKind::Weld
        && j.joint.softness.is_none()
        && matches!((j.a, j.b), (ResolvedBody::Dynamic(_), ResolvedBody::Dynamic(_)))
}

impl Glued {
    /// The clusters of `model` that can be solved as bodies, with the actors `states` at the step's start; `None`
    /// when there are none.
    pub fn find(model: &Model, states: &[BodyState]) -> Option<Glued> {
        let l = model.layout;
        let glue: Vec<usize> = (0..model.joints.len()).filter(|&k| is_glue(model, k)).collect();
        if glue.is_empty() {
            return None;
        }
        // pieces another joint or a spring holds: their clusters stay rows
        let mut held: Vec<usize> = model
            .holding_joints()
            .filter(|&(k, _)| !is_glue(model, k))
            .flat_map(|(_, j)| [j.a.actor(l), j.b.actor(l)])
            .flatten()
            .collect();
        held.extend(model.springs.iter().flat_map(|s| [s.a.actor(l), s.b.actor(l)]).flatten());
        // each cluster's pieces, and its welds (in order)
        let pieces = model.pieces_bound_by(&glue);
        let piece_of: BTreeMap<usize, usize> =
            pieces.iter().enumerate().flat_map(|(i, piece)| piece.iter().map(move |&a| (a, i))).collect();
        let mut clusters: Vec<(Vec<usize>, Vec<usize>)> = pieces.into_iter().map(|piece| (piece, Vec::new())).collect();
        for &k in &glue {
            clusters[piece_of[&model.joints[k].a.actor(l).expect("a body")]].1.push(k);
        }
        let mut glued = Glued { compounds: Vec::new(), of_actor: BTreeMap::new() };
        for (members, welds) in clusters {
            let moving = members.iter().all(|&a| states[a].is_dynamic() && states[a].inv_inertia != Matrix3::zeros());
            let windows: Vec<f64> = welds.iter().filter_map(|&k| model.joints[k].breaking).map(|b| b.window).collect();
            let one_window = windows.windows(2).all(|w| w[0] == w[1]);
            if members.len() < 2 || !moving || !one_window || members.iter().any(|a| held.contains(a)) {
                continue;
            }
            for &a in &members {
                glued.of_actor.insert(a, glued.compounds.len());
            }
            let state = compound_state(&members, states);
            let window = windows.first().copied().unwrap_or(0.0);
            glued.compounds.push(Compound { members, welds, state, window });
        }
        (!glued.compounds.is_empty()).then_some(glued)
    }

    /// Whether joint `k` is a weld solved inside a compound (not as rows).
    pub fn solves(&self, model: &Model, k: usize) -> bool {
        let a = model.joints[k].a.actor(model.layout);
        a.is_some_and(|a| is_glue(model, k) && self.of_actor.contains_key(&a))
    }

    /// The actors the soft step solves: `actors` with each compound's pieces fixed where they are (nothing
    /// refers to them) and the compounds appended; gives the compounds' first index.
    pub fn actors(&self, actors: &mut Vec<BodyState>) -> usize {
        let first = actors.len();
        for &a in self.of_actor.keys() {
            actors[a] = BodyState::fixed(actors[a].position);
        }
        actors.extend(self.compounds.iter().map(|c| c.state));
        first
    }

    /// Points each manifold on a piece at its compound (`first`: the compounds' first actor index), coloured
    /// again for the solve; gives each manifold's bodies and colour as they were, for `restore`, and its B's centre
    /// in the solve (where its angular impulse is taken about).
    pub fn remap(&self, manifolds: &mut [&mut SoftManifold], first: usize, actors: &[BodyState]) -> Remapped {
        let kept: Vec<[u32; 3]> = manifolds.iter().map(|m| [m.a as u32, m.b as u32, m.colour]).collect();
        let mut graph = tumble_contact::ColourGraph::new(actors.len());
        let (mut centres, mut windows) = (Vec::with_capacity(manifolds.len()), Vec::with_capacity(manifolds.len()));
        for m in manifolds.iter_mut() {
            let of = |a: usize| self.of_actor.get(&a).copied();
            // a manifold between two glued objects is weighed by B's window
            windows.push(of(m.b).or(of(m.a)).map_or(0.0, |c| self.compounds[c].window));
            let at = |a: usize| of(a).map_or(a, |c| first + c);
            (m.a, m.b) = (at(m.a), at(m.b));
            m.colour = graph.add((m.a, actors[m.a].is_dynamic()), (m.b, actors[m.b].is_dynamic()));
            centres.push(actors[m.b].position);
        }
        Remapped { kept, centres, windows }
    }

    /// Gives each manifold back its bodies and colour (`remap`'s).
    pub fn restore(manifolds: &mut [&mut SoftManifold], remapped: &Remapped) {
        for (m, &[a, b, colour]) in manifolds.iter_mut().zip(&remapped.kept) {
            (m.a, m.b, m.colour) = (a as usize, b as usize, colour);
        }
    }

    /// Each piece's velocity, displacement and rotation over the step from its compound's (the soft step's answer
    /// `out`, compounds from `first`): the compound's rigid motion carried to the piece.
    pub fn spread(&self, out: &mut tumble_contact::SoftStep, states: &[BodyState], first: usize) {
        for (c, compound) in self.compounds.iter().enumerate() {
            let at = first + c;
            let (v, d, turn) = (out.velocities[at], out.displacements[at], out.rotations[at]);
            let centre = compound.state.position;
            for &a in &compound.members {
                let arm = states[a].position - centre;
                let moved = turn * arm;
                out.velocities[a] = BodyVelocity { linear: v.linear + v.angular.cross(&moved), angular: v.angular };
                out.displacements[a] = d + moved - arm;
                out.rotations[a] = turn;
            }
        }
    }
}

/// The manifolds as `Glued::remap` left them for the solve: each one's bodies and colour as they were, its B's
/// centre in the solve (where its angular impulse is about) and the window its impulses are weighed by.
pub(super) struct Remapped {
    pub kept: Vec<[u32; 3]>,
    pub centres: Vec<Point3<f64>>,
    pub windows: Vec<f64>,
}

/// The compound of pieces `members` at the actors `states`: their mass, centre, inertia about it, momentum and
/// applied forces together.
fn compound_state(members: &[usize], states: &[BodyState]) -> BodyState {
    let mass: f64 = members.iter().map(|&a| 1.0 / states[a].inv_mass).sum();
    let centre = members.iter().fold(Vector3::zeros(), |s, &a| s + states[a].position.coords / states[a].inv_mass);
    let centre = Point3::from(centre / mass);
    let (mut inertia, mut momentum, mut spin, mut force, mut torque) =
        (Matrix3::zeros(), Vector3::zeros(), Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
    for &a in members {
        let s = &states[a];
        let (m, r) = (1.0 / s.inv_mass, s.position - centre);
        inertia += s.inertia + (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * m;
        momentum += s.velocity * m;
        spin += s.inertia * s.angular_velocity + r.cross(&(s.velocity * m));
        force += s.force;
        torque += s.torque + r.cross(&s.force);
    }
    let inv_inertia = inertia.try_inverse().unwrap_or_else(Matrix3::zeros);
    BodyState {
        inv_mass: 1.0 / mass,
        inertia,
        inv_inertia,
        position: centre,
        velocity: momentum / mass,
        angular_velocity: inv_inertia * spin,
        force,
        torque,
    }
}

/// What a step's solve left for the welds' loads: the pieces' states at its start, its answer (the manifolds'
/// impulses, `SoftStep::manifold_impulses`, and the compounds' velocities from `first`), the manifolds as
/// `remap` left them, and the step in substeps.
pub(super) struct Balance<'a> {
    pub states: &'a [BodyState],
    pub out: &'a tumble_contact::SoftStep,
    pub first: usize,
    pub remapped: &'a Remapped,
    pub h: f64,
    pub substeps: usize,
}

impl Balance<'_> {
    /// Whether a blow struck one of `compound`'s manifolds in the step (its peak impulses are not its weighed ones).
    fn struck(&self, compound: &Compound) -> bool {
        let members = |a: u32| compound.members.binary_search(&(a as usize)).is_ok();
        let impulses = self.out.manifold_impulses.iter().zip(&self.out.manifold_peak_impulses);
        impulses.zip(&self.remapped.kept).any(|((w, p), &[a, b, _])| w != p && (members(a) || members(b)))
    }

    /// A force's impulse over the step weighed substep by substep as window `window` weighs them (the step's
    /// length for none): the substep times the sum of e^(-k substep / window) over the substeps k before the end.
    fn weighed_step(&self, window: f64) -> f64 {
        let (n, hs) = (self.substeps.max(1) as f64, self.h / self.substeps.max(1) as f64);
        if window > 0.0 {
            hs * (-n * hs / window).exp_m1() / (-hs / window).exp_m1()
        } else {
            self.h
        }
    }
}

impl Glued {
    /// Each compounded weld's impulse over the step (its force on B and torque on B about its anchor), weighed
    /// substep by substep by its object's window as a joint's are (`SoftStep::joint_step_impulses`), by joint
    /// index; and, for the welds of an object struck in the step, the same with the blow counted at its full weight
    /// (`SoftStep::manifold_peak_impulses`: the load's peak within the step). `y`: the state at the step's start.
    pub fn loads(&self, model: &Model, y: &[f64], b: &Balance<'_>) -> (WeldLoads, WeldLoads) {
        let (mut out, mut peaks) = (BTreeMap::new(), BTreeMap::new());
        for (c, compound) in self.compounds.iter().enumerate() {
            let (omega, step) = (b.out.velocities[b.first + c].angular, b.weighed_step(compound.window));
            let welds: Vec<WeldArm> =
                compound.welds.iter().map(|&k| WeldArm::of(model, y, k, &compound.members)).collect();
            let solve = |impulses: &[Wrench], into: &mut WeldLoads| {
                let wrenches = needed(compound, omega, step, b, impulses);
                let found = super::glued_loads::least_loads(&welds, compound, b.states, wrenches);
                for (w, (force, torque)) in welds.iter().zip(found) {
                    into.insert(w.joint, JointLoad { force, torque });
                }
            };
            solve(&b.out.manifold_impulses, &mut out);
            if b.struck(compound) {
                solve(&b.out.manifold_peak_impulses, &mut peaks);
            }
        }
        (out, peaks)
    }
}

/// Loads by joint index.
pub(super) type WeldLoads = BTreeMap<usize, JointLoad>;

/// A wrench: linear and angular parts.
type Wrench = (Vector3<f64>, Vector3<f64>);

/// What the welds must give each member over the step (linear, and angular about its centre at the step's start),
/// before the object's own acceleration is shared out (`glued_loads::balance`): its turning's needs (the
/// centripetal force and Euler's gyroscopic torque at the object's spin `omega`) less its applied forces, over the
/// weighed step `step`, less its contacts' weighed impulses.
fn needed(compound: &Compound, omega: Vector3<f64>, step: f64, b: &Balance<'_>, impulses: &[Wrench]) -> Vec<Wrench> {
    let centre = compound.state.position;
    let mut out: Vec<(Vector3<f64>, Vector3<f64>)> = compound
        .members
        .iter()
        .map(|&a| {
            let s = &b.states[a];
            let r = s.position - centre;
            let linear = (omega.cross(&omega.cross(&r)) / s.inv_mass - s.force) * step;
            let angular = (omega.cross(&(s.inertia * omega)) - s.torque) * step;
            (linear, angular)
        })
        .collect();
    let manifolds = impulses.iter().zip(&b.remapped.kept).zip(&b.remapped.centres);
    for (((linear, angular), &[a, bb, _]), centre) in manifolds {
        for (end, sign) in [(a as usize, -1.0), (bb as usize, 1.0)] {
            let Ok(i) = compound.members.binary_search(&end) else { continue };
            // the impulse on B is (linear, angular about B's centre in the solve); A takes the opposite at the
            // same points
            let about = *angular + (centre - b.states[end].position).cross(linear);
            out[i].0 -= linear * sign;
            out[i].1 -= about * sign;
        }
    }
    out
}

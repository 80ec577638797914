//! Fast mode's contact solver: Catto's soft step (Box2D v3, "Solver2D" 2024), in 3-D. The step of h is cut into
//! substeps; each integrates the velocities (the applied forces given once a step, springs evaluated where the
//! substep starts, `springs.rs`), applies the impulses carried from the last substep (warm start), solves
//! every contact once as a soft constraint (a spring and damper given in hertz and a damping ratio, so an overlap is
//! pushed out smoothly and stiff stacks stay stable), moves the bodies, and solves again without the push (relax),
//! friction included; restitution comes once after the substeps. Impulses are kept per contact across steps (the
//! caller matches contacts by feature) and start the next step. Contacts, joints and springs join bodies into
//! islands. Islands are independent; small ones are gathered into batches swept side by side (`batches`), and batches
//! are solved on as many threads as asked, each in an order fixed by the contacts, so the answer is the same bit for
//! bit on any thread count and as island by island.
//!
//! What it gives up against the exact cone program (`velocity_step`): a resting contact sinks until its spring
//! carries the load (about g / (2 pi hertz)^2 per body weight), and an iteration count that bounds the work bounds
//! the accuracy of a deep stack. `residual` says how far an answer is from the exact contact conditions.

mod bundle;
mod colour;
mod geometry;
mod island;
mod joints;
mod row;
mod softness;
mod springs;
mod stages;
mod wide;

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::error::ContactError;
use crate::impulse::BodyVelocity;
use crate::islands::joint_islands;
use crate::joint::{Joint, JointImpulse};
use crate::threads::{cores, in_parallel_by};
use island::Island;
use joints::JointSet;
use nalgebra::{UnitQuaternion, Vector3};
use row::Mover;
pub use springs::SoftSpring;
use springs::SpringSet;

/// Settings of the soft step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoftSettings {
    /// Substeps per step (>= 1); 8 by default.
    pub substeps: usize,
    /// Sweeps of each pass per substep (>= 1); 2 by default.
    pub iterations: usize,
    /// Stiffness of contacts between moving bodies (Hz), capped at a quarter of the substep rate (beyond it the
    /// soft step loses its stability margin); contacts with static bodies get twice it. Infinity (the default)
    /// means the cap: the stiffest contact the substeps allow.
    pub contact_hertz: f64,
    /// Damping ratio of the contact springs (>= 0); 10 by default (overdamped: overlaps are pushed out without a
    /// bounce).
    pub damping_ratio: f64,
    /// Largest speed at which an overlap is pushed out (m/s); 3 by default.
    pub max_push_out: f64,
    /// Restitution applies to contacts closing faster than this (m/s); 0.1 by default.
    pub bounce_threshold: f64,
    /// Threads for the islands: 0 uses one per core, 1 stays on the calling thread.
    pub threads: usize,
    /// Stiffness of the pull that holds rigid joints together (Hz), capped at half the substep rate; infinity (the
    /// default) means the cap.
    pub joint_hertz: f64,
    /// Damping ratio of that pull (>= 0); 2 by default.
    pub joint_damping_ratio: f64,
}

impl Default for SoftSettings {
    fn default() -> Self {
        SoftSettings {
            substeps: 8,
            iterations: 2,
            contact_hertz: f64::INFINITY,
            damping_ratio: 10.0,
            max_push_out: 3.0,
            bounce_threshold: 0.1,
            threads: 0,
            joint_hertz: f64::INFINITY,
            joint_damping_ratio: 2.0,
        }
    }
}

impl SoftSettings {
    fn check(&self) -> Result<(), ContactError> {
        if self.substeps == 0 || self.substeps > 1000 {
            return Err(ContactError::invalid("substeps", format!("must be 1..=1000, got {}", self.substeps)));
        }
        if self.iterations == 0 || self.iterations > 1000 {
            return Err(ContactError::invalid("iterations", format!("must be 1..=1000, got {}", self.iterations)));
        }
        let positive = |name: &'static str, v: f64, infinite_ok: bool| {
            if v > 0.0 && (v.is_finite() || infinite_ok) {
                Ok(())
            } else {
                Err(ContactError::invalid(name, format!("must be > 0, got {v}")))
            }
        };
        positive("contact_hertz", self.contact_hertz, true)?;
        positive("max_push_out", self.max_push_out, false)?;
        positive("joint_hertz", self.joint_hertz, true)?;
        if !(self.joint_damping_ratio >= 0.0 && self.joint_damping_ratio.is_finite()) {
            return Err(ContactError::invalid(
                "joint_damping_ratio",
                format!("must be >= 0, got {}", self.joint_damping_ratio),
            ));
        }
        if !(self.damping_ratio >= 0.0 && self.damping_ratio.is_finite()) {
            return Err(ContactError::invalid("damping_ratio", format!("must be >= 0, got {}", self.damping_ratio)));
        }
        if !(self.bounce_threshold >= 0.0 && self.bounce_threshold.is_finite()) {
            return Err(ContactError::invalid(
                "bounce_threshold",
                format!("must be >= 0, got {}", self.bounce_threshold),
            ));
        }
        Ok(())
    }
}

/// A contact's impulses over one substep: normal, and friction as a world vector (so that it carries to the next
/// step's tangent directions).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftImpulse {
    pub normal: f64,
    pub tangent: Vector3<f64>,
}

/// What a soft step gives.
#[derive(Clone, Debug)]
pub struct SoftStep {
    /// Each body's velocities at the step's end.
    pub velocities: Vec<BodyVelocity>,
    /// Each body's displacement of its centre of mass over the step.
    pub displacements: Vec<Vector3<f64>>,
    /// Each body's rotation over the step (world frame: new orientation = rotation * old).
    pub rotations: Vec<UnitQuaternion<f64>>,
    /// Each contact's impulses of the last substep (to start the next step with).
    pub impulses: Vec<SoftImpulse>,
    /// Each contact's normal impulse over the whole step (the substeps' sum).
    pub normal_impulses: Vec<f64>,
    /// Each joint's row impulses of the last substep (to start the next step with).
    pub joint_impulses: Vec<JointImpulse>,
    /// Islands solved.
    pub islands: usize,
    /// How far the step's end is from the exact contact conditions (m/s): the largest approach speed of a touching
    /// contact, separating speed of a contact that pushes while apart, or slip of a contact sticking inside its
    /// friction bound. Zero for the exact answer; what the sweeps left unsolved otherwise.
    pub residual: f64,
    /// Time spent building the rows (s: each group's bodies, bundles, constraint axes and effective masses, joints
    /// and springs), summed over the groups (on several threads it can pass the wall time).
    pub prepare_seconds: f64,
}

/// Two steps are equal when their answers are: the time they took is not part of it.
impl PartialEq for SoftStep {
    fn eq(&self, o: &SoftStep) -> bool {
        self.velocities == o.velocities
            && self.displacements == o.displacements
            && self.rotations == o.rotations
            && self.impulses == o.impulses
            && self.normal_impulses == o.normal_impulses
            && self.joint_impulses == o.joint_impulses
            && self.islands == o.islands
            && self.residual.to_bits() == o.residual.to_bits()
    }
}

thread_local! {
    /// Each body's place among the members of the group being set up on this thread (usize::MAX: none), reset
    /// after each group: a lookup a contact end without a search.
    static LOCAL: std::cell::RefCell<Vec<usize>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Contacts from which a step's batches are spread over threads.
const PARALLEL_CONTACTS: usize = 1000;

/// Contacts from which one island is solved on all the threads, colour by colour.
const COLOUR_THREADS: usize = 1000;

/// Rows a batch of islands gathers before it is closed.
const BATCH_ROWS: usize = 256;

/// A group solved as one: contacts, joints and springs (indices into the step's).
#[derive(Clone, Debug, Default)]
struct Group {
    contacts: Vec<usize>,
    joints: Vec<usize>,
    springs: Vec<usize>,
}

/// An island: its contacts, joints and springs (indices into the step's).
type Links = (Vec<usize>, Vec<usize>, Vec<usize>);

/// The islands gathered into batches solved as one (in island order, up to `BATCH_ROWS` contacts each), and for
/// each island whether it needs sweeps until it settles (`island::converges`; such an island is a batch of its
/// own, as is an island with joints or springs). Islands share no moving body, so a batch's colour order puts the
/// rows of different islands side by side (a lone box on the floor no longer chains four solves on one body) while
/// each island's rows keep the colours and order they have alone: the answer is the same bit for bit as island by
/// island.
fn batches(islands: Vec<Links>, bodies: &[BodyState], contacts: &[Contact], joints: &[Joint]) -> Vec<(Group, bool)> {
    let mut out: Vec<(Group, bool)> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    for (island, linked, springs) in islands {
        let ends = island.iter().flat_map(|&i| [contacts[i].a, contacts[i].b]);
        let ends = ends.chain(linked.iter().flat_map(|&j| [joints[j].a, joints[j].b]));
        let converge = island::converges(ends.map(|b| bodies[b].inv_mass));
        if converge || !linked.is_empty() || !springs.is_empty() {
            out.push((Group { contacts: island, joints: linked, springs }, converge));
            continue;
        }
        open.extend(island);
        if open.len() >= BATCH_ROWS {
            out.push((Group { contacts: std::mem::take(&mut open), ..Group::default() }, false));
        }
    }
    if !open.is_empty() {
        out.push((Group { contacts: open, ..Group::default() }, false));
    }
    out
}

/// What one group's solve gives the step: each dynamic body's velocities and motion, each contact's impulses (by
/// its index in the step's contacts), and the residual.
struct Solved {
    bodies: Vec<(usize, BodyVelocity, Vector3<f64>, UnitQuaternion<f64>)>,
    contacts: Vec<(usize, SoftImpulse, f64)>,
    joints: Vec<(usize, JointImpulse)>,
    residual: f64,
    prepare_seconds: f64,
}

impl Solved {
    fn of(members: &[usize], island: &Island, group: &Group, bodies: &[BodyState], prepare_seconds: f64) -> Solved {
        let moved = members.iter().zip(&island.movers).filter(|(&b, _)| bodies[b].is_dynamic());
        let mut contacts = Vec::with_capacity(group.contacts.len());
        for (bu, fr) in island.bundles.iter().zip(&island.frictions) {
            for l in 0..bu.lanes {
                for p in 0..bu.count[l] {
                    let info = &island.infos[bu.info[l][p]];
                    let impulse = SoftImpulse { normal: bu.rows[p].normal[l], tangent: fr.points[p].vector(l) };
                    contacts.push((group.contacts[info.index], impulse, info.step_normal));
                }
            }
        }
        Solved {
            bodies: moved.map(|(&b, m)| (b, BodyVelocity { linear: m.v, angular: m.w }, m.dp, m.dq)).collect(),
            contacts,
            joints: group.joints.iter().copied().zip(island.joints.impulses.iter().copied()).collect(),
            residual: island.residual(),
            prepare_seconds,
        }
    }
}

/// Checks each joint against the bodies: indices in range, two different bodies, one of them moving, every number
/// finite.
fn check_joints(bodies: &[BodyState], joints: &[Joint], warm: &[JointImpulse]) -> Result<(), ContactError> {
    if warm.len() != joints.len() {
        return Err(ContactError::invalid(
            "joint_warm",
            format!("has {} entries for {} joints", warm.len(), joints.len()),
        ));
    }
    for (k, j) in joints.iter().enumerate() {
        if j.a >= bodies.len() || j.b >= bodies.len() || j.a == j.b {
            return Err(ContactError::invalid("joints", format!("joint {k} joins bodies {} and {}", j.a, j.b)));
        }
        if !(bodies[j.a].is_dynamic() || bodies[j.b].is_dynamic()) {
            return Err(ContactError::invalid("joints", format!("joint {k} joins two bodies that do not move")));
        }
        let f = &j.frame;
        let numbers =
            [f.ra, f.rb, f.axis, f.across[0], f.across[1], f.axis_b].into_iter().flat_map(|v| [v.x, v.y, v.z]);
        if !(numbers.chain(f.error.coords.iter().copied()).all(f64::is_finite)
            && warm[k].0.iter().all(|p| p.is_finite()))
        {
            return Err(ContactError::invalid("joints", format!("joint {k} has a non-finite number")));
        }
    }
    Ok(())
}

/// Checks each spring against the bodies: indices in range, two different bodies, one of them moving, every
/// number finite, stiffness, damping and rest length not negative.
fn check_springs(bodies: &[BodyState], springs: &[SoftSpring]) -> Result<(), ContactError> {
    for (k, s) in springs.iter().enumerate() {
        if s.a >= bodies.len() || s.b >= bodies.len() || s.a == s.b {
            return Err(ContactError::invalid("springs", format!("spring {k} joins bodies {} and {}", s.a, s.b)));
        }
        if !(bodies[s.a].is_dynamic() || bodies[s.b].is_dynamic()) {
            return Err(ContactError::invalid("springs", format!("spring {k} joins two bodies that do not move")));
        }
        if !s.is_valid() {
            return Err(ContactError::invalid(
                "springs",
                format!("spring {k} has a non-finite or negative stiffness, damping, rest length or arm"),
            ));
        }
    }
    Ok(())
}

/// What one soft step solves: the bodies, their contacts (each started from `warm[i]`, the same contact's
/// impulses of the last step, or zero), joints (each started from its impulses of the last step in `joint_warm`, or
/// zero) and springs (forces evaluated at every substep; a body's `force` and `torque` must not hold them as well).
/// Bodies joined by none of them move freely by the same substeps.
#[derive(Clone, Copy, Debug, Default)]
pub struct SoftProblem<'a> {
    pub bodies: &'a [BodyState],
    pub contacts: &'a [Contact],
    pub warm: &'a [SoftImpulse],
    pub joints: &'a [Joint],
    pub joint_warm: &'a [JointImpulse],
    pub springs: &'a [SoftSpring],
}

impl<'a> SoftProblem<'a> {
    /// The bodies and their contacts with their warm starts; no joints or springs.
    pub fn new(bodies: &'a [BodyState], contacts: &'a [Contact], warm: &'a [SoftImpulse]) -> Self {
        SoftProblem { bodies, contacts, warm, ..Default::default() }
    }

    /// Joints with their warm starts.
    pub fn joints(self, joints: &'a [Joint], joint_warm: &'a [JointImpulse]) -> Self {
        SoftProblem { joints, joint_warm, ..self }
    }

    /// Springs.
    pub fn springs(self, springs: &'a [SoftSpring]) -> Self {
        SoftProblem { springs, ..self }
    }
}

/// A soft step of h.
pub fn soft_step(problem: &SoftProblem<'_>, h: f64, settings: &SoftSettings) -> Result<SoftStep, ContactError> {
    let SoftProblem { bodies, contacts, warm, joints, joint_warm, springs } = *problem;
    settings.check()?;
    if !(h.is_finite() && h > 0.0) {
        return Err(ContactError::invalid("dt", format!("must be finite and > 0, got {h}")));
    }
    if warm.len() != contacts.len() {
        return Err(ContactError::invalid(
            "warm",
            format!("has {} entries for {} contacts", warm.len(), contacts.len()),
        ));
    }
    check_all(bodies, contacts)?;
    check_joints(bodies, joints, joint_warm)?;
    check_springs(bodies, springs)?;
    let substeps = settings.substeps;
    let mut out = SoftStep {
        velocities: Vec::with_capacity(bodies.len()),
        displacements: vec![Vector3::zeros(); bodies.len()],
        rotations: vec![UnitQuaternion::identity(); bodies.len()],
        impulses: vec![SoftImpulse::default(); contacts.len()],
        normal_impulses: vec![0.0; contacts.len()],
        joint_impulses: vec![JointImpulse::default(); joints.len()],
        islands: 0,
        residual: 0.0,
        prepare_seconds: 0.0,
    };
    let pairs: Vec<(usize, usize)> =
        joints.iter().map(|j| (j.a, j.b)).chain(springs.iter().map(|s| (s.a, s.b))).collect();
    // each island's links split into its joints and its springs (which follow the joints among the pairs)
    let islands: Vec<Links> = joint_islands(bodies, contacts, &pairs)
        .into_iter()
        .map(|(island, linked)| {
            let (js, ss): (Vec<usize>, Vec<usize>) = linked.into_iter().partition(|&k| k < joints.len());
            (island, js, ss.into_iter().map(|k| k - joints.len()).collect())
        })
        .collect();
    out.islands = islands.len();
    let groups = batches(islands, bodies, contacts, joints);
    let solve = |(group, converge): &(Group, bool), threads: usize| -> Result<Solved, ContactError> {
        LOCAL.with(|slots| {
            let clock = std::time::Instant::now();
            let slots = &mut *slots.borrow_mut();
            if slots.len() < bodies.len() {
                slots.resize(bodies.len(), usize::MAX);
            }
            // the group's bodies in order of first appearance (contacts, joints, then springs), each given its place
            let mut members: Vec<usize> = Vec::new();
            let ends = group.contacts.iter().flat_map(|&i| [contacts[i].a, contacts[i].b]);
            let ends = ends.chain(group.joints.iter().flat_map(|&k| [joints[k].a, joints[k].b]));
            for b in ends.chain(group.springs.iter().flat_map(|&k| [springs[k].a, springs[k].b])) {
                if slots[b] == usize::MAX {
                    slots[b] = members.len();
                    members.push(b);
                }
            }
            let movers = members.iter().map(|&b| Mover::new(&bodies[b])).collect();
            let cs: Vec<&Contact> = group.contacts.iter().map(|&i| &contacts[i]).collect();
            let ws: Vec<SoftImpulse> = group.contacts.iter().map(|&i| warm[i]).collect();
            let mut island = Island::new(movers, bodies, &cs, |b| slots[b], &ws, *converge);
            if !group.joints.is_empty() {
                let local = group.joints.iter().map(|&k| {
                    let j = &joints[k];
                    let placed = Joint { a: slots[j.a], b: slots[j.b], ..*j };
                    (placed, bodies[j.a].position.coords, bodies[j.b].position.coords)
                });
                island.joints = JointSet::new(local.collect(), group.joints.iter().map(|&k| joint_warm[k]).collect());
            }
            if !group.springs.is_empty() {
                let local = group.springs.iter().map(|&k| {
                    let s = &springs[k];
                    let placed = SoftSpring { a: slots[s.a], b: slots[s.b], ..*s };
                    (placed, bodies[s.a].position.coords, bodies[s.b].position.coords)
                });
                island.springs = SpringSet::new(local);
            }
            for &b in &members {
                slots[b] = usize::MAX;
            }
            let prepare_seconds = clock.elapsed().as_secs_f64();
            island.solve(h, settings, threads);
            // only what the step gives is kept: an island's rows (kilobytes a manifold) are dropped here, so that
            // a step over many islands never holds all their rows at once
            Ok(Solved::of(&members, &island, group, bodies, prepare_seconds))
        })
    };
    // a soft row costs tens of nanoseconds a sweep: threads pay from about a thousand contacts (measured: the pile of
    // 100 cubes, 400 contacts, 0.50 ms a step on one thread and 0.54-0.60 on two; 1,000 cubes 7.0-8.3 and 5.3-6.3)
    // a group of many contacts is solved on all the threads, graph colour by graph colour; the others island by
    // island on them
    let threads = if settings.threads == 0 { cores() } else { settings.threads };
    let whole = |(g, _): &(Group, bool)| threads > 1 && g.contacts.len() >= COLOUR_THREADS;
    let rows = contacts.len() + joints.len() + springs.len();
    let size = |(g, _): &(Group, bool)| g.contacts.len() + g.joints.len() + g.springs.len();
    let solved: Vec<Result<Solved, ContactError>> = if groups.iter().any(whole) {
        let rest: Vec<(Group, bool)> = groups.iter().filter(|g| !whole(g)).cloned().collect();
        let mut rest = in_parallel_by(&rest, size, (rows, PARALLEL_CONTACTS), settings.threads, |g| solve(g, 1));
        let mut rest = rest.drain(..);
        groups
            .iter()
            .map(|g| if whole(g) { solve(g, threads) } else { rest.next().expect("one result a group") })
            .collect()
    } else {
        in_parallel_by(&groups, size, (rows, PARALLEL_CONTACTS), settings.threads, |g| solve(g, 1))
    };
    let mut velocities: Vec<Option<BodyVelocity>> = vec![None; bodies.len()];
    for result in solved {
        let solved = result?;
        out.residual = out.residual.max(solved.residual);
        out.prepare_seconds += solved.prepare_seconds;
        for (b, v, dp, dq) in solved.bodies {
            velocities[b] = Some(v);
            out.displacements[b] = dp;
            out.rotations[b] = dq;
        }
        for (i, impulse, step_normal) in solved.contacts {
            out.impulses[i] = impulse;
            out.normal_impulses[i] = step_normal;
        }
        for (k, impulse) in solved.joints {
            out.joint_impulses[k] = impulse;
        }
    }
    // Bodies in no island (and static ones) move on their own, by the same substeps.
    for (b, body) in bodies.iter().enumerate() {
        let v = match velocities[b] {
            Some(v) => v,
            None => {
                let mut m = Mover::new(body);
                m.free(h, substeps);
                out.displacements[b] = m.dp;
                out.rotations[b] = m.dq;
                BodyVelocity { linear: m.v, angular: m.w }
            }
        };
        out.velocities.push(v);
    }
    Ok(out)
}

#[cfg(test)]
mod tests;

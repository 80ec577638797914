//! Fast mode's contact solver: Catto's soft step (Box2D v3, "Solver2D" 2024), in 3-D. The step of h is cut into
//! substeps; each integrates the velocities (the applied forces given once a step, springs evaluated where the
//! substep starts, `springs.rs`), applies the impulses carried from the last substep (warm start), solves
//! every contact once as a soft constraint (a spring and damper given in hertz and a damping ratio, so an overlap is
//! pushed out smoothly and stiff stacks stay stable), moves the bodies, and solves again without the push (relax),
//! friction included; restitution comes once after the substeps. Contacts come as manifolds the caller keeps from
//! step to step (`manifold.rs`): a body pair's points with their impulses, which start the next step, and the
//! manifold's colour in the constraint graph the caller keeps (`graph.rs`). All manifolds are solved together, colour
//! by colour (`group.rs`, `stages.rs`), on as many threads as asked, each colour's share in an order fixed by the
//! manifolds, so the answer is the same bit for bit on any thread count and as island by island; an island of a large
//! mass ratio is solved on its own until its impulses settle. `soft_step` takes plain contacts instead and makes the
//! manifolds, coloured afresh.
//!
//! What it gives up against the exact cone program (`velocity_step`): a resting contact sinks until its spring
//! carries the load (about g / (2 pi hertz)^2 per body weight), and an iteration count that bounds the work bounds
//! the accuracy of a deep stack. `residual` says how far an answer is from the exact contact conditions.

mod answer;
mod bundle;
mod checks;
mod friction_bundle;
mod geometry;
mod graph;
mod group;
mod joints;
mod manifold;
mod row;
mod settings;
mod softness;
mod springs;
mod stages;
mod wide;

use crate::body::BodyState;
use crate::contact::{check_all, Contact};
use crate::error::ContactError;
use crate::impulse::BodyVelocity;
use crate::islands::link_islands;
use crate::joint::{JointConstraint, JointImpulse};
use crate::threads::{cores, in_parallel_by};
pub use answer::SoftStep;
use checks::{check_bodies, check_joints, check_springs};
pub use graph::{ColourGraph, COLOURS, OVERFLOW, UNCOLOURED};
use group::Group;
use joints::JointSet;
pub use manifold::{SoftManifold, SoftPoint, MANIFOLD_POINTS};
use nalgebra::{UnitQuaternion, Vector3};
use row::Mover;
pub use settings::SoftSettings;
pub use springs::SoftSpring;
use springs::SpringSet;
use std::borrow::BorrowMut;

/// A contact's impulses over one substep: normal, and friction as a world vector (so that it carries to the next
/// step's tangent directions).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftImpulse {
    pub normal: f64,
    pub tangent: Vector3<f64>,
}

thread_local! {
    /// Each body's place among the members of the group being set up on this thread (usize::MAX: none), reset
    /// after each group: a lookup a contact end without a search.
    static LOCAL: std::cell::RefCell<Vec<usize>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Contact points from which a group is solved on all the threads, colour by colour, and from which a step's groups
/// are shared out among them (a soft row costs tens of nanoseconds a sweep: threads pay from about a thousand).
const COLOUR_THREADS: usize = 1000;

/// Contact points a batch of islands gathers before it is closed (a few hundred kilobytes of rows, which stay in the
/// cache over the group's substeps).
const BATCH_POINTS: usize = 512;

/// The joints, joint warm starts and springs of a soft step besides its manifolds, and each joint's and each
/// manifold's window: the time (s) over which its impulses over the step are weighed
/// (`SoftStep::joint_step_impulses`, `SoftStep::manifold_impulses`), 0 for none (empty: none).
#[derive(Clone, Copy, Debug, Default)]
pub struct SoftLinks<'a> {
    pub joints: &'a [JointConstraint],
    pub joint_warm: &'a [JointImpulse],
    pub springs: &'a [SoftSpring],
    pub windows: &'a [f64],
    pub manifold_windows: &'a [f64],
}

/// What one soft step solves, by contacts: the bodies, their contacts (each started from `warm[i]`, the same
/// contact's impulses of the last step, or zero), joints (each started from its impulses of the last step in
/// `joint_warm`, or zero) and springs (forces evaluated at every substep; a body's `force` and `torque` must not hold
/// them as well). Bodies joined by none of them move freely by the same substeps. (`soft_solve` takes the contacts
/// as manifolds kept by the caller.)
#[derive(Clone, Copy, Debug, Default)]
pub struct SoftProblem<'a> {
    pub bodies: &'a [BodyState],
    pub contacts: &'a [Contact],
    pub warm: &'a [SoftImpulse],
    pub joints: &'a [JointConstraint],
    pub joint_warm: &'a [JointImpulse],
    pub springs: &'a [SoftSpring],
}

impl<'a> SoftProblem<'a> {
    /// The bodies and their contacts with their warm starts; no joints or springs.
    pub fn new(bodies: &'a [BodyState], contacts: &'a [Contact], warm: &'a [SoftImpulse]) -> Self {
        SoftProblem { bodies, contacts, warm, ..Default::default() }
    }

    /// Joints with their warm starts.
    pub fn joints(self, joints: &'a [JointConstraint], joint_warm: &'a [JointImpulse]) -> Self {
        SoftProblem { joints, joint_warm, ..self }
    }

    /// Springs.
    pub fn springs(self, springs: &'a [SoftSpring]) -> Self {
        SoftProblem { springs, ..self }
    }
}

/// A soft step of h by contacts: each body pair's contacts become manifolds of up to four points (in the order of
/// their first contacts), coloured afresh in that order, and solved by `soft_solve`; each contact's impulses come
/// back in `impulses` and `normal_impulses`. A manifold's friction starts from its contacts' friction impulses
/// summed and comes back shared among them by their normal impulses; its twist starts from none.
pub fn soft_step(problem: &SoftProblem<'_>, h: f64, settings: &SoftSettings) -> Result<SoftStep, ContactError> {
    let SoftProblem { bodies, contacts, warm, joints, joint_warm, springs } = *problem;
    if warm.len() != contacts.len() {
        return Err(ContactError::invalid(
            "warm",
            format!("has {} entries for {} contacts", warm.len(), contacts.len()),
        ));
    }
    check_all(bodies, contacts)?;
    // manifolds: a body pair's contacts, four at most, in the order of their first contacts
    let mut by_pair: Vec<(usize, usize, usize)> = contacts.iter().zip(0..).map(|(c, k)| (c.a, c.b, k)).collect();
    by_pair.sort_unstable();
    let mut groups: Vec<&[(usize, usize, usize)]> =
        by_pair.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)).flat_map(|run| run.chunks(MANIFOLD_POINTS)).collect();
    groups.sort_unstable_by_key(|m| m[0].2);
    let mut graph = ColourGraph::new(bodies.len());
    let moves = |b: usize| bodies[b].is_dynamic();
    let mut manifolds: Vec<SoftManifold> = groups
        .iter()
        .map(|g| {
            let first = &contacts[g[0].2];
            let mut m = SoftManifold::new(first.a, first.b, first.friction, first.restitution)
                .with_resistance(first.rolling_resistance, first.torsional_resistance);
            m.colour = graph.add((m.a, moves(m.a)), (m.b, moves(m.b)));
            for (p, &(_, _, k)) in g.iter().enumerate() {
                let c = &contacts[k];
                let point = SoftPoint {
                    point: c.point,
                    normal: c.normal.into_inner(),
                    gap: c.distance,
                    normal_impulse: warm[k].normal,
                    step_normal: 0.0,
                };
                m.points[p] = point;
            }
            m.count = g.len();
            m
        })
        .collect();
    // a manifold carries one friction and restitution: contacts of a pair with others of their own are solved as
    // manifolds of their own
    let mut split: Vec<SoftManifold> = Vec::new();
    let mut origin: Vec<Vec<usize>> = Vec::new();
    for (m, g) in manifolds.drain(..).zip(&groups) {
        let runs = g.chunk_by(|x, y| {
            let (cx, cy) = (&contacts[x.2], &contacts[y.2]);
            (cx.friction, cx.restitution, cx.rolling_resistance, cx.torsional_resistance)
                == (cy.friction, cy.restitution, cy.rolling_resistance, cy.torsional_resistance)
        });
        let mut first = true;
        let mut at = 0;
        for run in runs {
            let c = &contacts[run[0].2];
            let mut part = SoftManifold::new(m.a, m.b, c.friction, c.restitution)
                .with_resistance(c.rolling_resistance, c.torsional_resistance);
            part.colour = if first { m.colour } else { graph.add((m.a, moves(m.a)), (m.b, moves(m.b))) };
            first = false;
            part.count = run.len();
            part.points[..run.len()].copy_from_slice(&m.points[at..at + run.len()]);
            // the manifold's friction starts from its contacts' friction impulses summed
            part.tangent_impulse = run.iter().map(|x| warm[x.2].tangent).sum();
            at += run.len();
            origin.push(run.iter().map(|x| x.2).collect());
            split.push(part);
        }
    }
    let links = SoftLinks { joints, joint_warm, springs, ..SoftLinks::default() };
    let mut out = soft_solve(bodies, &mut split, &links, h, settings)?;
    out.impulses = vec![SoftImpulse::default(); contacts.len()];
    out.manifold_impulses = Vec::new();
    out.manifold_peak_impulses = Vec::new();
    out.normal_impulses = vec![0.0; contacts.len()];
    for (m, ks) in split.iter().zip(&origin) {
        // a manifold's friction shared among its contacts by their normal impulses (evenly if none pushed)
        let total: f64 = m.points().iter().map(|p| p.normal_impulse).sum();
        for (p, &k) in m.points().iter().zip(ks) {
            let share = if total > 0.0 { p.normal_impulse / total } else { 1.0 / m.count as f64 };
            out.impulses[k] = SoftImpulse { normal: p.normal_impulse, tangent: m.tangent_impulse * share };
            out.normal_impulses[k] = p.step_normal;
        }
    }
    Ok(out)
}

/// What a group of the step solves: its manifolds (indices into the step's, in order), its islands' joint sets (the
/// joints of each, indices into the step's) and its springs; whether it sweeps until its impulses settle.
#[derive(Clone, Debug, Default)]
struct Spec {
    manifolds: Vec<usize>,
    joints: Vec<Vec<usize>>,
    springs: Vec<usize>,
    converge: bool,
}

/// A soft step of h for `bodies` with the caller's `manifolds` (each coloured in the caller's constraint graph,
/// its points' impulses the last step's), joints and springs: each manifold point's impulses come back in it (this
/// step's), the bodies' motion in the answer. Islands whose masses differ by more than ten times are solved each on
/// its own, sweeping until its impulses settle; the rest together, colour by colour, on as many threads as asked
/// from about a thousand contact points: the same bits on any thread count.
pub fn soft_solve<M: BorrowMut<SoftManifold> + Send>(
    bodies: &[BodyState],
    manifolds: &mut [M],
    links: &SoftLinks<'_>,
    h: f64,
    settings: &SoftSettings,
) -> Result<SoftStep, ContactError> {
    let SoftLinks { joints, joint_warm, springs, windows, manifold_windows } = *links;
    settings.check()?;
    if !(h.is_finite() && h > 0.0) {
        return Err(ContactError::invalid("dt", format!("must be finite and > 0, got {h}")));
    }
    check_bodies(bodies)?;
    for (k, m) in manifolds.iter().enumerate() {
        m.borrow().check(k, bodies)?;
    }
    check_joints(bodies, joints, joint_warm, windows)?;
    checks::check_windows("manifold_windows", manifold_windows, manifolds.len())?;
    // each joint's weight on a substep's impulses a substep later (its window's decay)
    let substep = h / settings.substeps.max(1) as f64;
    let decay = |k: usize| windows.get(k).filter(|&&w| w > 0.0).map_or(1.0, |w| (-substep / w).exp());
    let decays: Vec<f64> = manifold_windows.iter().map(|&w| if w > 0.0 { (-substep / w).exp() } else { 1.0 }).collect();
    check_springs(bodies, springs)?;
    let clock = std::time::Instant::now();
    let views: Vec<&SoftManifold> = manifolds.iter().map(|m| m.borrow()).collect();
    let touching: Vec<usize> = (0..views.len()).filter(|&m| views[m].count > 0).collect();
    // islands of the manifolds with points, the joints and the springs
    let ends = touching
        .iter()
        .map(|&m| (views[m].a, views[m].b))
        .chain(joints.iter().map(|j| (j.a, j.b)))
        .chain(springs.iter().map(|s| (s.a, s.b)));
    let moves = |b: usize| bodies[b].is_dynamic();
    let (of_link, islands) = link_islands(bodies.len(), moves, ends.clone());
    // each island's lightest and heaviest moving body: an island of a large mass ratio converges
    let mut range = vec![(f64::INFINITY, 0.0f64); islands];
    for ((a, b), &i) in ends.zip(&of_link) {
        for m in [bodies[a].inv_mass, bodies[b].inv_mass].into_iter().filter(|&m| m > 0.0) {
            range[i] = (range[i].0.min(1.0 / m), range[i].1.max(1.0 / m));
        }
    }
    let mut joined = vec![false; islands];
    for &i in &of_link[touching.len()..] {
        joined[i] = true;
    }
    let converging: Vec<bool> = range
        .iter()
        .zip(&joined)
        .map(|(&(lo, hi), &joined)| {
            let limit = if joined { group::JOINED_MASS_RATIO } else { group::MASS_RATIO };
            lo > 0.0 && hi / lo > limit
        })
        .collect();
    // the groups, in island order: each island that converges on its own, each of a batch's points or more too, the
    // rest gathered into batches of about `BATCH_POINTS` (islands share no moving body: a batch's rows side by
    // side give the bits each gives alone, and a group's rows stay in the cache over all its substeps)
    let (nm, nj) = (touching.len(), joints.len());
    let mut island_points = vec![0usize; islands];
    for (k, &i) in of_link[..nm].iter().enumerate() {
        island_points[i] += views[touching[k]].count;
    }
    let mut place = vec![usize::MAX; islands];
    let mut specs: Vec<Spec> = Vec::new();
    let mut open: Option<(usize, usize)> = None;
    for i in 0..islands {
        if converging[i] || island_points[i] >= BATCH_POINTS {
            place[i] = specs.len();
            specs.push(Spec { converge: converging[i], ..Spec::default() });
            continue;
        }
        let (spec, points) = match open {
            Some(batch) => batch,
            None => {
                specs.push(Spec::default());
                (specs.len() - 1, 0)
            }
        };
        place[i] = spec;
        let points = points + island_points[i];
        open = (points < BATCH_POINTS).then_some((spec, points));
    }
    for (k, &i) in of_link.iter().enumerate() {
        let spec = &mut specs[place[i]];
        if k < nm {
            spec.manifolds.push(touching[k]);
        } else if k < nm + nj {
            // an island's joints together, islands in the order of their first joint
            match spec.joints.iter_mut().find(|set| of_link[nm + set[0]] == i) {
                Some(set) => set.push(k - nm),
                None => spec.joints.push(vec![k - nm]),
            }
        } else {
            spec.springs.push(k - nm - nj);
        }
    }
    let points = |spec: &Spec| spec.manifolds.iter().map(|&m| views[m].count).sum::<usize>();
    let size = |spec: &Spec| points(spec) + spec.joints.iter().map(Vec::len).sum::<usize>() + spec.springs.len();
    let threads = if settings.threads == 0 { cores() } else { settings.threads };
    // a group of many contact points is solved on all the threads, colour by colour; the others group by group on
    // them
    let whole = |spec: &Spec| threads > 1 && points(spec) >= COLOUR_THREADS;
    let solve = |spec: &Spec, threads: usize| -> Result<(Vec<usize>, Group, f64), ContactError> {
        LOCAL.with(|slots| {
            let clock = std::time::Instant::now();
            let slots = &mut *slots.borrow_mut();
            if slots.len() < bodies.len() {
                slots.resize(bodies.len(), usize::MAX);
            }
            // the group's bodies in order of first appearance (manifolds, joints, then springs), each given its place
            let mut members: Vec<usize> = Vec::new();
            let ends = spec.manifolds.iter().flat_map(|&m| [views[m].a, views[m].b]);
            let ends = ends.chain(spec.joints.iter().flatten().flat_map(|&k| [joints[k].a, joints[k].b]));
            for b in ends.chain(spec.springs.iter().flat_map(|&k| [springs[k].a, springs[k].b])) {
                if slots[b] == usize::MAX {
                    slots[b] = members.len();
                    members.push(b);
                }
            }
            let local = |b: usize| slots[b];
            let movers = members.iter().map(|&b| Mover::new(&bodies[b], settings.gyroscopic)).collect();
            let mut group = Group::new(movers, bodies, &views, &spec.manifolds, local, spec.converge, &decays);
            for set in &spec.joints {
                let placed = set.iter().map(|&k| {
                    let (j, xa, xb) = (&joints[k], bodies[joints[k].a].position, bodies[joints[k].b].position);
                    (JointConstraint { a: local(j.a), b: local(j.b), ..*j }, xa.coords, xb.coords)
                });
                let warm = set.iter().map(|&k| joint_warm[k]).collect();
                group.joints.push(JointSet::new(placed.collect(), warm, set.iter().map(|&k| decay(k)).collect()));
            }
            if !spec.springs.is_empty() {
                let placed = spec.springs.iter().map(|&k| {
                    let (s, xa, xb) = (&springs[k], bodies[springs[k].a].position, bodies[springs[k].b].position);
                    (SoftSpring { a: local(s.a), b: local(s.b), ..*s }, xa.coords, xb.coords)
                });
                group.springs = SpringSet::new(placed);
            }
            for &b in &members {
                slots[b] = usize::MAX;
            }
            let seconds = clock.elapsed().as_secs_f64();
            group.solve(h, settings, threads);
            Ok((members, group, seconds))
        })
    };
    let setup = clock.elapsed().as_secs_f64();
    let rest: Vec<&Spec> = specs.iter().filter(|s| !whole(s)).collect();
    let rows = rest.iter().map(|s| size(s)).sum();
    let mut rest = in_parallel_by(&rest, |s| size(s), (rows, COLOUR_THREADS), settings.threads, |s| solve(s, 1));
    let mut rest = rest.drain(..);
    let mut out = SoftStep {
        velocities: Vec::with_capacity(bodies.len()),
        displacements: vec![Vector3::zeros(); bodies.len()],
        rotations: vec![UnitQuaternion::identity(); bodies.len()],
        impulses: Vec::new(),
        normal_impulses: Vec::new(),
        joint_impulses: vec![JointImpulse::default(); joints.len()],
        joint_step_impulses: vec![JointImpulse::default(); joints.len()],
        manifold_impulses: vec![(Vector3::zeros(), Vector3::zeros()); manifolds.len()],
        manifold_peak_impulses: vec![(Vector3::zeros(), Vector3::zeros()); manifolds.len()],
        islands,
        residual: 0.0,
        prepare_seconds: setup,
        pushing: 0,
        collisions: 0,
    };
    let mut velocities: Vec<Option<BodyVelocity>> = vec![None; bodies.len()];
    let mut solved = Vec::with_capacity(specs.len());
    for spec in &specs {
        solved.push(if whole(spec) { solve(spec, threads) } else { rest.next().expect("one answer a group") });
    }
    drop(views);
    for (spec, result) in specs.iter().zip(solved) {
        let (members, group, seconds) = result?;
        for (&b, m) in members.iter().zip(&group.movers).filter(|(&b, _)| bodies[b].is_dynamic()) {
            velocities[b] = Some(BodyVelocity { linear: m.v, angular: m.w });
            out.displacements[b] = m.dp;
            out.rotations[b] = m.dq;
        }
        out.residual = out.residual.max(group.residual());
        out.prepare_seconds += seconds;
        out.take(&group, spec, manifolds, settings.bounce_threshold);
        group.give_back();
    }
    // bodies in no group (and static ones) move on their own, by the same substeps
    for (b, body) in bodies.iter().enumerate() {
        let v = velocities[b].unwrap_or_else(|| {
            let mut m = Mover::new(body, settings.gyroscopic);
            m.free(h, settings.substeps);
            out.displacements[b] = m.dp;
            out.rotations[b] = m.dq;
            BodyVelocity { linear: m.v, angular: m.w }
        });
        out.velocities.push(v);
    }
    Ok(out)
}

#[cfg(test)]
mod tests;

//! The test every answer to an island's program must pass (`residual`: the step's conditions to the solver's
//! tolerance, whichever method answered), the answer with no impulse at all (`untouched`) where it passes, and how
//! fast given velocities would close a contact (`closing`).

use super::island::{bias, row_layout, IslandSolution, Rows};
use super::settings::StepSettings;
use crate::body::BodyState;
use crate::contact::Contact;
use crate::impulse::{velocities_after, BodyVelocity};
use nalgebra::Vector3;

/// The island's answer when no contact needs an impulse: the free velocities with every impulse zero, if they
/// pass the test every answer of clarabel's must (`residual` within `complementarity_tolerance`). Zero impulses with
/// velocities the contacts accept are the program's optimum (the objective's unconstrained minimum is feasible), so
/// bodies that only touch (falling together, or resting on nothing) cost no solve.
pub(crate) fn untouched(
    bodies: &[BodyState],
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    island: &[usize],
    members: &[usize],
    free: &[BodyVelocity],
    s: &StepSettings,
) -> Option<IslandSolution> {
    let (layout, _) = row_layout(contacts, bounds, island, members.len());
    let out = IslandSolution {
        velocities: members.iter().map(|&k| (k, free[k])).collect(),
        normal: vec![0.0; island.len()],
        friction: vec![Vector3::zeros(); island.len()],
        iterations: 0,
        solved: false,
        newton: false,
        building_seconds: 0.0,
        joints: Vec::new(),
    };
    let r = residual(bodies, contacts, island, &layout, free, &out, s);
    // A caller's own velocity scale also bounds how far the free velocities may close a contact: relative to a
    // fast island's speeds, a step's fall under gravity (g h) looks small, and a box sliding at 2 m/s sank 1e-9 m
    // a step at h = 1e-5 s when only the relative test was made.
    let closing = island.iter().map(|&i| closing(&contacts[i], bodies, free, s)).fold(0.0f64, f64::max);
    let held = s.velocity_scale == 0.0 || closing <= s.solver.complementarity_tolerance * s.velocity_scale;
    (r <= s.solver.complementarity_tolerance && held).then_some(out)
}

/// How far an island's answer is from the conditions of the step, relative to its velocity scale V and impulse
/// scale P: momentum balance M (v - v*) = sum of contact impulses (per body, to P); the velocity constraint
/// n.v_rel + beta >= mu |v_rel,t| (cone) or >= 0 (otherwise), to V; the impulse bound |p_t| <= mu p_n (cone) or
/// <= mu p_prev (lagged), to P; and complementarity: p_n (n.v_rel + beta) + p_t . v_rel,t = 0 for the cone,
/// p_n (n.v_rel + beta) = 0 and maximal dissipation p_t . v_t = -mu p_prev |v_t| for lagged friction (to P V).
pub(crate) fn residual(
    bodies: &[BodyState],
    contacts: &[Contact],
    island: &[usize],
    layout: &[Rows],
    free: &[BodyVelocity],
    out: &IslandSolution,
    s: &StepSettings,
) -> f64 {
    // Work on the island's own bodies (a local copy, indices remapped): a world of thousands of bodies and
    // hundreds of islands would otherwise copy every body for every island.
    let mut local: Vec<usize> = island.iter().flat_map(|&i| [contacts[i].a, contacts[i].b]).collect();
    local.sort_unstable();
    local.dedup();
    let index = |k: &usize| local.binary_search(k).expect("a body of the island");
    let island_contacts: Vec<Contact> =
        island.iter().map(|&i| Contact { a: index(&contacts[i].a), b: index(&contacts[i].b), ..contacts[i] }).collect();
    let mut after: Vec<BodyVelocity> = local.iter().map(|&k| free[k]).collect();
    // bodies held only by joints are not the contacts' to judge
    let velocities: Vec<(usize, BodyVelocity)> =
        out.velocities.iter().filter(|(k, _)| local.binary_search(k).is_ok()).copied().collect();
    for (k, v) in &velocities {
        after[index(k)] = *v;
    }
    let bodies: Vec<BodyState> = local.iter().map(|&k| bodies[k]).collect();
    let state = |v: &[BodyVelocity]| -> Vec<BodyState> {
        bodies.iter().zip(v).map(|(b, v)| BodyState { velocity: v.linear, angular_velocity: v.angular, ..*b }).collect()
    };
    let free_local: Vec<BodyVelocity> = local.iter().map(|&k| free[k]).collect();
    let (moved, free_state) = (state(&after), state(&free_local));
    let bodies = &bodies[..];
    // The velocity scale: relative velocities and biases, and the speeds of the contact points themselves (two
    // bodies falling together touch at zero relative velocity and zero bias; their answer is judged against how fast
    // they move, at least the g h a step of gravity gives).
    let mut v_scale = s.velocity_scale.max(f64::MIN_POSITIVE);
    for c in &island_contacts {
        let (va, vb) = (free_state[c.a].point_velocity(&c.point), free_state[c.b].point_velocity(&c.point));
        v_scale = v_scale.max((vb - va).norm()).max(bias(c, bodies, s).abs()).max(va.norm()).max(vb.norm());
    }
    let p_scale = velocities
        .iter()
        .map(|(k, _)| v_scale / bodies[index(k)].inv_mass)
        .chain(out.normal.iter().copied())
        .fold(f64::MIN_POSITIVE, f64::max);
    let mut worst = 0.0f64;
    let impulses: Vec<Vector3<f64>> = island_contacts
        .iter()
        .enumerate()
        .map(|(slot, c)| c.normal.into_inner() * out.normal[slot] + out.friction[slot])
        .collect();
    let predicted = velocities_after(&free_state, &island_contacts, &impulses);
    for (k, v) in &velocities {
        let k = index(k);
        let b = &bodies[k];
        let dl = (v.linear - predicted[k].linear).norm() / b.inv_mass;
        let da = if b.rotates() { (b.inertia * (v.angular - predicted[k].angular)).norm() } else { 0.0 };
        let reach = island_contacts.iter().map(|c| (c.point - b.position).norm()).fold(1.0, f64::max);
        worst = worst.max(dl / p_scale).max(da / (p_scale * reach));
    }
    for (slot, c) in island_contacts.iter().enumerate() {
        let rel = moved[c.b].point_velocity(&c.point) - moved[c.a].point_velocity(&c.point);
        let n = c.normal.into_inner();
        let vn = n.dot(&rel) + bias(c, bodies, s);
        let vt = rel - n * n.dot(&rel);
        let (pn, pt) = (out.normal[slot], out.friction[slot]);
        // (velocity cone radius, impulse bound, complementarity terms)
        let (cone, bound, complementarity) = match layout[slot] {
            Rows::Frictionless => (0.0, 0.0, (pn * vn).abs()),
            Rows::Cone => (c.friction * vt.norm(), c.friction * pn, (pn * vn + pt.dot(&vt)).abs()),
            Rows::Lagged { bound, .. } => (0.0, bound, (pn * vn).abs().max((pt.dot(&vt) + bound * vt.norm()).abs())),
        };
        worst = worst
            .max((cone - vn) / v_scale)
            .max((pt.norm() - bound) / p_scale)
            .max(complementarity / (p_scale * v_scale));
    }
    worst
}

/// How fast velocities `v` would close contact `c` past its constraint: minus its normal velocity plus its bias
/// (positive: the constraint is broken).
pub(crate) fn closing(c: &Contact, bodies: &[BodyState], v: &[BodyVelocity], s: &StepSettings) -> f64 {
    let point = |k: usize| v[k].linear + v[k].angular.cross(&(c.point - bodies[k].position));
    -(c.normal.dot(&(point(c.b) - point(c.a))) + bias(c, bodies, s))
}

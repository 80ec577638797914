//! Fast mode's bounce energy limiter. A bounce in a time step can put energy in: Newton's law at several
//! simultaneous contacts (two corners of a rocking box, Kane's paradox), and a bounce started up to a step's travel
//! above the floor. An island that bounced and whose mechanical energy (kinetic plus gravity, at the positions the
//! step will reach) would end above where it started is solved again with its restitution scaled: by the largest
//! factor that keeps the energy, found by the secant method from the full answer and the one at 0.98 in up to three
//! more solves (a bounce begun a step's travel u h above the floor gains up to m g u h, about 2% of its energy at
//! 4 m/s and h = 1/240 s, so the factor is about 0.99), else by 0.9, 0.75, 0.5, 0.25 or 0.

use super::solve_velocities::Solver;
use crate::error::WorldError;
use nalgebra::Vector3;
use tumble_contact::{BodyState, BodyVelocity, Contact, VelocityStep};

/// Replaces in `out` the answer of every island (`groups`) whose bounce would gain energy.
pub(super) fn limit_bounce_energy(
    solver: &mut Solver<'_>,
    contacts: &[Contact],
    previous: &[f64],
    groups: &[Vec<usize>],
    g: Vector3<f64>,
    out: &mut VelocityStep,
) -> Result<(), WorldError> {
    let (h, threshold, states) = (solver.settings.dt, solver.settings.bounce_threshold, solver.states);
    for island in groups {
        let bounces = island
            .iter()
            .any(|&i| contacts[i].restitution > 0.0 && contacts[i].relative_normal_velocity(states) < -threshold);
        if !bounces {
            continue;
        }
        let members = island_bodies(states, contacts, island);
        let start: Vec<BodyVelocity> =
            states.iter().map(|b| BodyVelocity { linear: b.velocity, angular: b.angular_velocity }).collect();
        let energy = |v: &[BodyVelocity], dt: f64| {
            kinetic(states, v, &members)
                - members
                    .iter()
                    .map(|&k| g.dot(&(states[k].position.coords + v[k].linear * dt)) / states[k].inv_mass)
                    .sum::<f64>()
        };
        let e0 = energy(&start, 0.0);
        let limit = e0 + 1e-12 * e0.abs().max(kinetic(states, &start, &members));
        let e_one = energy(&out.velocities, h);
        if e_one <= limit {
            continue;
        }
        let mut solve_scaled = |scale: f64| {
            let sub: Vec<Contact> = island
                .iter()
                .map(|&i| Contact { restitution: contacts[i].restitution * scale, ..contacts[i] })
                .collect();
            let sub_prev: Vec<f64> = island.iter().map(|&i| previous[i]).collect();
            solver.solve(&sub, &sub_prev)
        };
        // The largest restitution scale that does not gain energy, by the secant method on the energy as a
        // function of the scale (smooth while restitution sets the bounce), from the full answer and the one at
        // 0.98; if no scale it tries keeps the energy, 0.9, 0.75, 0.5, 0.25 and the plastic answer.
        let at98 = solve_scaled(0.98)?;
        let e98 = energy(&at98.velocities, h);
        let mut best = (e98 <= limit).then_some((0.98, at98));
        let (mut a, mut b) = ((0.98, e98), (1.0, e_one));
        for _ in 0..3 {
            if b.1 == a.1 {
                break;
            }
            let scale = (a.0 + (limit - a.1) * (b.0 - a.0) / (b.1 - a.1)).clamp(0.0, 1.0) * (1.0 - 1e-9);
            let again = solve_scaled(scale)?;
            let e = energy(&again.velocities, h);
            if e <= limit && best.as_ref().is_none_or(|(s, _)| scale > *s) {
                best = Some((scale, again));
                if limit - e <= 1e-9 * limit.abs().max(1e-300) {
                    break;
                }
            }
            (a, b) = (b, (scale, e));
        }
        let mut chosen = best.map(|(_, v)| v);
        for scale in [0.9, 0.75, 0.5, 0.25, 0.0] {
            if chosen.is_some() {
                break;
            }
            let again = solve_scaled(scale)?;
            if energy(&again.velocities, h) <= limit || scale == 0.0 {
                chosen = Some(again);
            }
        }
        let Some(chosen) = chosen else { continue };
        for &k in &members {
            out.velocities[k] = chosen.velocities[k];
        }
        for (slot, &i) in island.iter().enumerate() {
            out.normal_impulses[i] = chosen.normal_impulses[slot];
            out.friction_impulses[i] = chosen.friction_impulses[slot];
        }
    }
    Ok(())
}

/// The moving bodies of an island.
fn island_bodies(states: &[BodyState], contacts: &[Contact], island: &[usize]) -> Vec<usize> {
    let mut members: Vec<usize> =
        island.iter().flat_map(|&i| [contacts[i].a, contacts[i].b]).filter(|&k| states[k].is_dynamic()).collect();
    members.sort_unstable();
    members.dedup();
    members
}

/// Kinetic energy of the bodies `members` at velocities v.
fn kinetic(states: &[BodyState], v: &[BodyVelocity], members: &[usize]) -> f64 {
    members
        .iter()
        .map(|&k| {
            let b = &states[k];
            0.5 * v[k].linear.norm_squared() / b.inv_mass + 0.5 * v[k].angular.dot(&(b.inertia * v[k].angular))
        })
        .sum()
}

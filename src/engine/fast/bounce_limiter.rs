//! Fast mode's bounce energy limiter. A bounce in a time step can put energy in: Newton's law at several
//! simultaneous contacts (two corners of a rocking box, Kane's paradox), and a bounce started up to a step's travel
//! above the floor. An island that bounced and whose mechanical energy (kinetic plus gravity, at the positions the
//! step will reach) would end above where it started is solved again with its restitution scaled by the largest
//! factor that keeps the energy (`bounce_scale.rs`; a bounce begun a step's travel u h above the floor gains up to
//! m g u h, about 2% of its energy at 4 m/s and h = 1/240 s, so the factor is about 0.99).

use super::solver::Solver;
use crate::engine::bounce_scale::{kinetic, largest_keeping_energy, moving_bodies};
use crate::error::WorldError;
use nalgebra::Vector3;
use tumble_contact::{BodyVelocity, Contact, VelocityStep};

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
        let members = moving_bodies(states, island.iter().map(|&i| &contacts[i]));
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
        let solve_scaled = |scale: f64| {
            let sub: Vec<Contact> = island
                .iter()
                .map(|&i| Contact { restitution: contacts[i].restitution * scale, ..contacts[i] })
                .collect();
            let sub_prev: Vec<f64> = island.iter().map(|&i| previous[i]).collect();
            solver.solve(&sub, &sub_prev).map(Some)
        };
        let chosen = largest_keeping_energy(e_one, limit, solve_scaled, |a: &VelocityStep| energy(&a.velocities, h))?;
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

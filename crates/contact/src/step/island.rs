//! One island of a velocity step, whichever method solves it: its answer (`IslandSolution`), each contact's rows,
//! the contacts' bias, and the velocities read from the unknowns or moved by joint impulses.

use super::problem::BilateralRow;
use super::settings::StepSettings;
use crate::body::BodyState;
use crate::contact::Contact;
use crate::impulse::BodyVelocity;
use nalgebra::Vector3;

pub(crate) struct IslandSolution {
    pub velocities: Vec<(usize, BodyVelocity)>,
    pub normal: Vec<f64>,
    pub friction: Vec<Vector3<f64>>,
    pub iterations: u32,
    /// Whether a solver was called (an island no contact of which needs an impulse is answered without one).
    pub solved: bool,
    /// Whether the Newton method gave the answer (not clarabel).
    pub newton: bool,
    /// Wall time spent building the island's programs (s).
    pub building_seconds: f64,
    /// The impulse of each of the island's joint rows (in the order given; empty without).
    pub joints: Vec<f64>,
}

/// How a contact's rows are laid out.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Rows {
    /// One nonnegative row.
    Frictionless,
    /// Anitescu's SOC(3) on (normal, mu t1, mu t2).
    Cone,
    /// A nonnegative normal row, then SOC(3) on (s, t1, t2) with epigraph variable `s` and bound `bound`.
    Lagged { s: usize, bound: f64 },
}

// (clarabel's program lays its rows out by width; the check reads only the kind)
#[cfg_attr(not(feature = "clarabel"), allow(dead_code))]
impl Rows {
    pub(crate) fn width(self) -> usize {
        match self {
            Rows::Frictionless => 1,
            Rows::Cone => 3,
            Rows::Lagged { .. } => 4,
        }
    }
}

/// Each contact's rows (lagged friction's epigraph variables numbered from `first_var`), and the variables in all.
pub(crate) fn row_layout(
    contacts: &[Contact],
    bounds: Option<&[f64]>,
    island: &[usize],
    first_var: usize,
) -> (Vec<Rows>, usize) {
    let mut vars = first_var;
    let layout = island
        .iter()
        .map(|&i| {
            let c = &contacts[i];
            match bounds {
                _ if c.friction == 0.0 => Rows::Frictionless,
                None => Rows::Cone,
                Some(b) if b[i] * c.friction > 0.0 => {
                    vars += 1;
                    Rows::Lagged { s: vars - 1, bound: b[i] * c.friction }
                }
                Some(_) => Rows::Frictionless,
            }
        })
        .collect();
    (layout, vars)
}

/// The constraint bias of a contact: speculative gap or penetration correction, and restitution.
pub(crate) fn bias(c: &Contact, bodies: &[BodyState], s: &StepSettings) -> f64 {
    let h = s.dt;
    let v_minus = c.relative_normal_velocity(bodies);
    let by_gap = if c.distance > 0.0 { c.distance / h } else { s.erp * c.distance / h };
    let closes_this_step = c.distance + h * v_minus <= 0.0;
    if c.restitution > 0.0 && v_minus < -s.bounce_threshold && closes_this_step {
        // The bounce at the step's start, then what the applied forces do to the normal velocity over the rest of
        // the step: a ball bouncing with e = 1 then keeps its energy to O(h^2) instead of gaining m g h v.
        let moved = |k: usize| {
            let f = super::problem::free_velocity(&bodies[k], s);
            BodyState { velocity: f.linear, angular_velocity: f.angular, ..bodies[k] }
        };
        let (a, b) = (moved(c.a), moved(c.b));
        let v_free = c.normal.dot(&(b.point_velocity(&c.point) - a.point_velocity(&c.point)));
        by_gap.min(c.restitution * v_minus - (v_free - v_minus))
    } else {
        by_gap
    }
}

/// The free velocities with the joint rows' impulses applied (what the contacts' conditions are judged against).
pub(crate) fn moved_by_joints(
    bodies: &[BodyState],
    bilateral: &[&BilateralRow],
    free: &[BodyVelocity],
    impulses: &[f64],
) -> Vec<BodyVelocity> {
    let mut moved = free.to_vec();
    for (r, &p) in bilateral.iter().zip(impulses) {
        for (k, lin, ang) in [(r.a, -r.lin, r.ang_a), (r.b, r.lin, r.ang_b)] {
            let b = &bodies[k];
            if b.is_dynamic() {
                moved[k].linear += lin * (p * b.inv_mass);
                moved[k].angular += b.inv_inertia * ang * p;
            }
        }
    }
    moved
}

/// Each member's velocities read from the unknowns x (3 for a particle, 6 for a rigid body, from `offset`).
pub(crate) fn velocities_of(
    bodies: &[BodyState],
    members: &[usize],
    offset: &[usize],
    x: &[f64],
) -> Vec<(usize, BodyVelocity)> {
    members
        .iter()
        .map(|&k| {
            let o = offset[k];
            let linear = Vector3::new(x[o], x[o + 1], x[o + 2]);
            let angular =
                if bodies[k].rotates() { Vector3::new(x[o + 3], x[o + 4], x[o + 5]) } else { Vector3::zeros() };
            (k, BodyVelocity { linear, angular })
        })
        .collect()
}

//! Rolling and torsional resistance as rows of the velocity step: each contact with a coefficient and a lagged
//! normal impulse p resists the bodies' relative turn with an angular impulse of at most the coefficient times p
//! times the rolling radius (`Contact::rolling_radius`), as far as it stops the turn (a motor row of target speed
//! zero, whose impulse is bounded, held in the same program as the contacts). Rolling is resisted along the axis
//! the bodies roll about at the step's start and across it, each bounded alone; torsion about the normal.

use crate::body::BodyState;
use crate::contact::{tangents, Contact};
use crate::friction::{BilateralKind, BilateralRow};
use nalgebra::Vector3;

/// The rows of contact `c` at lagged normal impulse `bound` (none without a coefficient, a bound, or a body that
/// turns).
pub(crate) fn resistance_rows(c: &Contact, bodies: &[BodyState], bound: f64, out: &mut Vec<BilateralRow>) {
    if bound <= 0.0 || (c.rolling_resistance == 0.0 && c.torsional_resistance == 0.0) {
        return;
    }
    let radius = c.rolling_radius(bodies);
    if radius == 0.0 {
        return;
    }
    let n = c.normal.into_inner();
    let turn = bodies[c.b].angular_velocity - bodies[c.a].angular_velocity;
    let across = turn - n * n.dot(&turn);
    // the axis the bodies roll about, if they roll, else any two across the normal
    let (u1, u2) = match across.try_normalize(1e-300) {
        Some(u) => (u, n.cross(&u)),
        None => tangents(&n),
    };
    let row = |axis: Vector3<f64>, max_impulse: f64| BilateralRow {
        a: c.a,
        b: c.b,
        lin: Vector3::zeros(),
        ang_a: -axis,
        ang_b: axis,
        speed: 0.0,
        kind: BilateralKind::Motor { max_impulse },
    };
    let rolling = c.rolling_resistance * radius * bound;
    if rolling > 0.0 {
        out.extend([row(u1, rolling), row(u2, rolling)]);
    }
    let torsion = c.torsional_resistance * radius * bound;
    if torsion > 0.0 {
        out.push(row(n, torsion));
    }
}

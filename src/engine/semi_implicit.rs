//! Positions from new velocities (semi-implicit Euler), shared by fast mode and accurate mode's contact steps.
//! Orientations turn by the new angular velocity; angular momentum is taken from the inertia the velocities were
//! solved with and scaled back so the turn does not raise the rotational energy. Accurate mode's states hold
//! momenta, fast mode's velocities (`Form`): a body's angular velocity after the turn is then its inertia there
//! inverse times that momentum.

use crate::model::layout::{get3, get_quat, set3, set_quat};
use crate::model::{BodyProps, Model};
use nalgebra::{UnitQuaternion, Vector3};
use tumble_collide::rotated_tensor;
use tumble_contact::{BodyVelocity, SoftStep};

/// What a state's rows after the positions hold: momenta (the world's state, accurate mode's) or velocities (fast
/// mode's, `model/velocities.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Form {
    Momenta,
    Velocities,
}

/// `turned_momentum`'s law for a state in velocity form: the angular velocity of body `b` turned from q0 to q1 at
/// angular velocity w, its momentum kept but scaled back so that the turn does not raise the rotational energy; in
/// the body's frames (three turns of a vector instead of two matrices built).
fn turned_velocity(
    b: &BodyProps,
    q0: &UnitQuaternion<f64>,
    q1: &UnitQuaternion<f64>,
    w: &Vector3<f64>,
) -> Vector3<f64> {
    let l = q0 * (b.inertia * q0.inverse_transform_vector(w));
    let before = 0.5 * l.dot(w);
    let local = q1.inverse_transform_vector(&l);
    let turned = b.inv_inertia * local;
    let after = 0.5 * local.dot(&turned);
    let scale = if after > before && after > 0.0 { (before / after).sqrt() } else { 1.0 };
    q1 * (turned * scale)
}

/// Semi-implicit Euler over h: every actor for which `moves(actor)` holds gets its position and orientation from
/// its new velocity `v[actor]`, and its momenta (or velocities, in `form`) from that velocity (actors: particles
/// first, then bodies).
#[allow(clippy::needless_range_loop)]
pub(crate) fn update_positions(
    m: &Model,
    y: &mut [f64],
    v: &[BodyVelocity],
    h: f64,
    form: Form,
    moves: impl Fn(usize) -> bool,
) {
    let l = m.layout;
    for i in 0..l.particles {
        if !moves(i) {
            continue;
        }
        let x = get3(y, l.px(i)) + v[i].linear * h;
        set3(y, l.px(i), &x);
        set3(y, l.pv(i), &v[i].linear);
    }
    for (j, b) in m.bodies.iter().enumerate() {
        let a = l.body_actor(j);
        if !moves(a) {
            continue;
        }
        let (lin, w) = (v[a].linear, v[a].angular);
        let x = get3(y, l.bx(j)) + lin * h;
        let q0 = UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
        let q1 = UnitQuaternion::from_scaled_axis(w * h) * q0;
        set3(y, l.bx(j), &x);
        set_quat(y, l.bq(j), &q1);
        match form {
            Form::Momenta => {
                set3(y, l.bp(j), &(lin * b.mass));
                set3(y, l.bl(j), &turned_momentum(b, &q0, &q1, &w));
            }
            Form::Velocities => {
                set3(y, l.bp(j), &lin);
                set3(y, l.bl(j), &turned_velocity(b, &q0, &q1, &w));
            }
        }
    }
}

/// The poses and velocities of a soft step (whose substeps moved the actors) into fast mode's state (velocity
/// form): every actor for which `moves(actor)` holds is displaced and turned as the step says, with its new
/// velocity, and its angular velocity that of its angular momentum where it ends: the momentum from the inertia at
/// the step's start, scaled as in `update_positions` so the turn gains no energy; a jointed body's angular velocity
/// as its rows left it (they turned its inertia with it). Keeping a jointed body's momentum from the start's inertia
/// fed a whipping chain's thin links a spin about their own axes until it blew up.
pub(crate) fn apply_moves(m: &Model, y: &mut [f64], out: &SoftStep, moves: impl Fn(usize) -> bool) {
    let l = m.layout;
    let jointed = m.jointed_bodies();
    for i in (0..l.particles).filter(|&i| moves(i)) {
        let x = get3(y, l.px(i)) + out.displacements[i];
        set3(y, l.px(i), &x);
        set3(y, l.pv(i), &out.velocities[i].linear);
    }
    for (j, b) in m.bodies.iter().enumerate() {
        let a = l.body_actor(j);
        if !moves(a) {
            continue;
        }
        let (lin, w) = (out.velocities[a].linear, out.velocities[a].angular);
        let x = get3(y, l.bx(j)) + out.displacements[a];
        let q0 = UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
        let q1 = out.rotations[a] * q0;
        set3(y, l.bx(j), &x);
        set_quat(y, l.bq(j), &q1);
        // a jointed body's velocities come from rows that turned its inertia with it (and its spin kept its
        // momentum over each substep): its angular velocity stays
        if jointed.get(j).copied().unwrap_or(false) {
            set3(y, l.bp(j), &lin);
            set3(y, l.bl(j), &w);
        } else {
            set3(y, l.bp(j), &lin);
            set3(y, l.bl(j), &turned_velocity(b, &q0, &q1, &w));
        }
    }
}

/// The angular momentum of body `b` turned from q0 to q1 at angular velocity w: L from the inertia the velocities
/// were solved with (at q0). Turning the body under a fixed L raises 1/2 L . I(q)^-1 L at second order in the turn
/// (the second derivative is (w x L) . I^-1 (w x L) >= 0), a steady gain for a fast spin; scaling L back to the
/// energy before the turn removes it.
fn turned_momentum(
    b: &BodyProps,
    q0: &UnitQuaternion<f64>,
    q1: &UnitQuaternion<f64>,
    w: &nalgebra::Vector3<f64>,
) -> nalgebra::Vector3<f64> {
    let r0 = q0.to_rotation_matrix().into_inner();
    let mut momentum = rotated_tensor(&r0, &b.inertia) * w;
    let r1 = q1.to_rotation_matrix().into_inner();
    let before = 0.5 * momentum.dot(w);
    let after = 0.5 * momentum.dot(&(rotated_tensor(&r1, &b.inv_inertia) * momentum));
    if after > before && after > 0.0 {
        momentum *= (before / after).sqrt();
    }
    momentum
}

//! What a contact step's error estimate looks at beyond the halves' difference (`touching.rs`): the slip a sliding
//! contact's stop may have cut short, how deep a state sinks a contact, the momenta the energy guard weighs, and the
//! two ways a state is made from others (the extrapolation of the halves, and the interpolation frames take).

use crate::engine::found_contact::{ContactKey, FoundContact};
use crate::model::layout::{get3, get_quat, set_quat};
use crate::model::Model;
use nalgebra::{Quaternion, Vector3};
use std::collections::BTreeMap;

/// A sliding contact's stop inside a step (its slip fallen more than a thousandfold from the step's start,
/// `before`, to its end, `after`): semi-implicit Euler stops it at the step's start, so the slip it cuts short is
/// half the start slip times the time to the stop, and step doubling cannot see it when both the step and its halves
/// stop. The time to the stop is read from the whole step's friction: of the friction a pair's contacts could give
/// over the step (mu times the normal force, summed), the part they gave (summed as vectors) stopped them, so at a
/// steady deceleration the stop came at that fraction of the step (`wrenches`: each contact's force, normal and
/// friction, on B). A contact apart by more than `apart` at the start (an impact inside the step, which the halves'
/// estimate governs) has no slide to stop: the share its friction gave is not a stop's time (a 29 g piece struck
/// against the floor at 4 m/s was cut at 0.2 of every step that reached the floor, steps of 1e-8 s).
pub(super) struct Stop {
    /// The slip cut short per second of the step (0 when no sliding contact stopped).
    pub slip: f64,
    /// The earliest stop, as a fraction of the step (1 when none stopped).
    pub at: f64,
}

pub(super) fn stopped_slip(
    found: &[FoundContact],
    before: &[tumble_contact::BodyState],
    after: &[tumble_contact::BodyState],
    wrenches: &BTreeMap<ContactKey, Vector3<f64>>,
    apart: f64,
) -> Stop {
    let slip = |states: &[tumble_contact::BodyState], c: &tumble_contact::Contact| {
        let rel = states[c.b].point_velocity(&c.point) - states[c.a].point_velocity(&c.point);
        let n = c.normal.into_inner();
        (rel - n * n.dot(&rel)).norm()
    };
    // per pair of actors: the friction given (summed as vectors: a stuck pair's redundant points may push against
    // each other) and the friction there was to give
    let mut pairs: BTreeMap<(usize, usize), (Vector3<f64>, f64)> = BTreeMap::new();
    for f in found.iter().filter(|f| f.contact.friction > 0.0) {
        let (c, w) = (&f.contact, wrenches.get(&f.key).copied().unwrap_or_default());
        let n = c.normal.into_inner();
        let e = pairs.entry((c.a, c.b)).or_default();
        e.0 += w - n * n.dot(&w);
        e.1 += c.friction * n.dot(&w).max(0.0);
    }
    let mut stop = Stop { slip: 0.0, at: 1.0 };
    for c in found.iter().map(|f| &f.contact).filter(|c| c.friction > 0.0 && c.distance <= apart) {
        let (start, end) = (slip(before, c), slip(after, c));
        if start > 1e3 * end {
            let (given, bound) = pairs[&(c.a, c.b)];
            let at = if bound > 0.0 { (given.norm() / bound).clamp(0.0, 1.0) } else { 1.0 };
            stop.slip = stop.slip.max(0.5 * start * at);
            stop.at = stop.at.min(at);
        }
    }
    stop
}

/// How much deeper than at the step's start (state `from`) any contact of `found` is in state `to`: each contact
/// point carried with its two bodies' rigid motion (translation and the exact turn of their orientations, so a
/// turning body's corner follows its arc), taken along the normal. Zero when no contact sank.
pub(super) fn sinking(model: &Model, found: &[FoundContact], from: &[f64], to: &[f64]) -> f64 {
    let l = model.layout;
    let moved = |actor: usize, p: &nalgebra::Point3<f64>| -> nalgebra::Vector3<f64> {
        if actor < l.particles {
            get3(to, l.px(actor)) - get3(from, l.px(actor))
        } else if actor < l.actors() {
            let j = actor - l.particles;
            let (x0, x1) = (get3(from, l.bx(j)), get3(to, l.bx(j)));
            let q = |y: &[f64]| nalgebra::UnitQuaternion::from_quaternion(get_quat(y, l.bq(j)));
            let turn = q(to) * q(from).inverse();
            let r = p.coords - x0;
            x1 - x0 + (turn * r - r)
        } else {
            nalgebra::Vector3::zeros()
        }
    };
    found
        .iter()
        .map(|f| {
            let c = &f.contact;
            let gap = c.distance + c.normal.dot(&(moved(c.b, &c.point) - moved(c.a, &c.point)));
            ((-gap) - (-c.distance).max(0.0)).max(0.0)
        })
        .fold(0.0, f64::max)
}

/// The sum of the `involved` actors' momentum magnitudes in state y (kg m/s).
pub(super) fn momenta(model: &Model, involved: &[bool], y: &[f64]) -> f64 {
    let l = model.layout;
    let particles: f64 = model
        .particles
        .iter()
        .enumerate()
        .filter(|(i, _)| involved[*i])
        .map(|(i, p)| p.mass * get3(y, l.pv(i)).norm())
        .sum();
    let bodies: f64 =
        (0..model.bodies.len()).filter(|j| involved[l.body_actor(*j)]).map(|j| get3(y, l.bp(j)).norm()).sum();
    particles + bodies
}

/// The frame a fraction `s` of the way through a contact step from `a` to `b`. Positions move on the step's straight
/// path (semi-implicit Euler moves them at one velocity across the step), orientations blended and normalised; each
/// actor's momenta are blended and then scaled so that its kinetic energy is the same blend of its kinetic energies
/// at the step's ends. A frame's energy therefore lies on the line between the energies of the two states the
/// engine took (exactly under gravity; a spring's energy bends with its length), never above the greater: a blend
/// of momenta alone dips below that line (a bounce inside a step passes near zero momentum), and the frames after
/// the dip would read as energy gained.
pub(super) fn interpolate(model: &Model, a: &[f64], b: &[f64], s: f64) -> Vec<f64> {
    let mut y: Vec<f64> = a.iter().zip(b).map(|(x, z)| x + s * (z - x)).collect();
    let l = model.layout;
    for j in 0..model.bodies.len() {
        let q = get_quat(&y, l.bq(j));
        set_quat(&mut y, l.bq(j), &nalgebra::UnitQuaternion::from_quaternion(q));
    }
    for actor in 0..l.actors() {
        let (start, end) = (model.actor_kinetic_energy(a, actor), model.actor_kinetic_energy(b, actor));
        let target = start + s * (end - start);
        let blended = model.actor_kinetic_energy(&y, actor);
        // (momenta that cancel in the blend take the end's direction)
        let (from, scale) = if blended > 1e-300 {
            (None, (target / blended).sqrt())
        } else if end > 1e-300 {
            (Some(b), (target / end).sqrt())
        } else {
            continue;
        };
        for k in momentum_rows(model, actor) {
            y[k] = scale * from.map_or(y[k], |b| b[k]);
        }
    }
    y
}

/// The indices of an actor's momentum rows in the state: a particle's velocity, a body's linear and angular
/// momenta.
pub(super) fn momentum_rows(model: &Model, actor: usize) -> Vec<usize> {
    let l = model.layout;
    if actor < l.particles {
        (l.pv(actor)..l.pv(actor) + 3).collect()
    } else {
        let j = actor - l.particles;
        (l.bp(j)..l.bp(j) + 3).chain(l.bl(j)..l.bl(j) + 3).collect()
    }
}

/// y <- 2 y - other (Richardson extrapolation of the two half steps against the whole one); quaternions aligned
/// in sign first and normalised after.
pub(super) fn extrapolate(model: &Model, y: &mut [f64], other: &[f64]) {
    for (v, o) in y.iter_mut().zip(other) {
        *v = 2.0 * *v - o;
    }
    let l = model.layout;
    for j in 0..model.bodies.len() {
        // undo the plain formula on the quaternion and redo it with the signs aligned
        let k = l.bq(j);
        let e = get_quat(y, k);
        let o = get_quat(other, k);
        let half: Quaternion<f64> = (e + o) * 0.5;
        let o = if half.dot(&o) < 0.0 { -o } else { o };
        let q = half * 2.0 - o;
        let n = q.norm();
        set_quat(y, k, &nalgebra::UnitQuaternion::from_quaternion(if n > 0.0 { q } else { half }));
    }
}

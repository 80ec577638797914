//! How far a contact step may carry a touching pair: a share of the smaller shape's size along the contact, and a
//! turn against each other (the contacts' manifolds hold only while their points stay on the faces they were found
//! on).

use super::contact_stages::ContactStages;
use crate::engine::found_contact::FoundContact;

/// How far a contact step may slide a touching pair, as a share of the smaller shape's bounding radius.
const SLIDE_SHARE: f64 = 0.1;
/// How far a contact step may turn a touching pair against each other (rad), unless both are balls.
const TURN_LIMIT: f64 = 0.1;

/// The longest step that slides no touching pair of `found` (at its relative tangential speed at the contact
/// point) more than `SLIDE_SHARE` of its smaller shape's radius (pairs with a half-space, whose face has no edge,
/// excepted) and turns none more than `TURN_LIMIT` against each other (a ball's own turn not counted); pairs apart
/// by more than the tolerance are not limited.
pub(super) fn slide_limit(cx: &ContactStages<'_>, found: &[FoundContact], states: &[tumble_contact::BodyState]) -> f64 {
    let mut limit = f64::INFINITY;
    let touching = cx.memory.scales.tolerance.max(cx.settings.contact_distance);
    for f in found {
        let (ca, cb) = f.key.colliders;
        let (ra, rb) = (cx.collider_set.colliders[ca as usize].radius, cx.collider_set.colliders[cb as usize].radius);
        let c = &f.contact;
        if c.distance > touching {
            continue;
        }
        let v = states[c.a].point_velocity(&c.point) - states[c.b].point_velocity(&c.point);
        let speed = (v - c.normal.into_inner() * c.normal.dot(&v)).norm();
        if speed > 0.0 && ra.max(rb).is_finite() {
            limit = limit.min(SLIDE_SHARE * ra.min(rb) / speed);
        }
        // a pair that turns against each other brings other points of its shapes into contact (a domino tipping on
        // its edge), which a step's contacts, found at its start, do not hold; a ball's own turn changes nothing (a
        // ball rolling on the floor is not limited), so against a ball the other shape's turn counts
        let round =
            |k: u32| matches!(cx.collider_set.colliders[k as usize].shape, tumble_collide::Shape::Sphere { .. });
        let (wa, wb) = (states[c.a].angular_velocity, states[c.b].angular_velocity);
        let turn = match (round(ca), round(cb)) {
            (true, true) => 0.0,
            (true, false) => wb.norm(),
            (false, true) => wa.norm(),
            (false, false) => (wa - wb).norm(),
        };
        if turn > 0.0 {
            limit = limit.min(TURN_LIMIT / turn);
        }
    }
    limit
}

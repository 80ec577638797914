//! Broken joints in an engine: the flags its memory keeps, put into the model (whose rows leave a broken joint
//! out) and the collider set (whose joined pairs, never tested, no longer include a broken joint's bodies).

use crate::engine::collider_set::ColliderSet;
use crate::model::Model;

/// Gives the model and the collider set these broken flags (one per joint), or says why they do not fit.
pub(crate) fn set_broken(
    model: &mut Model,
    collider_set: Option<&mut ColliderSet>,
    broken: &[bool],
) -> Result<(), String> {
    model.set_broken_joints(broken)?;
    if let Some(collider_set) = collider_set {
        collider_set.set_joined(model.joined_pairs());
    }
    Ok(())
}

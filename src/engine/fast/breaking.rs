//! Fast mode's joint-breaking stage, after the soft step: each breakable joint's load from its rows' impulses of
//! the last substep over the substep (Box2D's joint force: what the joint carried at the step's end); a joint past
//! its bounds breaks, holding nothing from the next step on, and its bodies collide again.

use super::step::StepContext;
use crate::engine::breaking::set_broken;

/// Breaks the joints the step took past their bounds (substeps of `substep` s); gives them, in order.
pub(super) fn break_joints(cx: &mut StepContext<'_>, substep: f64) -> Vec<usize> {
    if !cx.model.can_break() {
        return Vec::new();
    }
    let (rows, ends) = cx.model.all_rows(&cx.memory.y, false);
    let warm = &cx.memory.joint_warm;
    let loads = cx.model.joint_loads(&rows, &ends, |i, r| warm[rows[i].0].0[r.slot] / substep);
    let broken = cx.model.overloaded(&loads);
    if broken.is_empty() {
        return broken;
    }
    for &k in &broken {
        cx.memory.broken[k] = true;
        cx.memory.joint_warm[k] = Default::default();
    }
    set_broken(cx.model, cx.scene.as_deref_mut(), &cx.memory.broken).expect("one flag per joint");
    broken
}

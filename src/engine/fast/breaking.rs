//! Fast mode's joint-breaking stage, after the soft step: each breakable joint's load from its rows' impulses of
//! the last substep over the substep (Box2D's joint force: what the joint carried at the step's end), or, for a
//! joint with a window, its load averaged over the window, brought on substep by substep by the impulses it
//! carried (`Model::judged_loads`), a struck glued object's welds at the blow's peak (`Model::judge_peaks`); a
//! joint past its bounds breaks, holding nothing from the next step on, and its bodies collide again.

use super::context::StepContext;
use super::soft_solve::Solved;
use crate::engine::breaking::set_broken;
use crate::model::breaking::JointLoad;
use std::collections::BTreeMap;
use tumble_contact::JointImpulse;

/// Breaks the joints the step of `h` took past their bounds (substeps of `substep` s; `solved`: the soft step's
/// answer, with each joint it solved as rows and its impulses over the step, weighed substep by substep by its
/// window, and each glued weld's load over the step); gives them, in order.
pub(super) fn break_joints(cx: &mut StepContext<'_>, solved: &Solved, substep: f64, h: f64) -> Vec<usize> {
    if !cx.model.can_break() {
        return Vec::new();
    }
    let (rows, ends) = cx.model.all_rows(&cx.memory.y, false);
    let warm = &cx.memory.joint_warm;
    let mut loads = cx.model.joint_loads(&rows, &ends, |i, r| warm[rows[i].0].0[r.slot] / substep);
    // a glued weld's load at the instant is its load over the step (its impulse, weighed as a joint's, over h)
    for (&k, carried) in &solved.glued {
        loads[k] = JointLoad { force: carried.force / h, torque: carried.torque / h };
    }
    if cx.model.has_break_windows() {
        let mut by_joint = vec![JointImpulse::default(); cx.model.joints.len()];
        for (&k, p) in solved.rows.iter().zip(&solved.out.joint_step_impulses) {
            by_joint[k] = *p;
        }
        let mut over_step = cx.model.joint_loads(&rows, &ends, |i, r| by_joint[rows[i].0].0[r.slot]);
        for (&k, carried) in &solved.glued {
            over_step[k] = *carried;
        }
        // the struck welds' averages before the step, which the peaks are brought on from
        let before: BTreeMap<usize, JointLoad> = solved
            .glued_peaks
            .keys()
            .map(|&k| (k, cx.memory.load_averages.get(k).copied().unwrap_or_default()))
            .collect();
        loads = cx.model.judged_loads(&mut cx.memory.load_averages, &loads, &over_step, h, substep);
        cx.model.judge_peaks(&mut loads, &before, &solved.glued_peaks, h, substep);
    }
    let broken = cx.model.overloaded(&loads);
    if broken.is_empty() {
        return broken;
    }
    for &k in &broken {
        cx.memory.broken[k] = true;
        cx.memory.joint_warm[k] = Default::default();
    }
    set_broken(cx.model, cx.collider_set.as_deref_mut(), &cx.memory.broken).expect("one flag per joint");
    broken
}

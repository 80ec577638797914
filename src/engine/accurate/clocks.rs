//! Islands on their own clocks (after Mirtich's "Timewarp rigid body simulation", 2000): from one sync time to the
//! next (every 1/60 s, whatever the frames: recording frames changes nothing), the touching phase splits the actors
//! into groups that cannot meet within that span (the components of the pairs
//! within reach over it, springs joining too); where two groups or more have awake actors, each group is advanced to
//! the frame alone, by its own contact steps under its own error control, with every other actor held still (which
//! changes nothing: no pair between groups is within reach), and the groups meet at the sync time; a frame inside
//! takes each group's actors from that group's own steps. Each group keeps its
//! step size from one span to the next (`TouchingPhase::clocks`, by its first actor). So ten boxes that land at ten
//! different times cost ten boxes' steps, not every box at the step the busiest needs. The groups are advanced in
//! the order of their first actor, so the bits are the same on any thread count. Worlds with joints keep one clock,
//! and so do worlds of more than `MAX_ACTORS` actors and spans with more than `MAX_CLOCKS` groups. The sync times
//! are `sync.rs`'s. This module is above the touching phase's steps (`touching.rs`), which it runs for each group:
//! they reach `own_clocks` only through the advance's `Until::own_clocks`.

use super::contact_stages::ContactStages;
use super::convex_step::{actors_with_forces, every_contact_in_reach};
use super::free_flight::{copy_free, links};
use super::sleep::Sleep;
use super::sync::next_sync;
use super::system::AccurateSystem;
use super::touching::{touching_steps, Until};
use super::touching_phase::TouchingPhase;
use crate::engine::failure::failure;
use crate::engine::frames::FrameCursor;
use crate::engine::Budget;
use crate::run::Run;
use std::collections::BTreeMap;
use tumble_integrate::OdeError;

/// Most groups, and most actors, on their own clocks. A group's steps still do the whole state's bookkeeping (its
/// forces, the broad phase, the positions: a share of every actor's cost a step), so in a large world, or with many
/// small groups, they cost more than one clock saves: 100 boxes dropped apart took 1.30 s on their own clocks (0.73 s
/// with at most 16 groups) and 0.55 s on one; ten took 0.049 s against 0.070 s. Past these, one clock.
const MAX_CLOCKS: usize = 16;
const MAX_ACTORS: usize = 64;

/// The groups of actors that cannot meet over [t, t + span] and have awake actors, each its actors in increasing
/// order, the groups in the order of their first actor (actors in no pair and awake join the first group); None
/// unless there are two or more, and at most `MAX_CLOCKS` of them among at most `MAX_ACTORS` actors.
fn clock_groups(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    sleep: &Sleep,
    (t, y, span): (f64, &[f64], f64),
) -> Result<Option<Vec<Vec<usize>>>, OdeError> {
    let l = system.model.layout;
    let actors = l.actors();
    if actors > MAX_ACTORS {
        return Ok(None);
    }
    let states = actors_with_forces(system, statics, t, y)?;
    let (_, every) = every_contact_in_reach(cx, &system.model, &states, y, t, span)?;
    let pairs = every.iter().map(|f| (f.contact.a, f.contact.b)).chain(links(&system.model));
    let (island, count) = tumble_contact::body_islands(actors + statics.len(), |k| k < actors, pairs);
    let awake = |k: usize| !sleep.resting_actor(k);
    // the pairless actors are islands of their own: the awake ones join the first group with awake actors
    let mut paired = vec![false; count];
    for f in &every {
        for k in [f.contact.a, f.contact.b] {
            if k < actors {
                paired[island[k]] = true;
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = vec![Vec::new(); count];
    let mut loose = Vec::new();
    for k in 0..actors {
        if paired[island[k]] {
            groups[island[k]].push(k);
        } else if awake(k) {
            loose.push(k);
        }
    }
    let mut groups: Vec<Vec<usize>> = groups.into_iter().filter(|g| g.iter().any(|&k| awake(k))).collect();
    if groups.len() < 2 || groups.len() > MAX_CLOCKS {
        return Ok(None);
    }
    groups.sort_by_key(|g| g[0]);
    groups[0].extend(loose);
    groups[0].sort_unstable();
    Ok(Some(groups))
}

/// The touching phase's span on own clocks from (t, y) to the next sync time (at most `end`), if the actors split into
/// groups (`clock_groups`) that stay apart: the time and state reached, each frame inside recorded into `run` from
/// its groups' own steps; None where one clock takes the span (one group, or groups that met after all).
#[allow(clippy::too_many_arguments)]
pub(super) fn own_clocks(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    statics: &[nalgebra::Isometry3<f64>],
    phase: &mut TouchingPhase,
    (t, y, end): (f64, &[f64], f64),
    frames: &mut FrameCursor<'_>,
    mut run: Option<&mut Run>,
    budget: &mut Budget<'_>,
) -> Result<Option<(f64, Vec<f64>)>, OdeError> {
    let meet = next_sync(t).min(end);
    if meet <= t + frames.slack() {
        return Ok(None);
    }
    let Some(groups) = clock_groups(cx, system, statics, &phase.sleep, (t, y, meet - t))? else { return Ok(None) };
    let inside = frames.rest().partition_point(|&s| s < meet - frames.slack());
    let times = &frames.rest()[..inside];
    let Some((next, states)) = advance_groups(cx, system, phase, &groups, statics, (t, y, meet), times, budget)? else {
        return Ok(None);
    };
    for (s, state) in states {
        if let Some(run) = run.as_deref_mut() {
            let contacts = phase.last.iter().map(|c| (c.point, c.normal));
            run.record(&system.model, s, &state, cx.memory.penetration, contacts);
        }
        frames.advance();
    }
    Ok(Some((meet, next)))
}

/// Advances each of `groups` from (t, y) to `end` on its own clock (the module's scheme), the others held still;
/// the phase carries on with the groups' contacts, sleep and step sizes. Returns the state at `end` and at each of
/// the frame `times` inside, each group's actors from its own steps; or None, the phase untouched, where two groups
/// met after all (a collision inside a group threw a body farther than its speed at the start said: the reach is
/// judged at the start), to be taken again on one clock.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn advance_groups(
    cx: &mut ContactStages<'_>,
    system: &mut AccurateSystem,
    phase: &mut TouchingPhase,
    groups: &[Vec<usize>],
    statics: &[nalgebra::Isometry3<f64>],
    (t, y, end): (f64, &[f64], f64),
    times: &[f64],
    budget: &mut Budget<'_>,
) -> Result<Option<(Vec<f64>, Vec<(f64, Vec<f64>)>)>, OdeError> {
    let l = system.model.layout;
    let actors = l.actors();
    let mut group_of = vec![usize::MAX; actors];
    for (g, members) in groups.iter().enumerate() {
        members.iter().for_each(|&k| group_of[k] = g);
    }
    // each collider's group (usize::MAX: a static's, or an actor's in no group)
    let collider_group: Vec<usize> = (0..cx.collider_set.colliders.len())
        .map(|c| cx.collider_set.actor_of_collider(c).filter(|&a| a < actors).map_or(usize::MAX, |a| group_of[a]))
        .collect();
    let key_group = |key: &crate::engine::found_contact::ContactKey| {
        let of = |c: u32| collider_group.get(c as usize).copied().unwrap_or(usize::MAX);
        [of(key.colliders.0), of(key.colliders.1)].into_iter().find(|&g| g != usize::MAX)
    };
    let mut next = y.to_vec();
    let mut frames: Vec<(f64, Vec<f64>)> = times.iter().map(|&s| (s, y.to_vec())).collect();
    let (mut lagged, mut warm, mut last) = (BTreeMap::new(), BTreeMap::new(), Vec::new());
    let mut sleep = phase.sleep.clone();
    let mut clocks = BTreeMap::new();
    let mut penetration = 0.0f64;
    let mut smallest = f64::INFINITY;
    for (g, members) in groups.iter().enumerate() {
        let others: Vec<bool> = (0..actors).map(|k| group_of[k] != g).collect();
        let mut held = phase.sleep.clone();
        held.held = (0..actors).filter(|&k| others[k] || phase.sleep.is_held(k)).collect();
        let h = phase.clocks.get(&members[0]).copied().unwrap_or(phase.h);
        cx.memory.touching = Some(TouchingPhase {
            lagged: phase.lagged.iter().filter(|(k, _)| key_group(k) == Some(g)).map(|(k, v)| (*k, *v)).collect(),
            h,
            window: (f64::NAN, 0),
            free: None,
            last: phase.last.iter().filter(|c| group_of.get(c.a).or(group_of.get(c.b)) == Some(&g)).cloned().collect(),
            difference: None,
            sleep: held,
            warm: phase.warm.iter().filter(|(k, _)| key_group(k) == Some(g)).map(|(k, v)| (*k, *v)).collect(),
            at: None,
            clocks: BTreeMap::new(),
            synced: phase.synced,
        });
        let mut cursor = FrameCursor::new(times, end);
        let until = Until { end, pause: end, own_clocks: None };
        let out = touching_steps(cx, system, (t, y.to_vec()), until, &mut cursor, None, budget)?;
        let sub = cx.memory.touching.take().unwrap_or_else(|| unreachable_phase(phase));
        if out.frames.len() != times.len() || out.t < end - cursor.slack() {
            return Err(failure(
                t,
                format!("a group's advance to {end:e} s stopped at {:e} s (an engine fault)", out.t),
            ));
        }
        copy_free(&system.model, &others, &out.y, &mut next);
        for ((_, frame), (_, state)) in frames.iter_mut().zip(&out.frames) {
            copy_free(&system.model, &others, state, frame);
        }
        lagged.extend(sub.lagged);
        warm.extend(sub.warm);
        last.extend(sub.last);
        clocks.insert(members[0], sub.h);
        smallest = smallest.min(sub.h);
        penetration = penetration.max(cx.memory.penetration);
        sleep.take_group(&sub.sleep, members);
    }
    // did two groups meet? (any pair of actors of two groups within the contact tolerance at the end)
    let states = actors_with_forces(system, statics, end, &next)?;
    let (_, every) = every_contact_in_reach(cx, &system.model, &states, &next, end, 0.0)?;
    let near = cx.memory.scales.tolerance;
    let crossed = |a: usize, b: usize| a < actors && b < actors && group_of[a] != group_of[b];
    if every.iter().any(|f| crossed(f.contact.a, f.contact.b) && f.contact.distance <= near) {
        return Ok(None);
    }
    phase.lagged = lagged;
    phase.warm = warm;
    phase.last = last;
    phase.sleep = sleep;
    phase.clocks = clocks;
    phase.h = smallest;
    phase.difference = None;
    phase.free = None;
    cx.memory.penetration = penetration;
    Ok(Some((next, frames)))
}

/// The phase a group's advance left (it always leaves one: its held actors keep it going to its end).
fn unreachable_phase(phase: &TouchingPhase) -> TouchingPhase {
    TouchingPhase { clocks: BTreeMap::new(), ..phase.clone() }
}

impl Sleep {
    /// Takes the sleep of the actors `members` (increasing) from `group`'s (their advance's), keeping the rest.
    fn take_group(&mut self, group: &Sleep, members: &[usize]) {
        let mine = |k: &usize| members.binary_search(k).is_ok();
        self.resting_since.retain(|(k, _)| !mine(k));
        self.resting_since.extend(group.resting_since.iter().filter(|(k, _)| mine(k)).copied());
        self.resting_since.sort_unstable_by_key(|(k, _)| *k);
        self.islands.retain(|i| !i.iter().any(mine));
        self.islands.extend(group.islands.iter().filter(|i| i.iter().all(mine)).cloned());
        self.held.retain(|k| !mine(k));
        self.held.extend(group.held.iter().copied().filter(mine));
        self.held.sort_unstable();
    }
}

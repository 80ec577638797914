//! Fast mode's contacts of a step: the pairs of colliders that can close on each other within the step (their
//! relative speed and spins), and their contacts, either computed afresh (the exact solver's) or kept from step to
//! step in the contact pairs (the soft step's), the narrow phase shared out among the workers.

use crate::engine::collider_set::ColliderSet;
use crate::engine::contact_pairs::{ContactPairs, Pair};
use crate::engine::contact_reduction::{reduce, reduce_indices};
use crate::engine::found_contact::FoundContact;
use nalgebra::{Isometry3, Vector3};
use tumble_collide::contacts;

/// Pairs from which the narrow phase is shared out among the workers.
const PARALLEL_PAIRS: usize = 256;

/// How far two actors can close on each other in a step of `h`: their relative speed (`speeds`) plus both spins'
/// reach, times h, never more than the two reaches; plus `base`.
pub(crate) struct Closing {
    reach: Vec<f64>,
    spin: Vec<f64>,
    speeds: Vec<Vector3<f64>>,
    h: f64,
    base: f64,
}

impl Closing {
    pub fn of(&self, a: usize, b: usize) -> f64 {
        let relative = match (self.speeds.get(a), self.speeds.get(b)) {
            (Some(x), Some(y)) => (x - y).norm(),
            _ => f64::INFINITY,
        };
        // never more than the two reaches (the old bound), so an unknown actor cannot widen it
        ((relative * self.h + self.spin[a] + self.spin[b]).min(self.reach[a] + self.reach[b])) + self.base
    }
}

impl ColliderSet {
    /// Fast mode's contact pairs of a step of h: the broad phase on boxes grown by how far each actor can move
    /// (`reach`) plus half of `base`, and for each pair how far the two can close on each other in the step: their
    /// relative speed plus both spins' reach, times h, plus `base` (a pair's contacts are sought within it). Bodies
    /// moving together (a stack falling, a row of boxes landing side by side) are not joined by contacts they cannot
    /// close.
    fn closing_pairs(
        &mut self,
        poses: &[Isometry3<f64>],
        states: &[tumble_contact::BodyState],
        (h, base): (f64, f64),
    ) -> Result<(Vec<(usize, usize)>, Closing), String> {
        let (reach, spin) = self.reach_and_spin(states, h);
        let grown: Vec<f64> = reach.iter().map(|m| m + 0.5 * base).collect();
        let boxes = self.boxes(poses, &grown)?;
        let speeds: Vec<Vector3<f64>> = states.iter().map(|s| s.velocity).collect();
        let closing = Closing { reach, spin, speeds, h, base };
        // Two colliders whose own boxes (the grown ones less the growth) are farther apart than the pair can close
        // have no contact within reach: left out before the narrow phase (a falling tower's neighbours, moving
        // together, overlap only by their growth). Exact: the shapes are at least as far apart as their boxes.
        let actor: Vec<usize> = self.colliders.iter().map(|c| self.index(c.actor)).collect();
        let within_reach = |i: usize, j: usize| {
            let (ia, ib) = (actor[i], actor[j]);
            let (a, b) = (&boxes[i], &boxes[j]);
            let gap = (0..3).map(|k| (b.min[k] - a.max[k]).max(a.min[k] - b.max[k])).fold(f64::MIN, f64::max);
            !(gap + grown[ia] + grown[ib] > closing.of(ia, ib))
        };
        let pairs = self.broad_pairs_where(&boxes, within_reach)?;
        Ok((pairs, closing))
    }

    /// Fast mode's contacts of a step of h (the exact solver's), reduced (`contact_reduction.rs`): every pair within
    /// reach (`closing_pairs`) computed afresh.
    pub fn find_closing(
        &mut self,
        poses: &[Isometry3<f64>],
        states: &[tumble_contact::BodyState],
        reach: (f64, f64),
    ) -> Result<Vec<FoundContact>, String> {
        let (pairs, closing) = self.closing_pairs(poses, states, reach)?;
        Ok(reduce(self.pair_contacts(&pairs, poses, |a, b| closing.of(a, b)), states))
    }

    /// Fast mode's contacts of a step of h kept in `store` (the soft step's): each pair within reach
    /// (`closing_pairs`) reuses its manifold if it barely moved (`contact_pairs/pair.rs`), else computes it, reduces it
    /// and sets its contacts, warm-started from its last ones; pairs begin and end in the constraint graph. The
    /// pairs are shared out among `threads` workers.
    pub fn keep_closing(
        &mut self,
        poses: &[Isometry3<f64>],
        states: &[tumble_contact::BodyState],
        reach: (f64, f64),
        store: &mut ContactPairs,
        threads: usize,
    ) -> Result<(), String> {
        let (pairs, closing) = self.closing_pairs(poses, states, reach)?;
        let movable = |a: usize| !self.immovable[a];
        let actor = |c: usize| self.index(self.colliders[c].actor);
        let rest = |(i, j): (usize, usize)| self.idle[actor(i)] && self.idle[actor(j)];
        let mut entries = store.open(&pairs, movable, rest);
        self.kept_pair_contacts(&mut entries, poses, &|a, b| closing.of(a, b), states, threads);
        let movable = |a: usize| !self.immovable[a];
        store.close(entries, self.actors(), movable);
        Ok(())
    }

    /// Each of the pairs kept across steps (`entries`, as `ContactPairs::open` gives them) given its contacts at
    /// `poses`, each pair within `prediction(actor_a, actor_b)`, reduced (the actors `states` give the reduction
    /// its centres of mass), on up to `threads` workers: the pairs are shared out in order, each written by one.
    fn kept_pair_contacts(
        &mut self,
        entries: &mut [Pair],
        poses: &[Isometry3<f64>],
        prediction: &(impl Fn(usize, usize) -> f64 + Sync),
        states: &[tumble_contact::BodyState],
        threads: usize,
    ) {
        // below this many pairs, one worker is quicker than sharing them out; 0 threads: one per core
        let threads = match threads {
            _ if entries.len() < PARALLEL_PAIRS => 1,
            0 => tumble_contact::cores(),
            t => t,
        };
        let workers = tumble_contact::Workers::new(threads);
        let shares = workers.count;
        let n = entries.len();
        let bounds: Vec<usize> = (0..=shares).map(|t| n * t / shares).collect();
        let checks: Vec<std::sync::atomic::AtomicUsize> = (0..shares).map(|_| Default::default()).collect();
        {
            let mut rest = &mut entries[..];
            let mut parts: Vec<std::sync::Mutex<&mut [Pair]>> = Vec::with_capacity(shares);
            for t in 0..shares {
                let (mine, tail) = rest.split_at_mut(bounds[t + 1] - bounds[t]);
                parts.push(std::sync::Mutex::new(mine));
                rest = tail;
            }
            let this = &*self;
            workers.run(|t| {
                let mut part = parts[t].lock().unwrap_or_else(|e| e.into_inner());
                let tested = this.share_contacts(&mut part, poses, prediction, states);
                checks[t].store(tested, std::sync::atomic::Ordering::Relaxed);
            });
        }
        self.checks += checks.iter().map(|c| c.load(std::sync::atomic::Ordering::Relaxed)).sum::<usize>();
    }

    /// One worker's share of `kept_pair_contacts`: its pairs' contacts set; gives the narrow-phase tests it ran.
    fn share_contacts(
        &self,
        entries: &mut [Pair],
        poses: &[Isometry3<f64>],
        prediction: &impl Fn(usize, usize) -> f64,
        states: &[tumble_contact::BodyState],
    ) -> usize {
        let mut checks = 0;
        let (mut contacts_now, mut found, mut kept, mut gaps) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for entry in entries {
            let (i, j) = entry.pair();
            let (ca, cb) = (&self.colliders[i], &self.colliders[j]);
            let (ia, ib) = (self.index(ca.actor), self.index(cb.actor));
            let (pa, pb) = (poses[ia] * ca.offset, poses[ib] * cb.offset);
            let compute = |p: f64| {
                checks += 1;
                contacts(&ca.shape, &pa, &cb.shape, &pb, p)
            };
            let (a, b) = ((&ca.shape, &pa, ca.radius), (&cb.shape, &pb, cb.radius));
            if entry.contacts(a, b, prediction(ia, ib), compute, &mut contacts_now).is_err() {
                contacts_now.clear();
            }
            let material = ca.material.combine(&cb.material, &self.rules);
            let as_found = |c: &tumble_collide::ShapeContact| self.found_contact((i, j), (ia, ib), material, *c);
            gaps.clear();
            gaps.extend(contacts_now.iter().map(|c| c.distance));
            let reduce = || {
                let found: Vec<FoundContact> = contacts_now.iter().map(as_found).collect();
                reduce_indices(&found, states)
            };
            entry.choose(&gaps, reduce, &mut kept);
            // a resting pair carries the same points step after step: only their places and gaps change
            if !entry.carry_kept(&contacts_now, &kept, material) {
                found.clear();
                found.extend(contacts_now.iter().map(as_found));
                entry.set_contacts(&found, &kept);
            }
        }
        checks
    }
}

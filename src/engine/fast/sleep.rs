//! Sleeping in fast mode: an actor (particle or dynamic body) that has moved slower than the sleep speed for the
//! sleep time is still; a group of actors in contact sleeps when all its members are still, and is skipped (held
//! fixed, momenta zero) until an awake actor touches one of them, which wakes the whole group. This is what sleeps
//! (`Sleep`, part of the engine's memory); the stage that brings it up to a step's end is `update_sleep.rs`.

use crate::mode::FastSettings;
use crate::model::layout::set3;
use crate::model::Model;
use nalgebra::Vector3;

/// Who sleeps, and how long each awake actor has been resting (slower than the sleep speed).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(crate) struct Sleep {
    asleep: Vec<bool>,
    #[serde(rename = "still")] // (its name in files)
    resting_for: Vec<f64>,
}

/// Groups of dynamic actors (indices below `n`) joined by contacts (their actor pairs), as a root per actor.
fn groups(touching: impl Iterator<Item = (usize, usize)>, n: usize) -> Vec<usize> {
    let mut sets = tumble_contact::UnionFind::new(n);
    for (a, b) in touching.filter(|&(a, b)| a < n && b < n) {
        sets.union(a, b);
    }
    (0..n).map(|x| sets.find(x)).collect()
}

impl Sleep {
    /// Whether it fits `actors` actors.
    pub fn fits(&self, actors: usize) -> bool {
        self.asleep.len() == actors
            && self.resting_for.len() == actors
            && self.resting_for.iter().all(|s| s.is_finite())
    }

    pub fn new(actors: usize) -> Self {
        Sleep { asleep: vec![false; actors], resting_for: vec![0.0; actors] }
    }

    /// Number of dynamic actors.
    pub fn len(&self) -> usize {
        self.asleep.len()
    }

    /// Who sleeps, by actor.
    pub fn flags(&self) -> &[bool] {
        &self.asleep
    }

    /// Whether actor i sleeps.
    pub fn asleep(&self, i: usize) -> bool {
        self.asleep.get(i).copied().unwrap_or(false)
    }

    /// How many sleep.
    pub fn count(&self) -> usize {
        self.asleep.iter().filter(|&&s| s).count()
    }

    /// Wakes every group in which an awake actor touches a sleeping one (`touching`: the actor pairs in contact);
    /// returns whether any woke.
    pub fn wake_touched(&mut self, touching: impl Iterator<Item = (usize, usize)>, n: usize) -> bool {
        if !self.asleep.iter().any(|&s| s) {
            return false;
        }
        let root = groups(touching, n);
        let mut mixed = vec![(false, false); n];
        for i in 0..n {
            let m = &mut mixed[root[i]];
            if self.asleep[i] {
                m.0 = true;
            } else {
                m.1 = true;
            }
        }
        let mut woke = false;
        for i in 0..n {
            if self.asleep[i] && mixed[root[i]] == (true, true) {
                self.asleep[i] = false;
                self.resting_for[i] = 0.0;
                woke = true;
            }
        }
        woke
    }

    /// Books a step of length h: `speeds[i]` bounds how fast any point of actor i moves. Groups whose awake members
    /// have all been still for the sleep time fall asleep.
    #[allow(clippy::needless_range_loop)]
    pub fn update(&mut self, touching: impl Iterator<Item = (usize, usize)>, speeds: &[f64], s: &FastSettings, h: f64) {
        let n = self.asleep.len();
        for i in 0..n {
            if !self.asleep[i] {
                self.resting_for[i] = if speeds[i] < s.sleep_speed { self.resting_for[i] + h } else { 0.0 };
            }
        }
        let root = groups(touching, n);
        let mut ready = vec![true; n];
        for i in 0..n {
            if !self.asleep[i] && self.resting_for[i] < s.sleep_time {
                ready[root[i]] = false;
            }
        }
        for i in 0..n {
            if ready[root[i]] {
                self.asleep[i] = true;
            }
        }
    }

    /// Zeroes the momenta of sleeping actors in state y.
    pub fn freeze(&self, y: &mut [f64], model: &Model) {
        let l = model.layout;
        let zero = Vector3::zeros();
        for i in 0..l.particles {
            if self.asleep[i] {
                set3(y, l.pv(i), &zero);
            }
        }
        for j in 0..l.bodies {
            if self.asleep[l.body_actor(j)] {
                set3(y, l.bp(j), &zero);
                set3(y, l.bl(j), &zero);
            }
        }
    }
}

//! Sleeping in accurate mode's touching phase (worlds without joints, as in fast mode: a joint's rows need moving
//! ends): an island (actors joined by contacts or springs) whose
//! actors have all moved slower than the resting speed for `AccurateSettings::sleep_time` is frozen: its
//! velocities are set to zero and, while it sleeps, its actors are fixed bodies to the contact steps (they cost no
//! solve, and contacts among them are not even kept), held still in free flight, and a world with nothing awake
//! advances its clock alone. An island wakes, whole, when an awake actor comes within a step's reach of one of its
//! actors; every island wakes when the state is set (a push, an edit) or a material changes. What sleeps is part of
//! the engine's memory, so a saved and loaded world sleeps and wakes with the same bits. Actors at rest inside an
//! island that still moves are held one by one (`held.rs`).

use crate::engine::found_contact::FoundContact;
use crate::model::layout::get3;
use crate::model::Model;
use serde::{Deserialize, Serialize};
use tumble_contact::BodyState;

/// What sleeps and what is calm.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Sleep {
    /// For each actor (particles, then dynamic bodies) touching something, since when it has moved slower than the
    /// resting speed; actors not listed are moving or touch nothing. Ordered by actor.
    #[serde(rename = "calm_since")] // (its name in files)
    pub resting_since: Vec<(usize, f64)>,
    /// The islands asleep, each its actors in increasing order, the islands in the order they fell asleep.
    pub islands: Vec<Vec<usize>>,
    /// The actors held inside moving islands (`held.rs`), in increasing order. (Absent from files written before
    /// actors were held: none.)
    #[serde(default)]
    pub held: Vec<usize>,
}

impl Sleep {
    /// Whether it fits a scene of `actors` moving actors.
    pub fn fits(&self, actors: usize) -> bool {
        self.resting_since.iter().all(|(a, t)| *a < actors && t.is_finite())
            && self.islands.iter().flatten().all(|a| *a < actors)
            && self.held.windows(2).all(|w| w[0] < w[1])
            && self.held.iter().all(|a| *a < actors)
    }

    /// Actors asleep or held.
    pub fn count(&self) -> usize {
        self.islands.iter().map(Vec::len).sum::<usize>() + self.held.len()
    }

    /// The actors asleep or held.
    fn resting(&self) -> impl Iterator<Item = usize> + '_ {
        self.islands.iter().flatten().copied().chain(self.held.iter().copied())
    }

    /// Whether `actor` rests: asleep, or held inside a moving island.
    pub fn resting_actor(&self, actor: usize) -> bool {
        self.asleep(actor) || self.is_held(actor)
    }

    /// Whether `actor` sleeps.
    pub fn asleep(&self, actor: usize) -> bool {
        self.islands.iter().any(|i| i.binary_search(&actor).is_ok())
    }

    /// Wakes every island (the state was set, or a material changed).
    pub fn wake_all(&mut self) {
        self.islands.clear();
        self.resting_since.clear();
        self.held.clear();
    }

    /// The sleeping and held actors made fixed bodies at rest in the contact steps' view of the actors.
    pub fn hold(&self, states: &mut [BodyState]) {
        for a in self.resting() {
            let s = &mut states[a];
            *s = BodyState::fixed(s.position);
        }
    }

    /// Marks the sleeping and held actors as held (`involved`, in free flight's sense).
    pub fn mark(&self, involved: &mut [bool]) {
        for a in self.resting() {
            involved[a] = true;
        }
    }

    /// Wakes each island one of whose actors is in a contact of `found` with an awake moving actor (`actors` of
    /// them; a held actor is not awake, and is woken by its loads, not by touch); whether any woke.
    pub fn wake_touched(&mut self, found: &[FoundContact], actors: usize) -> bool {
        let mut woke = false;
        for f in found {
            let (a, b) = (f.contact.a, f.contact.b);
            for (sleeper, other) in [(a, b), (b, a)] {
                if other < actors && !self.resting_actor(other) {
                    if let Some(k) = self.islands.iter().position(|i| i.binary_search(&sleeper).is_ok()) {
                        for actor in self.islands.remove(k) {
                            self.resting_since.retain(|(x, _)| *x != actor);
                        }
                        woke = true;
                    }
                }
            }
        }
        woke
    }

    /// After a step accepted at time t with the contacts `found` and `links` (springs and joints between actors):
    /// brings each touching actor's calm time up to date from its speed in y, puts to sleep, with their velocities zeroed in y, the islands whose actors have all been calm for
    /// `sleep_time`, and holds (`held.rs`) the actors calm that long in the islands that still move. Whether any
    /// fell asleep or was held.
    pub fn settle(
        &mut self,
        model: &Model,
        found: &[FoundContact],
        links: &[(usize, usize)],
        y: &mut [f64],
        t: f64,
        (resting_speed, sleep_time): (f64, f64),
    ) -> bool {
        let l = model.layout;
        let actors = l.actors();
        let touching = |a: usize| a < actors && !self.resting_actor(a);
        // union-find over the awake touching actors
        let mut sets = tumble_contact::UnionFind::new(actors);
        let mut member = vec![false; actors];
        let pairs = found.iter().map(|f| (f.contact.a, f.contact.b));
        for (a, b) in pairs.clone().chain(links.iter().copied()) {
            for x in [a, b] {
                if touching(x) {
                    member[x] = true;
                }
            }
            if touching(a) && touching(b) {
                sets.union(a, b);
            }
        }
        // an island joined to a sleeping actor by a contact stays awake (it is being woken or will be)
        let mut blocked = vec![false; actors];
        for (a, b) in pairs.chain(links.iter().copied()) {
            for (x, other) in [(a, b), (b, a)] {
                if touching(x) && other < actors && self.asleep(other) {
                    blocked[sets.find(x)] = true;
                }
            }
        }
        let resting_since: Vec<(usize, f64)> = (0..actors)
            .filter(|&a| member[a])
            .filter(|&a| speed(model, y, a) < resting_speed)
            // a kinematic body with moving still to do is never calm
            .filter(|&a| a < l.particles || !model.kinematic_moves_after(a - l.particles, t))
            .map(|a| (a, self.resting_since.iter().find(|(x, _)| *x == a).map_or(t, |(_, since)| *since)))
            .collect();
        self.resting_since = resting_since;
        // islands in order of their smallest actor; asleep when every member has been calm long enough
        let mut islands: Vec<Vec<usize>> = Vec::new();
        let mut slot = vec![usize::MAX; actors];
        for a in (0..actors).filter(|&a| member[a]) {
            let r = sets.find(a);
            if slot[r] == usize::MAX {
                slot[r] = islands.len();
                islands.push(Vec::new());
            }
            islands[slot[r]].push(a);
        }
        let mut fell = false;
        let mut holding = Vec::new();
        for island in islands {
            let r = sets.find(island[0]);
            let calm = |a: &usize| self.resting_since.iter().any(|(x, since)| x == a && t - since >= sleep_time);
            if !blocked[r] && island.iter().all(calm) {
                for &a in &island {
                    zero_velocity(model, y, a);
                }
                self.resting_since.retain(|(x, _)| island.binary_search(x).is_err());
                self.islands.push(island);
                fell = true;
            } else {
                holding.extend(island.iter().copied().filter(calm));
            }
        }
        // the calm actors of islands that still move are held
        for &a in &holding {
            self.hold_actor(a);
            zero_velocity(model, y, a);
            fell = true;
        }
        self.resting_since.retain(|(x, _)| !holding.contains(x));
        fell
    }
}

/// The fastest an actor's points move in state y (m/s): its centre's speed, plus for a body its angular momentum's
/// share at the radius of gyration (|L| / (m r)).
pub(super) fn speed(model: &Model, y: &[f64], a: usize) -> f64 {
    let l = model.layout;
    if a < l.particles {
        return get3(y, l.pv(a)).norm();
    }
    let j = a - l.particles;
    let body = &model.bodies[j];
    let r = (body.inertia.trace() / (2.0 * body.mass)).sqrt();
    let turning = if r > 0.0 { get3(y, l.bl(j)).norm() / (body.mass * r) } else { 0.0 };
    get3(y, l.bp(j)).norm() / body.mass + turning
}

/// Sets an actor's velocity (a particle's) or momenta (a body's) to zero in state y.
fn zero_velocity(model: &Model, y: &mut [f64], a: usize) {
    let l = model.layout;
    let blocks = if a < l.particles { vec![l.pv(a)] } else { vec![l.bp(a - l.particles), l.bl(a - l.particles)] };
    for k in blocks {
        y[k..k + 3].fill(0.0);
    }
}

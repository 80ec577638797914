//! The colliders of a compiled world: every collider with the actor that carries it (a particle with a radius, a
//! dynamic body, a static body), their poses in a state, and contact finding: sort-and-sweep over the colliders'
//! boxes, then parry's contact geometry for each overlapping pair that can touch, turned into contacts for
//! tumble-contact (body indices, point, normal from A to B, gap, combined material; `found_contact.rs`). Fast
//! mode's pairs that can close within a step, and their kept contacts, are `closing_pairs.rs`; reach `reach.rs`.

use crate::body::RigidBody;
use crate::collider::{Collider, CombineRules, Material};
use crate::engine::found_contact::{contact_point, feature_code, ContactKey, FoundContact};
use crate::handle::Arena;
use crate::model::layout::Layout;
use crate::particle::Particle;
use crate::spring::BodyHandle;
use nalgebra::{Isometry3, Vector3};
use std::sync::Arc;
use tumble_collide::{contacts, Aabb, ContactKind, Shape, SortAndSweep};

/// Who carries a collider: actors are numbered particles first, then dynamic bodies, then static bodies, which is
/// the order of the body arrays handed to tumble-contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Actor {
    Particle(usize),
    Body(usize),
    Static(usize),
}

/// A collider of the scene.
#[derive(Clone, Debug)]
pub(crate) struct ColliderEntry {
    pub actor: Actor,
    pub shape: Shape,
    /// The shape's pose in the actor's frame (origin at the centre of mass).
    pub offset: Isometry3<f64>,
    pub material: Material,
    /// Radius of a ball about the actor's origin that holds the shape (infinite for a half-space).
    pub reach: f64,
    /// Radius of a ball about the shape's own origin that holds it (infinite for a half-space).
    pub radius: f64,
    /// Its actor's collision groups: two colliders touch only if theirs share a bit.
    pub groups: u32,
}

/// The colliders of a world and a broad phase that persists from call to call.
#[derive(Clone)]
pub(crate) struct ColliderSet {
    pub colliders: Vec<ColliderEntry>,
    /// The static actors' poses, shared with the stages that read them while they change the set.
    pub static_poses: Arc<[Isometry3<f64>]>,
    pub layout: Layout,
    broad: SortAndSweep,
    /// Narrow-phase pair tests so far.
    pub checks: usize,
    /// Actors that cannot move this step (static, or asleep): pairs of two are not tested.
    pub idle: Vec<bool>,
    /// Actors nothing can push (static and kinematic): pairs of two are not tested.
    pub(super) immovable: Vec<bool>,
    /// Contacts the last call found: room made for as many (a growing list of contacts would copy them).
    found_last: usize,
    /// Pairs of actors a joint joins directly (sorted, lower index first): they never touch (a joint's bodies
    /// overlap at the joint, as a ragdoll's limbs do at their sockets).
    joined: Vec<(usize, usize)>,
    /// Fast mode's fat boxes and the pairs whose fat boxes overlap (`broad_pairs_where`).
    fat: FatBoxes,
    /// The world's rules for combining two materials.
    pub rules: CombineRules,
}

/// Fat boxes kept from step to step, and the pairs of colliders whose fat boxes overlap (unsorted; empty before the
/// first search).
#[derive(Clone, Debug, Default)]
struct FatBoxes {
    boxes: Vec<Aabb>,
    pairs: Vec<(u32, u32)>,
}

/// How far a fat box reaches past its collider's box, as a fraction of the collider's bounding radius.
const FAT: f64 = 0.1;

fn collider_entry(actor: Actor, c: &Collider, b: &RigidBody) -> ColliderEntry {
    let radius = c.shape.bounding_radius();
    let reach = c.offset.translation.vector.norm() + radius;
    let (material, groups) = (b.material, b.groups);
    ColliderEntry { actor, shape: c.shape.clone(), offset: c.offset, material, reach, radius, groups }
}

impl ColliderSet {
    /// The scene of these particles and bodies (`dynamic` lists the dynamic bodies in state order), or `None`
    /// when no two colliders could ever touch (no shapes, or nothing that moves has one).
    pub fn build(
        layout: Layout,
        particles: &Arena<Particle>,
        bodies: &Arena<RigidBody>,
        dynamic: &[BodyHandle],
        rules: CombineRules,
    ) -> Option<ColliderSet> {
        let mut colliders = Vec::new();
        for (i, (_, p)) in particles.iter().enumerate() {
            if p.radius > 0.0 {
                let shape = Shape::sphere(p.radius).expect("radius checked > 0");
                colliders.push(ColliderEntry {
                    actor: Actor::Particle(i),
                    shape,
                    offset: Isometry3::identity(),
                    material: p.material,
                    reach: p.radius,
                    radius: p.radius,
                    groups: crate::body::ALL_GROUPS,
                });
            }
        }
        for (j, &h) in dynamic.iter().enumerate() {
            let b = bodies.get(h).expect("live");
            colliders.extend(b.colliders.iter().map(|c| collider_entry(Actor::Body(j), c, b)));
        }
        let mut static_poses = Vec::new();
        for (_, b) in bodies.iter().filter(|(_, b)| b.is_static) {
            let s = static_poses.len();
            static_poses.push(b.pose());
            colliders.extend(b.colliders.iter().map(|c| collider_entry(Actor::Static(s), c, b)));
        }
        let moving = colliders.iter().filter(|c| !matches!(c.actor, Actor::Static(_))).count();
        if moving == 0 || colliders.len() < 2 {
            return None;
        }
        let actors = layout.actors() + static_poses.len();
        let idle = (0..actors).map(|a| a >= layout.actors()).collect();
        let immovable = (0..actors)
            .map(|a| match a.checked_sub(layout.particles) {
                Some(j) if j < layout.bodies => bodies.get(dynamic[j]).expect("live").kinematic.is_some(),
                Some(_) => true,
                None => false,
            })
            .collect();
        Some(ColliderSet {
            colliders,
            static_poses: static_poses.into(),
            layout,
            broad: SortAndSweep::new(),
            checks: 0,
            idle,
            immovable,
            found_last: 0,
            rules,
            joined: Vec::new(),
            fat: FatBoxes::default(),
        })
    }

    /// The index of an actor in the body arrays given to tumble-contact.
    pub fn index(&self, a: Actor) -> usize {
        match a {
            Actor::Particle(i) => i,
            Actor::Body(j) => self.layout.body_actor(j),
            Actor::Static(s) => self.layout.actors() + s,
        }
    }

    /// The actor index (as `index` gives it) of collider `c`, if there is one.
    pub fn actor_of_collider(&self, c: usize) -> Option<usize> {
        self.colliders.get(c).map(|c| self.index(c.actor))
    }

    /// Number of actors.
    pub fn actors(&self) -> usize {
        self.layout.actors() + self.static_poses.len()
    }

    /// The size of the scene in state y: the diagonal of the box around every finite collider of an actor that moves
    /// (static ground and walls do not set it: a 20 m floor under 0.4 m cubes is not a 20 m scene), or around every
    /// finite collider when nothing moves; at least 1e-3.
    pub fn size(&self, y: &[f64]) -> f64 {
        let poses = self.poses(y);
        let zeros = vec![0.0; self.actors()];
        let boxes = self.boxes(&poses, &zeros).unwrap_or_default();
        let around = |moving: bool| {
            let mut finite = boxes
                .iter()
                .zip(&self.colliders)
                .filter(|(b, c)| b.is_finite() && (!moving || !matches!(c.actor, Actor::Static(_))))
                .map(|(b, _)| *b);
            let first = finite.next();
            finite.fold(first, |acc, b| acc.map(|a| a.merged(&b))).map(|b| (b.max - b.min).norm().max(1e-3))
        };
        around(true).or_else(|| around(false)).unwrap_or(1e-3)
    }

    /// The pose of every actor in state y (particles: translation only).
    pub fn poses(&self, y: &[f64]) -> Vec<Isometry3<f64>> {
        crate::model::actor_poses(self.layout, y, &self.static_poses)
    }

    /// Whether two colliders may ever touch, whatever sleeps: not on one actor, not both static or kinematic, not two
    /// particles, not joined, in a collision group of both.
    fn may_ever_touch(&self, a: usize, b: usize) -> bool {
        if self.colliders[a].groups & self.colliders[b].groups == 0 {
            return false;
        }
        let (x, y) = (self.colliders[a].actor, self.colliders[b].actor);
        let (i, j) = (self.index(x), self.index(y));
        if self.immovable[i] && self.immovable[j] {
            return false;
        }
        if !self.joined.is_empty() && self.joined.binary_search(&(i.min(j), i.max(j))).is_ok() {
            return false;
        }
        match (x, y) {
            (Actor::Particle(_), Actor::Particle(_)) => false,
            (x, y) => x != y,
        }
    }

    /// Sets the pairs of actors a joint joins directly (sorted, lower index first): they never touch.
    pub fn set_joined(&mut self, joined: Vec<(usize, usize)>) {
        self.joined = joined;
        // the kept pairs were filtered with the old ones
        self.fat.pairs.clear();
    }

    /// The world box of every collider at `poses`, each grown by its actor's `margins` entry.
    /// An error (a message) if a pose or margin is not finite: a diverging step, which the caller fails cleanly.
    pub(super) fn boxes(&self, poses: &[Isometry3<f64>], margins: &[f64]) -> Result<Vec<Aabb>, String> {
        self.colliders
            .iter()
            .map(|c| {
                let actor = self.index(c.actor);
                let pose = poses[actor] * c.offset;
                let margin = margins[actor];
                if !margin.is_finite() {
                    return Err(format!("actor {actor} moves at a speed that is not finite"));
                }
                let aabb = c.shape.aabb(&pose).map_err(|e| format!("actor {actor}'s pose is not finite ({e})"))?;
                Ok(aabb.loosened(margin))
            })
            .collect()
    }

    /// The contacts at `poses` closer than their pair's prediction distance (the sum of the two actors'
    /// `margins`, plus `base`): broad phase on boxes grown by the margins, then parry's manifolds.
    pub fn find(&mut self, poses: &[Isometry3<f64>], margins: &[f64], base: f64) -> Result<Vec<FoundContact>, String> {
        let grown: Vec<f64> = margins.iter().map(|m| m + 0.5 * base).collect();
        let boxes = self.boxes(poses, &grown)?;
        let pairs = self.broad_pairs(&boxes)?;
        Ok(self.pair_contacts(&pairs, poses, |a, b| grown[a] + grown[b]))
    }

    /// Whether an actor takes colours in the constraint graph (a sweep moves it: not static or kinematic).
    pub fn movable(&self, actor: usize) -> bool {
        !self.immovable[actor]
    }

    /// The pairs of colliders (first one moving) whose boxes, swept from `from` to `to` and grown by each actor's
    /// `margins` entry, overlap and that may touch.
    pub fn swept_pairs(
        &mut self,
        from: &[Isometry3<f64>],
        to: &[Isometry3<f64>],
        margins: &[f64],
    ) -> Result<Vec<(usize, usize)>, String> {
        let boxes: Vec<Aabb> =
            self.boxes(from, margins)?.iter().zip(self.boxes(to, margins)?).map(|(a, b)| a.merged(&b)).collect();
        self.broad_pairs(&boxes)
    }

    /// The overlapping pairs that may touch, sorted: the order the broad phase found them in depends on its
    /// history (columns, insertion sorts), and must not reach the contact solves.
    fn broad_pairs(&mut self, boxes: &[Aabb]) -> Result<Vec<(usize, usize)>, String> {
        self.broad_pairs_where(boxes, |_, _| true)
    }

    /// `broad_pairs` of boxes held in fat boxes kept from step to step (Box2D's): a box that leaves its fat box gets a
    /// new one, its own grown by a tenth of its collider's bounding radius, and the sort-and-sweep runs on the fat
    /// boxes only when one changed, keeping the pairs that may ever touch; those are then tested on `boxes` (and on
    /// sleep) every time, and by `keep`, which must hold only where they overlap (it sees the pair in either order).
    pub(super) fn broad_pairs_where(
        &mut self,
        boxes: &[Aabb],
        keep: impl Fn(usize, usize) -> bool,
    ) -> Result<Vec<(usize, usize)>, String> {
        let fat = &mut self.fat;
        let mut changed = fat.boxes.len() != boxes.len();
        if changed {
            fat.boxes = boxes.to_vec();
        }
        for ((f, b), c) in fat.boxes.iter_mut().zip(boxes).zip(&self.colliders) {
            if changed || !(f.contains(&b.min) && f.contains(&b.max)) {
                let margin = if c.radius.is_finite() { FAT * c.radius } else { 0.0 };
                *f = b.loosened(margin);
                changed = true;
            }
        }
        if changed || fat.pairs.is_empty() {
            let mut all = self.broad.update(&self.fat.boxes).map_err(|e| e.to_string())?.to_vec();
            all.retain(|&(i, j)| self.may_ever_touch(i as usize, j as usize));
            self.fat.pairs = all;
        }
        let fat = std::mem::take(&mut self.fat.pairs);
        // not both static or asleep
        let awake = |i: usize, j: usize| {
            let (a, b) = (self.index(self.colliders[i].actor), self.index(self.colliders[j].actor));
            !(self.idle[a] && self.idle[b])
        };
        let mut pairs: Vec<(usize, usize)> = fat
            .iter()
            .map(|&(i, j)| (i as usize, j as usize))
            .filter(|&(i, j)| awake(i, j) && boxes[i].overlaps(&boxes[j]) && keep(i, j))
            // Keep the moving actor as A when one side is static.
            .map(|(i, j)| if matches!(self.colliders[i].actor, Actor::Static(_)) { (j, i) } else { (i, j) })
            .collect();
        self.fat.pairs = fat;
        pairs.sort_unstable();
        Ok(pairs)
    }

    /// The contacts of the collider pairs `pairs` at `poses`, each pair within `prediction(actor_a, actor_b)`, every
    /// manifold computed and kept whole.
    pub fn pair_contacts(
        &mut self,
        pairs: &[(usize, usize)],
        poses: &[Isometry3<f64>],
        prediction: impl Fn(usize, usize) -> f64,
    ) -> Vec<FoundContact> {
        let mut out = Vec::with_capacity(self.found_last + self.found_last / 8);
        for &(i, j) in pairs {
            let (ca, cb) = (&self.colliders[i], &self.colliders[j]);
            let (ia, ib) = (self.index(ca.actor), self.index(cb.actor));
            let (pa, pb) = (poses[ia] * ca.offset, poses[ib] * cb.offset);
            self.checks += 1;
            let Ok(found) = contacts(&ca.shape, &pa, &cb.shape, &pb, prediction(ia, ib)) else { continue };
            let material = ca.material.combine(&cb.material, &self.rules);
            out.extend(found.into_iter().map(|c| self.found_contact((i, j), (ia, ib), material, c)));
        }
        self.found_last = out.len();
        out
    }

    /// A contact of parry's between colliders `pair` of actors `actors` as tumble-contact takes it.
    pub(super) fn found_contact(
        &self,
        pair: (usize, usize),
        (ia, ib): (usize, usize),
        material: Material,
        c: tumble_collide::ShapeContact,
    ) -> FoundContact {
        let (ca, cb) = (&self.colliders[pair.0], &self.colliders[pair.1]);
        let motion = match c.kind {
            ContactKind::FaceVertex => tumble_contact::NormalMotion::WithA,
            ContactKind::Curved
                if matches!(ca.shape, Shape::Sphere { .. })
                    && matches!(cb.shape, Shape::Sphere { .. })
                    && ca.offset.translation.vector == Vector3::zeros()
                    && cb.offset.translation.vector == Vector3::zeros() =>
            {
                tumble_contact::NormalMotion::BetweenCentres
            }
            // vertex-face, and edge-edge (whose edges parry does not hand us): the normal turns with B
            _ => tumble_contact::NormalMotion::WithB,
        };
        let point = contact_point(&c);
        let contact = tumble_contact::Contact {
            a: ia,
            b: ib,
            point,
            normal: c.normal,
            distance: c.distance,
            restitution: material.restitution,
            friction: material.friction,
            normal_motion: motion,
            rolling_resistance: material.rolling_resistance,
            torsional_resistance: material.torsional_resistance,
        };
        let key = ContactKey {
            colliders: (pair.0 as u32, pair.1 as u32),
            features: (feature_code(c.feature_a), feature_code(c.feature_b)),
        };
        FoundContact { contact, key, point_a: c.point_a, point_b: c.point_b }
    }

    /// Gives every collider of actor `actor` (its index in the body arrays) `material`.
    pub fn set_material(&mut self, actor: usize, material: Material) {
        for c in 0..self.colliders.len() {
            if self.index(self.colliders[c].actor) == actor {
                self.colliders[c].material = material;
            }
        }
    }

    /// The distance between the colliders i and j at the actors' `poses` (m; zero where they overlap, infinite where
    /// it cannot be had).
    pub fn pair_distance(&mut self, i: usize, j: usize, poses: &[Isometry3<f64>]) -> f64 {
        let (ca, cb) = (&self.colliders[i], &self.colliders[j]);
        let (pa, pb) = (poses[self.index(ca.actor)] * ca.offset, poses[self.index(cb.actor)] * cb.offset);
        self.checks += 1;
        tumble_collide::distance(&ca.shape, &pa, &cb.shape, &pb).unwrap_or(f64::INFINITY)
    }

    /// The shapes of a collider pair.
    pub fn shapes(&self, i: usize, j: usize) -> (&Shape, &Shape, Isometry3<f64>, Isometry3<f64>, usize, usize) {
        let (ca, cb) = (&self.colliders[i], &self.colliders[j]);
        (&ca.shape, &cb.shape, ca.offset, cb.offset, self.index(ca.actor), self.index(cb.actor))
    }
}

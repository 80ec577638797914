//! Accurate mode, the chapter's scheme: the integrator carries the smooth motion under its error control; after
//! every accepted step the contacts are checked; a collision inside the step is located by bisection on the step's
//! dense output and the step is cut there; at each such event a contact phase applies impulses to the colliding
//! contacts (all touching ones at once, restitution only where the closing speed exceeds the resting speed), lifts
//! resting contacts that drifted into each other back to zero gap, and hands the resting ones to the right-hand
//! side, which gives them the QP forces. Bounces slower than the resting speed are absorbed, so a bouncing ball
//! comes to rest after finitely many bounces instead of an endless cascade.

use crate::contact_scene::{ContactKey, ContactScene, Found};
use crate::layout::{get3, get_quat, set3, set_quat};
use crate::mode::AccurateSettings;
use crate::model::Model;
use crate::report::WorldReport;
use crate::resting_set::{actor_poses, RestingContact, RestingSet};
use nalgebra::{Isometry3, UnitQuaternion};
use std::collections::HashSet;
use std::time::Instant;
use tumble_collide::{distance, first_contact, ShapeError, ToiMethod, ToiOptions};
use tumble_contact::{collision_impulses, position_correction, Contact, SolverSettings};
use tumble_integrate::{Integrator, OdeError, StepView};

/// The contact side of an accurate-mode world.
pub(crate) struct Accurate {
    pub scene: ContactScene,
    settings: AccurateSettings,
    /// Relative normal speed below which contacts rest (resolved from the settings or the scene's size).
    pub resting_speed: f64,
    resting_keys: HashSet<ContactKey>,
    solver: SolverSettings,
    /// Contact counters since the last report.
    pub report: WorldReport,
    /// Largest penetration found at the last contact phase.
    pub penetration: f64,
}

fn failure(t: f64, message: String) -> OdeError {
    OdeError::System { t, message }
}

impl Accurate {
    pub fn new(scene: ContactScene, settings: AccurateSettings, gravity: f64, size: f64) -> Self {
        let resting_speed = settings.resting_speed.unwrap_or_else(|| tumble_contact::velocity_tolerance(size, gravity));
        Accurate {
            scene,
            settings,
            resting_speed,
            resting_keys: HashSet::new(),
            solver: SolverSettings::default(),
            report: WorldReport::new("accurate"),
            penetration: 0.0,
        }
    }

    /// The contact phase at the integrator's current state: impulses, position correction, the resting set.
    pub fn contact_phase(&mut self, model: &mut Model, integ: &mut Integrator<Model>) -> Result<(), OdeError> {
        let clock = Instant::now();
        let t = integ.time();
        let mut y = integ.state().to_vec();
        let statics = self.scene.static_poses.clone();
        let delta = self.settings.contact_distance;
        let v_rest = self.resting_speed;
        model.update_kin(&y);
        let poses = actor_poses(model, &y, &statics);
        let dp = vec![0.0; y.len() - model.layout.positions()];
        let mut states = model.contact_states(&y, &dp, &statics);
        // The bisection stops up to `time_tolerance` before contact, when a pair may still be apart by as much as
        // it closes in that time: contacts within that distance (plus the contact distance) count as touching.
        let closing = self.scene.reach(&states, 2.0 * self.settings.time_tolerance);
        let checks = self.scene.checks;
        let found = self.scene.find(&poses, &closing, delta);
        self.report.collision_checks += self.scene.checks - checks;
        self.penetration = found.iter().map(|f| -f.contact.distance).fold(0.0, f64::max);
        self.report.max_penetration = self.report.max_penetration.max(self.penetration);
        // Separating contacts take no part.
        let mut active: Vec<(Found, f64)> = found
            .into_iter()
            .map(|f| {
                let v = f.contact.relative_normal_velocity(&states);
                (f, v)
            })
            .filter(|(_, v)| *v <= v_rest)
            .collect();
        if active.iter().any(|(_, v)| *v < 0.0) {
            let contacts: Vec<Contact> = active
                .iter()
                .map(|(f, v)| Contact {
                    restitution: if *v < -v_rest { f.contact.restitution } else { 0.0 },
                    ..f.contact
                })
                .collect();
            let out = collision_impulses(&states, &contacts, &self.solver)
                .map_err(|e| failure(t, format!("impulses: {e}")))?;
            self.report.qp_solves += out.solver_calls;
            self.report.collisions += active.iter().filter(|(_, v)| *v < -v_rest).count();
            self.report.impulses += out.magnitudes.iter().filter(|&&j| j > 0.0).count();
            write_velocities(model, &mut y, &out.velocities);
            model.update_kin(&y);
            states = model.contact_states(&y, &dp, &statics);
            for (f, v) in &mut active {
                *v = f.contact.relative_normal_velocity(&states);
            }
        }
        // Only contacts that now neither close nor open rest; what bounced away (or was drifting apart) leaves,
        // and if it comes back slower than the resting speed, it is stopped then.
        active.retain(|(_, v)| *v <= 1e-3 * v_rest);
        if active.iter().any(|(f, _)| f.contact.distance < -delta) {
            let contacts: Vec<Contact> = active.iter().map(|(f, _)| f.contact).collect();
            let shift = position_correction(&states, &contacts, &self.solver)
                .map_err(|e| failure(t, format!("projection: {e}")))?;
            self.report.qp_solves += shift.solver_calls;
            shift_positions(model, &mut y, &shift.moves);
        }
        let poses = actor_poses(model, &y, &statics);
        let contacts: Vec<RestingContact> = active.iter().map(|(f, _)| RestingContact::attach(f, &poses)).collect();
        self.resting_keys = contacts.iter().map(|c| c.key).collect();
        let previous = model.resting.take();
        let (solves, seconds) = previous.map_or((0, 0.0), |p| (p.solves, p.seconds));
        model.resting = Some(RestingSet { contacts, statics, settings: self.solver, reach: delta, solves, seconds });
        integ.set_state(t, &y)?;
        self.report.collision_seconds += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// Looks at an accepted step for a collision (bisection on the dense output), a pass through a thin body
    /// (distance-bounded search) or drift of a resting contact; returns the time to stop at.
    pub fn detect(&mut self, step: &mut StepView<'_, Model>) -> Result<Option<f64>, OdeError> {
        let clock = Instant::now();
        let result = self.detect_inner(step);
        self.report.collision_seconds += clock.elapsed().as_secs_f64();
        result
    }

    fn detect_inner(&mut self, step: &mut StepView<'_, Model>) -> Result<Option<f64>, OdeError> {
        let (t0, t1) = (step.t0(), step.t1());
        let h = t1 - t0;
        let delta = self.settings.contact_distance;
        let statics = self.scene.static_poses.clone();
        let model = step.system();
        let poses0 = actor_poses(model, step.y0(), &statics);
        let poses1 = actor_poses(model, step.y1(), &statics);
        let speeds = self.speeds(model, step.y0(), step.y1(), &statics);
        // Boxes swept between the ends, grown by how far a curved path can bulge from its chord.
        let margins: Vec<f64> = speeds.iter().map(|(s, bulge)| bulge * h + delta + 1e-12 * s).collect();
        let checks = self.scene.checks;
        let pairs = self.scene.swept_pairs(&poses0, &poses1, &margins);
        if pairs.is_empty() {
            return Ok(None);
        }
        let found1 = self.scene.pair_contacts(&pairs, &poses1, |_, _| delta);
        let resting = &self.resting_keys;
        // A resting contact that sank past the contact distance has drifted; any other contact that interpenetrates
        // at all is a collision.
        let drift = found1.iter().any(|f| resting.contains(&f.key) && f.contact.distance < -delta);
        // In a pair that was already touching at the step's start (a contact within the contact distance), a contact
        // that is not resting (it was opening) collides only once it sinks past 1e-3 of the contact distance
        // (1e-10 m by default); in other pairs, as soon as it interpenetrates. Touching contacts sit at a gap of zero
        // give or take rounding (+-4e-13 m seen; parry may also renumber their features), so a light body under a
        // heavy one would otherwise raise an event at every step. The collision time of such a contact is off by
        // at most that depth over the closing speed (3e-11 s for the bouncing ball).
        // The collider pairs of the contacts that satisfy `pick`, each once.
        let pairs_where = |pick: &dyn Fn(&Found) -> bool| -> Vec<(usize, usize)> {
            let mut p: Vec<(usize, usize)> = found1
                .iter()
                .filter(|f| pick(f))
                .map(|f| (f.key.colliders.0 as usize, f.key.colliders.1 as usize))
                .collect();
            p.sort_unstable();
            p.dedup();
            p
        };
        let candidate = pairs_where(&|f| !resting.contains(&f.key) && f.contact.distance < 0.0);
        let touching0: HashSet<(u32, u32)> = if candidate.is_empty() {
            HashSet::new()
        } else {
            let found0 = self.scene.pair_contacts(&candidate, &poses0, |_, _| delta);
            found0.iter().filter(|f| f.contact.distance <= delta).map(|f| f.key.colliders).collect()
        };
        // In a pair that has resting contacts, a contact parry names differently (it may renumber the features of
        // one geometric contact from step to step) is not a new collision unless it sinks as deep as a drift does.
        let resting_pairs: HashSet<(u32, u32)> = resting.iter().map(|k| k.colliders).collect();
        let hits = |f: &Found, resting: &HashSet<ContactKey>| {
            let depth = if resting_pairs.contains(&f.key.colliders) {
                -delta
            } else if touching0.contains(&f.key.colliders) {
                -1e-3 * delta
            } else {
                0.0
            };
            !resting.contains(&f.key) && f.contact.distance < depth
        };
        let fresh = pairs_where(&|f| hits(f, resting));
        let mut event: Option<f64> = None;
        if !fresh.is_empty() {
            // The chapter's bisection: the last time before any new contact interpenetrates. It goes on past the
            // tolerance until the time has moved off the step's start: a flight shorter than the tolerance (a tiny
            // bounce) would otherwise stop at t0 again and again.
            let (mut lo, mut hi) = (t0, t1);
            while hi - lo > self.settings.time_tolerance || lo <= t0 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                self.report.bisection_steps += 1;
                let y = step.state_at(mid)?;
                let poses = actor_poses(step.system(), &y, &statics);
                let found = self.scene.pair_contacts(&fresh, &poses, |_, _| delta);
                if found.iter().any(|f| hits(f, &self.resting_keys)) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            event = Some(lo);
        }
        // Passes through: pairs apart at both ends whose distances leave room for a contact in between.
        let touching: HashSet<(usize, usize)> =
            found1.iter().map(|f| (f.key.colliders.0 as usize, f.key.colliders.1 as usize)).collect();
        for &(i, j) in pairs.iter().filter(|p| !touching.contains(p)) {
            let (sa, sb, oa, ob, ia, ib) = self.scene.shapes(i, j);
            let (sa, sb) = (sa.clone(), sb.clone());
            let d0 = distance(&sa, &(poses0[ia] * oa), &sb, &(poses0[ib] * ob)).unwrap_or(f64::INFINITY);
            let d1 = distance(&sa, &(poses1[ia] * oa), &sb, &(poses1[ib] * ob)).unwrap_or(f64::INFINITY);
            let closing = speeds[ia].0 + speeds[ib].0;
            if d1 <= delta || d0 + d1 > closing * h {
                continue;
            }
            let mut trouble: Option<OdeError> = None;
            let model_statics = statics.clone();
            let mut poses = |t: f64| -> Result<(Isometry3<f64>, Isometry3<f64>), ShapeError> {
                let y = step.state_at(t).map_err(|e| {
                    let msg = e.to_string();
                    trouble = Some(e);
                    ShapeError { name: "poses", reason: msg }
                })?;
                let p = actor_poses(step.system(), &y, &model_statics);
                Ok((p[ia] * oa, p[ib] * ob))
            };
            let options = ToiOptions {
                method: ToiMethod::Bisection,
                tolerance: (delta / closing.max(1e-300)).max(self.settings.time_tolerance),
                max_iterations: 10_000,
            };
            // A pair touching at the step's start (it has just bounced apart) is searched from the first of
            // t0 + h/2^30, h/2^29, ..., h/2 at which it is clear, so that coming back later in a long step (a
            // ballistic flight that Dormand-Prince takes in one step) is not missed; one still touching at t0 + h/2
            // is left to the next step.
            let mut start = t0;
            if d0 <= delta {
                let clear = (1..=30).rev().map(|k| t0 + h / f64::from(1u32 << k)).find(|&t| {
                    poses(t).ok().and_then(|(pa, pb)| distance(&sa, &pa, &sb, &pb).ok()).is_some_and(|d| d > delta)
                });
                match clear {
                    Some(t) => start = t,
                    None => continue,
                }
            }
            match first_contact(&sa, &sb, poses, start, t1, closing, &options) {
                Ok(Some(hit)) => {
                    self.report.bisection_steps += hit.iterations;
                    event = Some(event.map_or(hit.time, |e: f64| e.min(hit.time)));
                }
                Ok(None) => {}
                // A pair that grazes (apart by little more than the contact distance while turning fast) can need
                // more queries than the search may make: the step is cut in half instead, and the next one searches
                // a shorter interval.
                Err(e) if trouble.is_none() && e.name == "options" => {
                    self.report.bisection_steps += options.max_iterations;
                    let half = t0 + 0.5 * h;
                    event = Some(event.map_or(half, |e: f64| e.min(half)));
                }
                Err(e) => return Err(trouble.unwrap_or_else(|| failure(t0, format!("pass-through search: {e}")))),
            }
        }
        self.report.collision_checks += self.scene.checks - checks;
        if drift {
            event = Some(event.map_or(t1, |e| e.min(t1)));
        }
        Ok(event)
    }

    /// Per actor: a bound on the speed of its points over the step (the larger of the two ends, +10% for the
    /// interpolant), and how fast its velocity changes (|v1 - v0| / 4, the bulge of its path per unit time).
    #[allow(clippy::needless_range_loop)]
    fn speeds(&self, model: &Model, y0: &[f64], y1: &[f64], statics: &[Isometry3<f64>]) -> Vec<(f64, f64)> {
        let l = model.layout;
        let mut radius = vec![0.0f64; self.scene.actors()];
        for c in &self.scene.colliders {
            let a = self.scene.index(c.actor);
            radius[a] = radius[a].max(if c.reach.is_finite() { c.reach } else { 0.0 });
        }
        let mut out = vec![(0.0, 0.0); l.particles + l.bodies + statics.len()];
        for i in 0..l.particles {
            let (v0, v1) = (get3(y0, l.pv(i)), get3(y1, l.pv(i)));
            out[i] = (1.1 * v0.norm().max(v1.norm()), 0.25 * (v1 - v0).norm());
        }
        for j in 0..l.bodies {
            let a = l.particles + j;
            let (k0, k1) = (model.body_kin(y0, j), model.body_kin(y1, j));
            let s0 = k0.velocity.norm() + k0.omega.norm() * radius[a];
            let s1 = k1.velocity.norm() + k1.omega.norm() * radius[a];
            let change = (k1.velocity - k0.velocity).norm()
                + (k1.omega - k0.omega).norm() * radius[a]
                + 0.5 * k0.omega.norm().max(k1.omega.norm()).powi(2) * radius[a];
            out[a] = (1.1 * s0.max(s1), 0.25 * change);
        }
        out
    }
}

/// Writes the velocities of tumble-contact's bodies into state y (momenta for bodies).
#[allow(clippy::needless_range_loop)]
fn write_velocities(model: &Model, y: &mut [f64], v: &[tumble_contact::BodyVelocity]) {
    let l = model.layout;
    for i in 0..l.particles {
        set3(y, l.pv(i), &v[i].linear);
    }
    for (j, b) in model.bodies.iter().enumerate() {
        let k = &model.kin[j];
        let a = l.particles + j;
        set3(y, l.bp(j), &(v[a].linear * b.mass));
        set3(y, l.bl(j), &(k.rot * b.inertia * k.rot.transpose() * v[a].angular));
    }
}

/// Moves particles and bodies by the displacements and small rotations of a position correction.
#[allow(clippy::needless_range_loop)]
fn shift_positions(model: &Model, y: &mut [f64], shift: &[tumble_contact::BodyVelocity]) {
    let l = model.layout;
    for i in 0..l.particles {
        let x = get3(y, l.px(i)) + shift[i].linear;
        set3(y, l.px(i), &x);
    }
    for j in 0..l.bodies {
        let a = l.particles + j;
        let x = get3(y, l.bx(j)) + shift[a].linear;
        let q =
            UnitQuaternion::from_scaled_axis(shift[a].angular) * UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
        set3(y, l.bx(j), &x);
        set_quat(y, l.bq(j), &q);
    }
}

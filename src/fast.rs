//! Fast mode, one step: the applied forces at the start of the step, contacts found with a margin (how far each
//! pair can close in the step, plus a fixed margin), one conic program per island for the new velocities (friction
//! lagged on each contact's previous normal impulse), then positions from the new velocities (semi-implicit
//! Euler). Islands that have been still long enough sleep and are skipped until something moving touches them.

use crate::contact_scene::{ContactKey, ContactScene};
use crate::layout::{get3, get_quat, set3, set_quat};
use crate::mode::{FastFriction, FastSettings};
use crate::model::Compiled;
use crate::report::WorldReport;
use crate::sleep::Sleep;
use crate::WorldError;
use nalgebra::UnitQuaternion;
use std::collections::HashMap;
use std::time::Instant;
use tumble_contact::{
    free_velocity, islands, velocity_step, velocity_step_lagged, BodyState, BodyVelocity, StepSettings,
};
use tumble_integrate::{OdeError, OdeSystem};

/// The method name fast mode reports.
pub(crate) const FAST: &str = "fast (semi-implicit Euler, contact by conic program)";

/// The state and memory of a fast-mode world.
pub(crate) struct FastEngine {
    pub compiled: Compiled,
    pub scene: Option<ContactScene>,
    pub t: f64,
    pub y: Vec<f64>,
    settings: FastSettings,
    previous: HashMap<ContactKey, f64>,
    sleep: Sleep,
    dy: Vec<f64>,
    /// What the steps since the last `take_report` cost.
    pub report: WorldReport,
    /// Largest penetration among the contacts of the last step.
    pub penetration: f64,
}

fn failure(t: f64, message: String) -> WorldError {
    WorldError::Simulation(OdeError::System { t, message })
}

impl FastEngine {
    pub fn new(compiled: Compiled, scene: Option<ContactScene>, t: f64, y: Vec<f64>, settings: FastSettings) -> Self {
        let actors = compiled.model.layout.particles + compiled.model.layout.bodies;
        FastEngine {
            dy: vec![0.0; y.len()],
            sleep: Sleep::new(actors),
            compiled,
            scene,
            t,
            y,
            settings,
            previous: HashMap::new(),
            report: WorldReport::new(FAST),
            penetration: 0.0,
        }
    }

    /// What a failed call must put back: time, state, lagged impulses and sleep.
    pub fn snapshot(&self) -> (f64, Vec<f64>, HashMap<ContactKey, f64>, Sleep) {
        (self.t, self.y.clone(), self.previous.clone(), self.sleep.clone())
    }

    pub fn restore(&mut self, (t, y, previous, sleep): (f64, Vec<f64>, HashMap<ContactKey, f64>, Sleep)) {
        (self.t, self.y, self.previous, self.sleep) = (t, y, previous, sleep);
    }

    pub fn take_report(&mut self) -> WorldReport {
        std::mem::replace(&mut self.report, WorldReport::new(FAST))
    }

    /// The bodies as tumble-contact sees them, with the applied forces of the current state (`dy` from the
    /// equations of motion); sleeping actors are passed as fixed.
    fn body_states(&self, statics: &[nalgebra::Isometry3<f64>]) -> Vec<BodyState> {
        let (m, y, dy) = (&self.compiled.model, &self.y, &self.dy);
        let l = m.layout;
        let mut out = Vec::with_capacity(l.particles + l.bodies + statics.len());
        for (i, p) in m.particles.iter().enumerate() {
            let x = nalgebra::Point3::from(get3(y, l.px(i)));
            if self.sleep.asleep(i) {
                out.push(BodyState::fixed(x));
                continue;
            }
            let mut s = BodyState::particle(p.mass, x, get3(y, l.pv(i)));
            s.force = get3(dy, l.pv(i)) * p.mass;
            out.push(s);
        }
        for (j, b) in m.bodies.iter().enumerate() {
            let x = nalgebra::Point3::from(get3(y, l.bx(j)));
            if self.sleep.asleep(l.particles + j) {
                out.push(BodyState::fixed(x));
                continue;
            }
            let k = m.body_kin(y, j);
            let inertia = k.rot * b.inertia * k.rot.transpose();
            let mut s = BodyState::rigid(b.mass, inertia, x);
            s.inv_inertia = k.rot * b.inv_inertia * k.rot.transpose();
            s.velocity = k.velocity;
            s.angular_velocity = k.omega;
            s.force = get3(dy, l.bp(j));
            // The step conserves angular momentum: w* = I^-1 (L + h tau). tumble-contact adds Euler's gyroscopic
            // term -w x I w explicitly, which pumps energy into a fast spin; adding it back here cancels it.
            s.torque = get3(dy, l.bl(j)) + k.omega.cross(&(inertia * k.omega));
            out.push(s);
        }
        out.extend(statics.iter().map(|p| BodyState::fixed(nalgebra::Point3::from(p.translation.vector))));
        out
    }

    /// One step of size h. On error the engine is unchanged.
    pub fn step(&mut self, h: f64) -> Result<(), WorldError> {
        let clock = Instant::now();
        let t = self.t;
        self.compiled.model.rhs(t, &self.y, &mut self.dy).map_err(|e| failure(t, e.to_string()))?;
        let statics = self.scene.as_ref().map(|s| s.static_poses.clone()).unwrap_or_default();
        let mut states = self.body_states(&statics);
        // Contacts, pairs that cannot close and pairs of sleeping or static actors left out.
        let found = match &mut self.scene {
            Some(scene) => {
                let c0 = Instant::now();
                let dynamic = self.sleep.len();
                for a in 0..dynamic {
                    scene.inert[a] = self.sleep.asleep(a);
                }
                let poses = scene.poses(&self.y);
                let reach = scene.reach(&states, h);
                let checks = scene.checks;
                let f = crate::manifold::reduce(scene.find(&poses, &reach, self.settings.margin));
                self.report.collision_checks += scene.checks - checks;
                self.report.collision_seconds += c0.elapsed().as_secs_f64();
                f
            }
            None => Vec::new(),
        };
        let dynamic = self.sleep.len();
        let woke = self.sleep.wake_touched(&found, dynamic);
        if woke {
            states = self.body_states(&statics);
        }
        let found: Vec<_> = found
            .into_iter()
            .filter(|f| states[f.contact.a].is_dynamic() || states[f.contact.b].is_dynamic())
            .collect();
        let contacts: Vec<tumble_contact::Contact> = found.iter().map(|f| f.contact).collect();
        self.penetration = contacts.iter().map(|c| -c.distance).fold(0.0, f64::max);
        let mut settings = StepSettings {
            erp: self.settings.erp,
            bounce_threshold: self.settings.bounce_threshold,
            ..StepSettings::new(h)
        };
        settings.solver.iterative_refinement = false;
        let c0 = Instant::now();
        let (velocities, normal): (Vec<BodyVelocity>, Vec<f64>) = if contacts.is_empty() {
            (states.iter().map(|b| free_velocity(b, h)).collect(), Vec::new())
        } else {
            let out = self.solve_contacts(&states, &contacts, &found, &settings)?;
            for (c, p) in contacts.iter().zip(&out.normal_impulses) {
                if *p > 0.0 {
                    self.report.impulses += 1;
                    if c.relative_normal_velocity(&states) < -self.settings.bounce_threshold {
                        self.report.collisions += 1;
                    }
                }
            }
            (out.velocities, out.normal_impulses)
        };
        self.report.contact_seconds += c0.elapsed().as_secs_f64();
        self.previous = found.iter().zip(&normal).map(|(f, &p)| (f.key, p)).collect();
        self.advance_positions(&velocities, h);
        if let (true, Some(scene)) = (self.settings.sleep, &self.scene) {
            let speeds = scene.reach(&states_with(&states, &velocities), 1.0);
            self.sleep.update(&found, &speeds, &self.settings, h);
            self.sleep.freeze(&mut self.y, &self.compiled.model);
        }
        self.t = t + h;
        self.report.sleepers = self.sleep.count();
        self.report.max_penetration = self.report.max_penetration.max(self.penetration);
        let r = &mut self.report.integrator;
        r.steps += 1;
        r.rhs_evals += 1;
        r.min_step = r.min_step.min(h);
        r.max_step = r.max_step.max(h);
        self.report.integrator.wall_seconds += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// The contact solve of a step: the conic program per island, friction lagged on each contact's previous normal
    /// impulse (a first pass gives new contacts one). A bounce in a time step can put energy in: Newton's law at
    /// several simultaneous contacts (two corners of a rocking box, Kane's paradox), and a bounce started up to a
    /// step's travel above the floor. An island that bounced and whose mechanical energy (kinetic plus gravity, at the
    /// positions the step will reach) would end above where it started is solved again with its restitution scaled:
    /// by the largest factor that keeps the energy, found by the secant method from the full answer and the one at
    /// 0.98 in up to three more solves (a bounce begun a step's travel u h above the floor gains up to m g u h, about
    /// 2% of its energy at 4 m/s and h = 1/240 s, so the factor is about 0.99), else by 0.9, 0.75, 0.5, 0.25 or 0.
    fn solve_contacts(
        &mut self,
        states: &[BodyState],
        contacts: &[tumble_contact::Contact],
        found: &[crate::contact_scene::Found],
        settings: &StepSettings,
    ) -> Result<tumble_contact::VelocityStep, WorldError> {
        let t = self.t;
        // A contact new to a pair that touched last step starts from the pair's last total impulse shared among its
        // contacts now; only islands with a pair that has just met need the first pass.
        let mut last_pair: HashMap<(u32, u32), f64> = HashMap::new();
        for (key, p) in &self.previous {
            *last_pair.entry(key.colliders).or_default() += p;
        }
        let mut now_pair: HashMap<(u32, u32), usize> = HashMap::new();
        for f in found {
            *now_pair.entry(f.key.colliders).or_default() += 1;
        }
        let known: Vec<Option<f64>> = found
            .iter()
            .map(|f| {
                let pair = f.key.colliders;
                self.previous.get(&f.key).copied().or_else(|| last_pair.get(&pair).map(|p| p / now_pair[&pair] as f64))
            })
            .collect();
        let mut previous: Vec<f64> = known.iter().map(|p| p.unwrap_or(0.0)).collect();
        let friction = self.settings.friction;
        let mut solves = 0;
        let mut solve = |cs: &[tumble_contact::Contact], prev: &[f64]| {
            let out = match friction {
                FastFriction::Lagged => velocity_step_lagged(states, cs, prev, settings),
                FastFriction::Cone => velocity_step(states, cs, settings),
            }
            .map_err(|e| failure(t, format!("contact solve: {e}")))?;
            solves += out.solver_calls;
            Ok::<_, WorldError>(out)
        };
        let groups = islands(states, contacts);
        if friction == FastFriction::Lagged && known.iter().any(|p| p.is_none()) {
            let fresh: Vec<usize> =
                groups.iter().filter(|g| g.iter().any(|&i| known[i].is_none())).flatten().copied().collect();
            let sub: Vec<tumble_contact::Contact> = fresh.iter().map(|&i| contacts[i]).collect();
            let sub_prev: Vec<f64> = fresh.iter().map(|&i| previous[i]).collect();
            let first = solve(&sub, &sub_prev)?;
            for (&i, p) in fresh.iter().zip(&first.normal_impulses) {
                if known[i].is_none() {
                    previous[i] = *p;
                }
            }
        }
        let mut out = solve(contacts, &previous)?;
        self.report.islands += groups.len();
        let h = settings.dt;
        for island in &groups {
            let bounces = island.iter().any(|&i| {
                contacts[i].restitution > 0.0
                    && contacts[i].relative_normal_velocity(states) < -settings.bounce_threshold
            });
            if !bounces {
                continue;
            }
            let members = island_bodies(states, contacts, island);
            let g = self.compiled.model.gravity;
            let start: Vec<BodyVelocity> =
                states.iter().map(|b| BodyVelocity { linear: b.velocity, angular: b.angular_velocity }).collect();
            let energy = |v: &[BodyVelocity], dt: f64| {
                kinetic(states, v, &members)
                    - members
                        .iter()
                        .map(|&k| g.dot(&(states[k].position.coords + v[k].linear * dt)) / states[k].inv_mass)
                        .sum::<f64>()
            };
            let e0 = energy(&start, 0.0);
            let limit = e0 + 1e-12 * e0.abs().max(kinetic(states, &start, &members));
            let e_one = energy(&out.velocities, h);
            if e_one <= limit {
                continue;
            }
            let mut solve_scaled = |scale: f64| {
                let sub: Vec<tumble_contact::Contact> = island
                    .iter()
                    .map(|&i| tumble_contact::Contact { restitution: contacts[i].restitution * scale, ..contacts[i] })
                    .collect();
                let sub_prev: Vec<f64> = island.iter().map(|&i| previous[i]).collect();
                solve(&sub, &sub_prev)
            };
            // The largest restitution scale that does not gain energy, by the secant method on the energy as a
            // function of the scale (smooth while restitution sets the bounce), from the full answer and the one at
            // 0.98; if no scale it tries keeps the energy, 0.9, 0.75, 0.5, 0.25 and the plastic answer.
            let at98 = solve_scaled(0.98)?;
            let e98 = energy(&at98.velocities, h);
            let mut best = (e98 <= limit).then_some((0.98, at98));
            let (mut a, mut b) = ((0.98, e98), (1.0, e_one));
            for _ in 0..3 {
                if b.1 == a.1 {
                    break;
                }
                let scale = (a.0 + (limit - a.1) * (b.0 - a.0) / (b.1 - a.1)).clamp(0.0, 1.0) * (1.0 - 1e-9);
                let again = solve_scaled(scale)?;
                let e = energy(&again.velocities, h);
                if e <= limit && best.as_ref().is_none_or(|(s, _)| scale > *s) {
                    best = Some((scale, again));
                    if limit - e <= 1e-9 * limit.abs().max(1e-300) {
                        break;
                    }
                }
                (a, b) = (b, (scale, e));
            }
            let mut chosen = best.map(|(_, v)| v);
            for scale in [0.9, 0.75, 0.5, 0.25, 0.0] {
                if chosen.is_some() {
                    break;
                }
                let again = solve_scaled(scale)?;
                if energy(&again.velocities, h) <= limit || scale == 0.0 {
                    chosen = Some(again);
                }
            }
            let chosen = chosen.expect("the plastic answer is always taken");
            for &k in &members {
                out.velocities[k] = chosen.velocities[k];
            }
            for (slot, &i) in island.iter().enumerate() {
                out.normal_impulses[i] = chosen.normal_impulses[slot];
                out.friction_impulses[i] = chosen.friction_impulses[slot];
            }
        }
        self.report.qp_solves += solves;
        Ok(out)
    }

    /// Semi-implicit Euler: positions and orientations from the new velocities; momenta from them.
    #[allow(clippy::needless_range_loop)]
    fn advance_positions(&mut self, v: &[BodyVelocity], h: f64) {
        let m = &self.compiled.model;
        let l = m.layout;
        for i in 0..l.particles {
            if self.sleep.asleep(i) {
                continue;
            }
            let x = get3(&self.y, l.px(i)) + v[i].linear * h;
            set3(&mut self.y, l.px(i), &x);
            set3(&mut self.y, l.pv(i), &v[i].linear);
        }
        for (j, b) in m.bodies.iter().enumerate() {
            let a = l.particles + j;
            if self.sleep.asleep(a) {
                continue;
            }
            let (lin, w) = (v[a].linear, v[a].angular);
            let x = get3(&self.y, l.bx(j)) + lin * h;
            let q0 = UnitQuaternion::new_normalize(get_quat(&self.y, l.bq(j)));
            // L from the inertia the velocities were solved with. Turning the body under a fixed L raises
            // 1/2 L . I(q)^-1 L at second order in the turn (the second derivative is (w x L) . I^-1 (w x L) >= 0),
            // a steady gain for a fast spin; scaling L back to the energy before the turn removes it.
            let r0 = q0.to_rotation_matrix().into_inner();
            let mut momentum = r0 * b.inertia * r0.transpose() * w;
            let q1 = UnitQuaternion::from_scaled_axis(w * h) * q0;
            let r1 = q1.to_rotation_matrix().into_inner();
            let before = 0.5 * momentum.dot(&w);
            let after = 0.5 * momentum.dot(&(r1 * b.inv_inertia * r1.transpose() * momentum));
            if after > before && after > 0.0 {
                momentum *= (before / after).sqrt();
            }
            set3(&mut self.y, l.bx(j), &x);
            set_quat(&mut self.y, l.bq(j), &q1);
            set3(&mut self.y, l.bp(j), &(lin * b.mass));
            set3(&mut self.y, l.bl(j), &momentum);
        }
    }
}

/// The moving bodies of an island.
fn island_bodies(states: &[BodyState], contacts: &[tumble_contact::Contact], island: &[usize]) -> Vec<usize> {
    let mut members: Vec<usize> =
        island.iter().flat_map(|&i| [contacts[i].a, contacts[i].b]).filter(|&k| states[k].is_dynamic()).collect();
    members.sort_unstable();
    members.dedup();
    members
}

/// Kinetic energy of the bodies `members` at velocities v.
fn kinetic(states: &[BodyState], v: &[BodyVelocity], members: &[usize]) -> f64 {
    members
        .iter()
        .map(|&k| {
            let b = &states[k];
            0.5 * v[k].linear.norm_squared() / b.inv_mass + 0.5 * v[k].angular.dot(&(b.inertia * v[k].angular))
        })
        .sum()
}

/// The states with these velocities (for speed bounds).
fn states_with(states: &[BodyState], v: &[BodyVelocity]) -> Vec<BodyState> {
    states.iter().zip(v).map(|(s, v)| BodyState { velocity: v.linear, angular_velocity: v.angular, ..*s }).collect()
}

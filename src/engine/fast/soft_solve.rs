//! Fast mode, third stage with the soft solver: new velocities and poses from Catto's soft step (tumble-contact's
//! `soft_step`: substeps, soft contacts in hertz, Coulomb friction), each contact started from its impulses of the
//! last step (matched by feature key; a contact new to a pair that touched takes the pair's mean), and the
//! impulses kept for the next step. The substeps move the bodies themselves, so this stage also gives the poses.

use super::{failure, FastEngine};
use crate::engine::contact_scene::{pair_runs, ContactKey, Found};
use crate::error::WorldError;
use crate::mode::SoftSolver;
use crate::model::joints::JointEnd;
use crate::plan::Stage;
use nalgebra::Point3;
use std::time::Instant;
use tumble_contact::{soft_step_with_joints, BodyState, Contact, Joint, SoftImpulse, SoftSettings, SoftStep};

/// Each contact's impulses from the last step: its own if it was there, else its pair's mean, else none.
/// `previous` is sorted by key (so a pair's contacts are neighbours, summed in key order).
fn warm_impulses(previous: &[(ContactKey, SoftImpulse)], found: &[Found]) -> Vec<SoftImpulse> {
    found
        .iter()
        .map(|f| match previous.binary_search_by(|(k, _)| k.cmp(&f.key)) {
            Ok(k) => previous[k].1,
            Err(_) => {
                let start = previous.partition_point(|(k, _)| k.colliders < f.key.colliders);
                let pair = previous[start..].iter().take_while(|(k, _)| k.colliders == f.key.colliders);
                let (mut sum, mut n) = (SoftImpulse::default(), 0usize);
                for (_, p) in pair {
                    sum.normal += p.normal;
                    sum.tangent += p.tangent;
                    n += 1;
                }
                if n == 0 {
                    SoftImpulse::default()
                } else {
                    SoftImpulse { normal: sum.normal / n as f64, tangent: sum.tangent / n as f64 }
                }
            }
        })
        .collect()
}

/// The step's impulses by contact key, sorted (a key found twice keeps its last impulse).
fn by_key(found: &[Found], impulses: &[SoftImpulse]) -> Vec<(ContactKey, SoftImpulse)> {
    let mut out: Vec<(ContactKey, SoftImpulse)> = found.iter().map(|f| f.key).zip(impulses.iter().copied()).collect();
    match pair_runs(&out, |e| e.0.colliders) {
        // pairs already in order (the scene gives them so): sort each pair's few contacts in place (stably)
        Some(runs) => runs.into_iter().for_each(|r| out[r].sort_by_key(|e| e.0)),
        None => out.sort_by_key(|e| e.0),
    }
    // keep the last of equal keys, as a map built in contact order would
    let mut kept: Vec<(ContactKey, SoftImpulse)> = Vec::with_capacity(out.len());
    for entry in out {
        match kept.last_mut() {
            Some(last) if last.0 == entry.0 => *last = entry,
            _ => kept.push(entry),
        }
    }
    kept
}

impl FastEngine {
    /// The soft step of h for the actors `states` with contacts `found`.
    pub(super) fn soft_solve(
        &mut self,
        states: &[BodyState],
        found: &[Found],
        h: f64,
        soft: SoftSolver,
    ) -> Result<SoftStep, WorldError> {
        let clock = Instant::now();
        let contacts: Vec<Contact> = found.iter().map(|f| f.contact).collect();
        let warm = warm_impulses(&self.warm, found);
        let settings = SoftSettings {
            substeps: soft.substeps,
            iterations: soft.iterations,
            contact_hertz: soft.contact_hertz,
            damping_ratio: soft.damping_ratio,
            max_push_out: soft.max_push_out,
            bounce_threshold: self.settings.bounce_threshold,
            threads: self.threads,
            ..SoftSettings::default()
        };
        let (actors, joints) = self.joints_at_start(states);
        let actors = actors.as_deref().unwrap_or(states);
        let out = soft_step_with_joints(actors, &contacts, &warm, &joints, &self.joint_warm, h, &settings)
            .map_err(|e| failure(self.time(), format!("contact solve: {e}")))?;
        self.joint_warm.clone_from(&out.joint_impulses);
        if !joints.is_empty() {
            self.report.stages.mark(Stage::Joints);
        }
        self.warm = by_key(found, &out.impulses);
        self.last_contacts = crate::engine::step_contacts::from_found(found, out.normal_impulses.iter().copied(), h);
        if !found.is_empty() {
            self.report.contact_residual = self.report.contact_residual.max(out.residual);
            self.report.islands += out.islands;
            self.report.stages.mark(Stage::ContactSoftStep);
            self.count_impulses(states, &contacts, &out.normal_impulses);
        }
        self.report.contact_seconds += clock.elapsed().as_secs_f64();
        Ok(out)
    }
}

impl FastEngine {
    /// The joints where the bodies are at the step's start, for the soft step: a dynamic end is its actor, a fixed
    /// end (the world, a static body) an extra fixed actor at its pose, appended to the actors (returned when any).
    fn joints_at_start(&self, states: &[BodyState]) -> (Option<Vec<BodyState>>, Vec<Joint>) {
        let model = &self.compiled.model;
        if model.joints.is_empty() {
            return (None, Vec::new());
        }
        let mut actors = states.to_vec();
        let l = model.layout;
        let mut index = |end: JointEnd| match end {
            JointEnd::Body(j) => l.particles + j,
            JointEnd::Fixed(p) => {
                actors.push(BodyState::fixed(Point3::from(p.translation.vector)));
                actors.len() - 1
            }
        };
        let mut joints = Vec::with_capacity(model.joints.len());
        for cj in &model.joints {
            let (ea, eb) = (model.end_state_of(&self.y, cj.a), model.end_state_of(&self.y, cj.b));
            let (a, b) = (index(cj.a), index(cj.b));
            joints.push(Joint { a, b, frame: cj.frame(&ea, &eb), ..cj.joint });
        }
        (Some(actors), joints)
    }
}

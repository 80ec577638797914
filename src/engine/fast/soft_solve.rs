//! Fast mode, third stage with the soft solver: new velocities and poses from Catto's soft step (tumble-contact's
//! `soft_step`: substeps, soft contacts in hertz, Coulomb friction), each contact started from its impulses of the
//! last step (matched by feature key; a contact new to a pair that touched takes the pair's mean), and the
//! impulses kept for the next step. The substeps move the bodies themselves, so this stage also gives the poses.

use super::{failure, FastEngine};
use crate::engine::contact_scene::{ContactKey, Found};
use crate::error::WorldError;
use crate::mode::SoftSolver;
use crate::plan::Stage;
use std::collections::BTreeMap;
use std::time::Instant;
use tumble_contact::{soft_step, BodyState, Contact, SoftImpulse, SoftSettings, SoftStep};

/// Each contact's impulses from the last step: its own if it was there, else its pair's mean, else none.
fn warm_impulses(previous: &BTreeMap<ContactKey, SoftImpulse>, found: &[Found]) -> Vec<SoftImpulse> {
    let mut pairs: BTreeMap<(u32, u32), (SoftImpulse, usize)> = BTreeMap::new();
    for (key, p) in previous {
        let e = pairs.entry(key.colliders).or_default();
        e.0.normal += p.normal;
        e.0.tangent += p.tangent;
        e.1 += 1;
    }
    found
        .iter()
        .map(|f| {
            previous.get(&f.key).copied().unwrap_or_else(|| match pairs.get(&f.key.colliders) {
                Some((sum, n)) => SoftImpulse { normal: sum.normal / *n as f64, tangent: sum.tangent / *n as f64 },
                None => SoftImpulse::default(),
            })
        })
        .collect()
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
        };
        let out = soft_step(states, &contacts, &warm, h, &settings)
            .map_err(|e| failure(self.time(), format!("contact solve: {e}")))?;
        self.warm = found.iter().zip(&out.impulses).map(|(f, p)| (f.key, *p)).collect();
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

//! The world in accurate mode with contact: advances that stop at every contact event, run a contact phase there
//! and go on; a failure puts the integrator back where the advance began.

use crate::accurate::Accurate;
use crate::contact_scene::ContactScene;
use crate::mode::Mode;
use crate::model::{Compiled, Model};
use crate::report::WorldReport;
use crate::world::Engine;
use crate::World;
use tumble_integrate::OdeError;

/// Events at one time without progress before the advance gives up (a contact phase that cannot settle).
const STUCK: usize = 200;

impl World {
    /// The accurate contact stage for a compiled world, if it has colliders that can touch.
    pub(crate) fn accurate_stage(&self, compiled: &Compiled) -> Option<Accurate> {
        let Mode::Accurate(settings) = self.mode else { return None };
        let scene = ContactScene::build(compiled.model.layout, &self.particles, &self.bodies, &compiled.bodies)?;
        let y = compiled.pack(&self.particles, &self.bodies);
        let size = scene.size(&y);
        Some(Accurate::new(scene, settings, self.gravity.norm(), size))
    }
}

/// Advances to `t_end` (pausing past `pause`), delivering `saves` with the penetration of the last contact phase;
/// returns how many were delivered. On error the integrator is back at its starting time and state.
pub(crate) fn advance(
    e: &mut Engine,
    t_end: f64,
    pause: f64,
    saves: &[f64],
    mut on_save: impl FnMut(&Model, f64, &[f64], f64),
    mut on_event: impl FnMut(f64),
) -> Result<usize, OdeError> {
    let (t0, y0) = (e.integrator.time(), e.integrator.state().to_vec());
    let resting0 = e.compiled.model.resting.clone();
    let result = advance_inner(e, t_end, pause, saves, &mut on_save, &mut on_event);
    if result.is_err() {
        e.integrator.set_state(t0, &y0).expect("the starting state was valid");
        e.compiled.model.resting = resting0;
    }
    result
}

fn advance_inner(
    e: &mut Engine,
    t_end: f64,
    pause: f64,
    saves: &[f64],
    on_save: &mut impl FnMut(&Model, f64, &[f64], f64),
    on_event: &mut impl FnMut(f64),
) -> Result<usize, OdeError> {
    let acc = e.accurate.as_mut().expect("called with a contact stage");
    acc.contact_phase(&mut e.compiled.model, &mut e.integrator)?;
    let (mut done, mut stuck, mut last) = (0, 0, e.integrator.time());
    loop {
        let penetration = acc.penetration;
        let adv = e.integrator.advance_with_events(
            &mut e.compiled.model,
            t_end,
            pause,
            &saves[done..],
            |m, t, y| on_save(m, t, y, penetration),
            |step| acc.detect(step),
        )?;
        done += adv.delivered;
        let Some(t) = adv.event else { return Ok(done) };
        on_event(t);
        stuck = if t > last { 0 } else { stuck + 1 };
        last = t;
        if stuck > STUCK {
            return Err(OdeError::System {
                t,
                message: format!("{STUCK} contact events at one time: the contacts do not settle"),
            });
        }
        acc.contact_phase(&mut e.compiled.model, &mut e.integrator)?;
    }
}

/// Moves the contact counters of an accurate engine into a report.
pub(crate) fn take_contact_report(e: &mut Engine, r: &mut WorldReport) {
    if let Some(acc) = &mut e.accurate {
        let c = std::mem::replace(&mut acc.report, WorldReport::new("accurate"));
        r.merge_contact(&c);
    }
    if let Some(set) = &mut e.compiled.model.resting {
        r.qp_solves += std::mem::take(&mut set.solves);
        r.contact_seconds += std::mem::take(&mut set.seconds);
    }
}

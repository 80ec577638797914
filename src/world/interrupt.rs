//! An interrupted run keeps its work: the frames recorded so far, and the world put at the last of them (its
//! objects at that frame's state, the joints that broke by then broken, the engine built afresh from them), so the
//! next call carries on from there. A failure is not an interrupt: after one the world is back where the call began.

use super::World;
use crate::model::ResolvedBody;
use crate::run::Run;

impl World {
    /// Puts the world at `run`'s last frame (the engine already back at the call's start and dropped here) and
    /// trims what the run logged after that frame; marks the run interrupted. A run without frames changes nothing.
    pub(crate) fn keep_to_last_frame(&mut self, run: &mut Run) {
        run.interrupted = true;
        let Some(last) = run.frames().checked_sub(1) else { return };
        let t = run.times[last];
        for (i, &h) in run.particles.iter().enumerate() {
            if let Some(p) = self.particles.get_mut(h) {
                p.position = run.particle_position(last, i);
                p.velocity = run.particle_velocity(last, i);
            }
        }
        for (j, &h) in run.bodies.iter().enumerate() {
            let (ResolvedBody::Dynamic(_), Some(b)) = (run.sources[j], self.bodies.get_mut(h)) else { continue };
            b.position = run.body_position(last, j);
            b.orientation = run.body_orientation(last, j);
            let (v, w) = (run.body_velocity(last, j), run.body_angular_velocity(last, j));
            match &mut b.kinematic {
                Some(k) => (k.velocity, k.angular_velocity) = (v, w),
                None => (b.momentum, b.angular_momentum) = (v * b.mass, b.world_inertia() * w),
            }
        }
        for &(when, h) in &run.joint_breaks {
            if let (true, Some(j)) = (when <= t, self.joints.get_mut(h)) {
                j.broken = true;
            }
        }
        run.joint_breaks.retain(|&(when, _)| when <= t);
        run.contact_events.retain(|&when| when <= t);
        let steps = run.step_times.partition_point(|&when| when <= t);
        run.step_times.truncate(steps);
        run.step_sizes.truncate(steps);
        self.time = t;
        self.drop_engine();
        self.stepped = true;
    }
}

//! A recorded run: frames of state at equal intervals, energy and momenta per frame, every accepted step's size,
//! and the report of what the run cost.

use crate::model::layout::{get3, get_quat};
use crate::model::{Model, ResolvedBody};
use crate::report::WorldReport;
use crate::spring::{BodyHandle, ParticleHandle};
use nalgebra::{Point3, UnitQuaternion, Vector3};

/// The frame interval of a run when none is given (s): 60 frames a second.
pub const DEFAULT_FRAME_INTERVAL: f64 = 1.0 / 60.0;

/// Frames of a run. Particles and bodies appear in the order of `particles` and `bodies` (all bodies, static
/// ones included, in the world's order). Per-frame arrays are flat: frame-major, then object, then component.
#[derive(Clone, Debug)]
pub struct Run {
    /// Frame times.
    pub times: Vec<f64>,
    /// The particles, in column order.
    pub particles: Vec<ParticleHandle>,
    /// The bodies, in column order.
    pub bodies: Vec<BodyHandle>,
    pub(crate) particle_positions: Vec<f64>,
    pub(crate) particle_velocities: Vec<f64>,
    pub(crate) body_positions: Vec<f64>,
    pub(crate) body_orientations: Vec<f64>,
    pub(crate) body_velocities: Vec<f64>,
    pub(crate) body_angular_velocities: Vec<f64>,
    /// Kinetic energy per frame.
    pub kinetic_energy: Vec<f64>,
    /// Potential energy per frame (gravity, springs, restoring terms).
    pub potential_energy: Vec<f64>,
    pub(crate) momentum: Vec<f64>,
    pub(crate) angular_momentum: Vec<f64>,
    /// End time of every accepted step.
    pub step_times: Vec<f64>,
    /// Size of every accepted step. A span where everything sleeps is no step (the clock jumps over it), so the
    /// sizes of a run that slept sum to less than its duration.
    pub step_sizes: Vec<f64>,
    /// Largest penetration among the contacts at each frame (m; zero without contact).
    pub penetration: Vec<f64>,
    /// Times of the contact events of accurate mode (collisions located by bisection, and drift corrections).
    pub contact_events: Vec<f64>,
    /// The joints, in the world's order, and the time each joint that broke during the run broke, in order.
    pub joints: Vec<crate::joint::JointHandle>,
    pub joint_breaks: Vec<(f64, crate::joint::JointHandle)>,
    /// How many contact points each frame has (the contacts of the step that ended there).
    pub contact_counts: Vec<usize>,
    /// The contact points of all frames, frame after frame: a point (x, y, z) then its normal (x, y, z).
    pub(crate) contact_points: Vec<f64>,
    /// What the run cost.
    pub report: WorldReport,
    /// Whether the run was interrupted (its control stopped it, Ctrl-C in Python): its frames are those done, and
    /// the world was left at the last of them.
    pub interrupted: bool,
    pub(crate) sources: Vec<ResolvedBody>,
}

impl Run {
    pub(crate) fn new(
        particles: Vec<ParticleHandle>,
        bodies: Vec<BodyHandle>,
        sources: Vec<ResolvedBody>,
        method: &'static str,
    ) -> Self {
        Run {
            times: Vec::new(),
            particles,
            bodies,
            particle_positions: Vec::new(),
            particle_velocities: Vec::new(),
            body_positions: Vec::new(),
            body_orientations: Vec::new(),
            body_velocities: Vec::new(),
            body_angular_velocities: Vec::new(),
            kinetic_energy: Vec::new(),
            potential_energy: Vec::new(),
            momentum: Vec::new(),
            angular_momentum: Vec::new(),
            step_times: Vec::new(),
            step_sizes: Vec::new(),
            penetration: Vec::new(),
            contact_events: Vec::new(),
            joints: Vec::new(),
            joint_breaks: Vec::new(),
            contact_counts: Vec::new(),
            contact_points: Vec::new(),
            report: WorldReport::new(method),
            interrupted: false,
            sources,
        }
    }

    /// Books joint `k` (the world's k-th) as broken at time t.
    pub(crate) fn break_joint(&mut self, t: f64, k: usize) {
        if let Some(&h) = self.joints.get(k) {
            self.joint_breaks.push((t, h));
        }
    }

    /// Appends one accepted step: its end time and size.
    pub(crate) fn log_step(&mut self, t: f64, h: f64) {
        self.step_times.push(t);
        self.step_sizes.push(h);
    }

    /// Appends the frame at time t with state y, the largest penetration among the contacts there and the contacts'
    /// points and normals (only read: recording frames never changes the physics).
    pub(crate) fn record<I>(&mut self, model: &Model, t: f64, y: &[f64], penetration: f64, contacts: I)
    where
        I: IntoIterator<Item = (Point3<f64>, Vector3<f64>)>,
    {
        let l = model.layout;
        self.times.push(t);
        self.penetration.push(penetration);
        let before = self.contact_points.len();
        for (p, n) in contacts {
            self.contact_points.extend_from_slice(&[p.x, p.y, p.z, n.x, n.y, n.z]);
        }
        self.contact_counts.push((self.contact_points.len() - before) / 6);
        self.particle_positions.extend_from_slice(&y[l.px(0)..l.px(0) + 3 * l.particles]);
        self.particle_velocities.extend_from_slice(&y[l.pv(0)..l.pv(0) + 3 * l.particles]);
        for source in &self.sources {
            let (x, q, v, w) = match *source {
                ResolvedBody::Dynamic(j) => match &model.bodies[j].kinematic {
                    // a kinematic body is on its path (frames between steps are interpolated, its path exact)
                    Some(path) => {
                        let (pose, (v, w)) = (path.pose_at(t), path.velocity_at(t));
                        (pose.translation.vector, pose.rotation, v, w)
                    }
                    None => {
                        let k = model.body_kin(y, j);
                        (get3(y, l.bx(j)), UnitQuaternion::new_normalize(get_quat(y, l.bq(j))), k.velocity, k.omega)
                    }
                },
                ResolvedBody::Fixed(p) => (p.translation.vector, p.rotation, Vector3::zeros(), Vector3::zeros()),
            };
            self.body_positions.extend_from_slice(x.as_slice());
            self.body_orientations.extend_from_slice(&[q.w, q.i, q.j, q.k]);
            self.body_velocities.extend_from_slice(v.as_slice());
            self.body_angular_velocities.extend_from_slice(w.as_slice());
        }
        self.kinetic_energy.push(model.kinetic_energy(y));
        self.potential_energy.push(model.potential_energy(y));
        self.momentum.extend_from_slice(model.momentum(y).as_slice());
        self.angular_momentum.extend_from_slice(model.angular_momentum(y).as_slice());
    }

    /// The contact points and normals at `frame` (the contacts of the step that ended there; empty without contact).
    pub fn contacts(&self, frame: usize) -> Vec<(Point3<f64>, Vector3<f64>)> {
        let start: usize = self.contact_counts[..frame].iter().sum();
        let data = &self.contact_points[6 * start..6 * (start + self.contact_counts[frame])];
        data.chunks_exact(6).map(|c| (Point3::new(c[0], c[1], c[2]), Vector3::new(c[3], c[4], c[5]))).collect()
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    fn vec3(data: &[f64], frame: usize, count: usize, i: usize) -> Vector3<f64> {
        let k = 3 * (frame * count + i);
        Vector3::new(data[k], data[k + 1], data[k + 2])
    }

    /// Position of particle column `i` at `frame`.
    pub fn particle_position(&self, frame: usize, i: usize) -> Vector3<f64> {
        Self::vec3(&self.particle_positions, frame, self.particles.len(), i)
    }
    /// Velocity of particle column `i` at `frame`.
    pub fn particle_velocity(&self, frame: usize, i: usize) -> Vector3<f64> {
        Self::vec3(&self.particle_velocities, frame, self.particles.len(), i)
    }
    /// Position of body column `j` at `frame`.
    pub fn body_position(&self, frame: usize, j: usize) -> Vector3<f64> {
        Self::vec3(&self.body_positions, frame, self.bodies.len(), j)
    }
    /// Velocity of body column `j` at `frame`.
    pub fn body_velocity(&self, frame: usize, j: usize) -> Vector3<f64> {
        Self::vec3(&self.body_velocities, frame, self.bodies.len(), j)
    }
    /// Angular velocity of body column `j` at `frame`.
    pub fn body_angular_velocity(&self, frame: usize, j: usize) -> Vector3<f64> {
        Self::vec3(&self.body_angular_velocities, frame, self.bodies.len(), j)
    }
    /// Orientation of body column `j` at `frame`.
    pub fn body_orientation(&self, frame: usize, j: usize) -> UnitQuaternion<f64> {
        let k = 4 * (frame * self.bodies.len() + j);
        let o = &self.body_orientations[k..k + 4];
        UnitQuaternion::new_normalize(nalgebra::Quaternion::new(o[0], o[1], o[2], o[3]))
    }
    /// Total mechanical energy at `frame` (kinetic plus potential).
    pub fn energy(&self, frame: usize) -> f64 {
        self.kinetic_energy[frame] + self.potential_energy[frame]
    }
    /// Linear momentum at `frame`.
    pub fn momentum(&self, frame: usize) -> Vector3<f64> {
        Self::vec3(&self.momentum, frame, 1, 0)
    }
    /// Angular momentum about the origin at `frame`.
    pub fn angular_momentum(&self, frame: usize) -> Vector3<f64> {
        Self::vec3(&self.angular_momentum, frame, 1, 0)
    }

    /// The flat arrays, for bindings: (particle positions, particle velocities, body positions, body orientations
    /// (w, x, y, z), body velocities, body angular velocities, momentum, angular momentum).
    #[allow(clippy::type_complexity)]
    pub fn into_arrays(self) -> (RunArrays, WorldReport) {
        let energy = self.kinetic_energy.iter().zip(&self.potential_energy).map(|(k, u)| k + u).collect();
        (
            RunArrays {
                times: self.times,
                particle_positions: self.particle_positions,
                particle_velocities: self.particle_velocities,
                body_positions: self.body_positions,
                body_orientations: self.body_orientations,
                body_velocities: self.body_velocities,
                body_angular_velocities: self.body_angular_velocities,
                kinetic_energy: self.kinetic_energy,
                potential_energy: self.potential_energy,
                energy,
                momentum: self.momentum,
                angular_momentum: self.angular_momentum,
                step_times: self.step_times,
                step_sizes: self.step_sizes,
                penetration: self.penetration,
                contact_events: self.contact_events,
                joint_break_times: self.joint_breaks.iter().map(|(t, _)| *t).collect(),
                contact_counts: self.contact_counts,
                contact_points: self.contact_points,
                particle_count: self.particles.len(),
                body_count: self.bodies.len(),
            },
            self.report,
        )
    }
}

/// A run's data as flat vectors (frame-major), handed to bindings without copying.
#[derive(Clone, Debug)]
pub struct RunArrays {
    pub times: Vec<f64>,
    pub particle_positions: Vec<f64>,
    pub particle_velocities: Vec<f64>,
    pub body_positions: Vec<f64>,
    pub body_orientations: Vec<f64>,
    pub body_velocities: Vec<f64>,
    pub body_angular_velocities: Vec<f64>,
    pub kinetic_energy: Vec<f64>,
    pub potential_energy: Vec<f64>,
    /// Kinetic plus potential energy per frame.
    pub energy: Vec<f64>,
    pub momentum: Vec<f64>,
    pub angular_momentum: Vec<f64>,
    pub step_times: Vec<f64>,
    pub step_sizes: Vec<f64>,
    pub penetration: Vec<f64>,
    pub contact_events: Vec<f64>,
    /// The times of `Run::joint_breaks`.
    pub joint_break_times: Vec<f64>,
    /// Contact points per frame, and each point with its normal (6 numbers) for all frames in order.
    pub contact_counts: Vec<usize>,
    pub contact_points: Vec<f64>,
    pub particle_count: usize,
    pub body_count: usize,
}

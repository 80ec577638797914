//! A world's whole state at once: `state()` reads every particle's and body's state in row order with the time
//! and the engine's memory (warm starts, sleep, kept manifolds, the integrator's next step and histories);
//! `set_state` puts one back, so that a world continues bit for bit as it did from there; `reset` returns to the
//! state each object was added with, at time zero. Rows are the order of `particles()` and `bodies()`;
//! `particle_row` and `body_row` find a handle's row after removals.

use super::{unknown, World};
use crate::engine::EngineMemory;
use crate::error::{check_finite, WorldError};
use crate::limits;
use crate::report::WorldReport;
use crate::spring::{BodyHandle, ParticleHandle};
use nalgebra::{UnitQuaternion, Vector3};
use std::sync::{Arc, Mutex};
use tumble_collide::rotated_tensor;

/// Every particle's and body's state (static bodies included, at their rows) and the time. Bodies carry momenta,
/// the state the equations of motion integrate (linear momentum M v, angular momentum I(t) w in world axes), so
/// that a state read and put back is exact to the bit. Edit the arrays and `set_state` starts the world from them
/// afresh; leave them and it continues with the engine's memory too.
#[derive(Clone, Debug)]
pub struct WorldState {
    pub time: f64,
    pub particle_positions: Vec<Vector3<f64>>,
    pub particle_velocities: Vec<Vector3<f64>>,
    pub body_positions: Vec<Vector3<f64>>,
    pub body_orientations: Vec<UnitQuaternion<f64>>,
    pub body_momenta: Vec<Vector3<f64>>,
    pub body_angular_momenta: Vec<Vector3<f64>>,
    memory: Option<Memory>,
}

/// The engine's memory when the state was read: the world's structure then (the memory fits only an engine of the
/// same structure and settings), a copy of it, and the arrays as read (it applies only if they come back unedited).
#[derive(Clone)]
struct Memory {
    structure: u64,
    /// The engine's divergence limit (set from the state's scale where it was built).
    divergence_limit: f64,
    /// Behind a mutex so that a state can cross threads (the memory holds `Send` integrator parts).
    snapshot: Arc<Mutex<EngineMemory>>,
    read: Box<WorldState>,
}

impl std::fmt::Debug for Memory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Memory(structure {})", self.structure)
    }
}

impl WorldState {
    /// Whether it carries the memory of the engine it was read from (`set_state` then continues bit for bit).
    pub fn has_memory(&self) -> bool {
        self.memory.is_some()
    }

    /// Forgets the engine's memory: `set_state` then starts the world from the arrays afresh.
    pub fn forget_memory(&mut self) {
        self.memory = None;
    }

    /// The same arrays, bit for bit.
    pub(crate) fn same_arrays(&self, o: &WorldState) -> bool {
        fn bits<'a>(v: impl Iterator<Item = &'a f64>) -> Vec<u64> {
            v.map(|x| x.to_bits()).collect()
        }
        let all = |s: &WorldState| {
            let mut out = vec![s.time.to_bits()];
            for list in [&s.particle_positions, &s.particle_velocities, &s.body_positions] {
                out.extend(bits(list.iter().flat_map(|v| v.iter())));
            }
            out.extend(bits(s.body_orientations.iter().flat_map(|q| q.coords.iter())));
            for list in [&s.body_momenta, &s.body_angular_momenta] {
                out.extend(bits(list.iter().flat_map(|v| v.iter())));
            }
            out
        };
        all(self) == all(o)
    }
}

/// A body's start: position, orientation, momentum, angular momentum.
pub(crate) type BodyStart = (Vector3<f64>, UnitQuaternion<f64>, Vector3<f64>, Vector3<f64>);

/// The state each object was added with (or set to before the world first stepped), by arena slot: what `reset`
/// returns to.
#[derive(Clone, Default)]
pub(crate) struct Starts {
    particles: Vec<(Vector3<f64>, Vector3<f64>)>,
    bodies: Vec<BodyStart>,
}

impl Starts {
    /// The start of the particle in slot `index`.
    pub(crate) fn particle(&self, index: u32) -> Option<(Vector3<f64>, Vector3<f64>)> {
        self.particles.get(index as usize).copied()
    }

    /// The start of the body in slot `index`.
    pub(crate) fn body(&self, index: u32) -> Option<BodyStart> {
        self.bodies.get(index as usize).copied()
    }

    /// Sets the start of the particle in slot `index`.
    pub(crate) fn set_particle(&mut self, index: u32, start: (Vector3<f64>, Vector3<f64>)) {
        put(&mut self.particles, index, start);
    }

    /// Sets the start of the body in slot `index`.
    pub(crate) fn set_body(&mut self, index: u32, start: BodyStart) {
        put(&mut self.bodies, index, start);
    }
}

fn put<T: Copy>(list: &mut Vec<T>, index: u32, value: T) {
    let i = index as usize;
    if list.len() <= i {
        list.resize(i + 1, value);
    }
    list[i] = value;
}

impl World {
    /// Records a particle's state as the one `reset` returns it to.
    pub(crate) fn record_particle_start(&mut self, h: ParticleHandle) {
        if let Some(p) = self.particles.get(h) {
            put(&mut self.starts.particles, h.index(), (p.position, p.velocity));
        }
    }

    /// Records a body's state as the one `reset` returns it to.
    pub(crate) fn record_body_start(&mut self, h: BodyHandle) {
        if let Some(b) = self.bodies.get(h) {
            put(&mut self.starts.bodies, h.index(), (b.position, b.orientation, b.momentum, b.angular_momentum));
        }
    }

    /// A particle's row in the state arrays (`particles()` order), valid until the next removal.
    pub fn particle_row(&self, h: ParticleHandle) -> Result<usize, WorldError> {
        self.particles.row(h).ok_or_else(|| unknown("handle", h))
    }

    /// A body's row in the state arrays (`bodies()` order, static bodies included), valid until the next removal.
    pub fn body_row(&self, h: BodyHandle) -> Result<usize, WorldError> {
        self.bodies.row(h).ok_or_else(|| unknown("handle", h))
    }

    /// The whole state now, with the engine's memory.
    pub fn state(&self) -> WorldState {
        let mut s = WorldState {
            time: self.time,
            particle_positions: self.particles.iter().map(|(_, p)| p.position).collect(),
            particle_velocities: self.particles.iter().map(|(_, p)| p.velocity).collect(),
            body_positions: self.bodies.iter().map(|(_, b)| b.position).collect(),
            body_orientations: self.bodies.iter().map(|(_, b)| b.orientation).collect(),
            body_momenta: self.bodies.iter().map(|(_, b)| b.momentum).collect(),
            body_angular_momenta: self.bodies.iter().map(|(_, b)| b.angular_momentum).collect(),
            memory: None,
        };
        if let (Some(e), false) = (&self.engine, self.state_changed) {
            s.memory = Some(Memory {
                structure: self.structure,
                divergence_limit: e.divergence_limit(),
                snapshot: Arc::new(Mutex::new(e.memory())),
                read: Box::new(s.clone()),
            });
        }
        s
    }

    /// Puts a whole state back. Read from this world (or a copy) and unedited, with its structure and settings
    /// unchanged since, the engine's memory comes back too and the world continues bit for bit as it did from there;
    /// otherwise the world starts from the state afresh, as a new world built with it would. Static bodies keep their poses
    /// (move them with `set_body_state`). Checked whole before anything changes: an error names the array.
    pub fn set_state(&mut self, state: &WorldState) -> Result<(), WorldError> {
        self.check_state(state)?;
        if let Some(m) = &state.memory {
            if m.structure == self.structure && state.same_arrays(&m.read) {
                // an engine of this structure (built anew if the world dropped its own) given the memory back
                let snapshot = m.snapshot.lock().unwrap_or_else(|e| e.into_inner()).clone();
                let engine = self.engine()?;
                engine.set_divergence_limit(m.divergence_limit);
                let t = engine.time();
                engine.set_memory(snapshot).map_err(|why| super::stepping::engine_fault(t, why))?;
                self.state_changed = false;
                self.store_state();
                return Ok(());
            }
        }
        self.time = state.time;
        for ((_, p), k) in self.particles.iter_mut().zip(0..) {
            p.position = state.particle_positions[k];
            p.velocity = state.particle_velocities[k];
        }
        for ((_, b), k) in self.bodies.iter_mut().zip(0..) {
            if !b.is_static {
                b.position = state.body_positions[k];
                b.orientation = state.body_orientations[k];
                b.momentum = state.body_momenta[k];
                b.angular_momentum = state.body_angular_momenta[k];
            }
            b.follow(self.time);
        }
        self.drop_engine();
        Ok(())
    }

    fn check_state(&self, s: &WorldState) -> Result<(), WorldError> {
        limits::in_range("time", s.time, -limits::TIME, limits::TIME, "s")?;
        let count = |name: &'static str, got: usize, want: usize, what: &str| {
            if got == want {
                Ok(())
            } else {
                Err(WorldError::invalid(name, format!("has {got} rows for the world's {want} {what}")))
            }
        };
        count("particle_positions", s.particle_positions.len(), self.particles.len(), "particles")?;
        count("particle_velocities", s.particle_velocities.len(), self.particles.len(), "particles")?;
        count("body_positions", s.body_positions.len(), self.bodies.len(), "bodies")?;
        count("body_orientations", s.body_orientations.len(), self.bodies.len(), "bodies")?;
        count("body_momenta", s.body_momenta.len(), self.bodies.len(), "bodies")?;
        count("body_angular_momenta", s.body_angular_momenta.len(), self.bodies.len(), "bodies")?;
        for (k, (p, v)) in s.particle_positions.iter().zip(&s.particle_velocities).enumerate() {
            row("particle_positions", k, limits::vector("particle_positions", p, limits::COORDINATE, "m"))?;
            row("particle_velocities", k, limits::vector("particle_velocities", v, limits::SPEED, "m/s"))?;
        }
        for (k, (_, b)) in self.bodies.iter().enumerate() {
            let (x, q) = (&s.body_positions[k], &s.body_orientations[k]);
            let (p, l) = (&s.body_momenta[k], &s.body_angular_momenta[k]);
            if b.is_static {
                let moved = [
                    ("body_positions", *x != b.position),
                    ("body_orientations", q.coords != b.orientation.coords),
                    ("body_momenta", *p != Vector3::zeros()),
                    ("body_angular_momenta", *l != Vector3::zeros()),
                ];
                if let Some((name, _)) = moved.into_iter().find(|m| m.1) {
                    let reason =
                        format!("row {k} is a static body, which set_state does not move (set_body_state does)");
                    return Err(WorldError::invalid(name, reason));
                }
                continue;
            }
            row("body_positions", k, limits::vector("body_positions", x, limits::COORDINATE, "m"))?;
            row("body_orientations", k, check_finite("body_orientations", q.coords.iter()))?;
            if (q.coords.norm() - 1.0).abs() > 1e-9 {
                let reason = format!("row {k} is not a unit quaternion (norm {})", q.coords.norm());
                return Err(WorldError::invalid("body_orientations", reason));
            }
            row("body_momenta", k, limits::vector("body_momenta", &(p / b.mass), limits::SPEED, "m/s (p / m)"))?;
            let r = q.to_rotation_matrix();
            let w = rotated_tensor(r.matrix(), &b.inv_inertia) * l;
            let reason = "rad/s (I^-1 L)";
            row("body_angular_momenta", k, limits::vector("body_angular_momenta", &w, limits::SPEED, reason))?;
        }
        Ok(())
    }

    /// Returns to time zero with every particle and body in the state it was added with (or set to before the
    /// world first stepped), the engine's memory and the report cleared: the world then runs bit for bit as a new
    /// world built the same way.
    pub fn reset(&mut self) {
        for (h, p) in self.particles.iter_mut() {
            if let Some(&(x, v)) = self.starts.particles.get(h.index() as usize) {
                (p.position, p.velocity) = (x, v);
            }
        }
        for (h, b) in self.bodies.iter_mut() {
            if let Some(&(x, q, p, l)) = self.starts.bodies.get(h.index() as usize) {
                (b.position, b.orientation, b.momentum, b.angular_momentum) = (x, q, p, l);
            }
        }
        self.time = 0.0;
        for (_, b) in self.bodies.iter_mut() {
            b.follow(0.0);
        }
        self.stepped = false;
        self.failed_run = None;
        self.totals = WorldReport::new(self.settings.method.name());
        self.drop_engine();
    }
}

/// An error of one row, said with the row.
fn row<T>(name: &'static str, k: usize, r: Result<T, WorldError>) -> Result<(), WorldError> {
    r.map(|_| ()).map_err(|e| match e {
        WorldError::InvalidArgument { reason, .. } => WorldError::invalid(name, format!("row {k}: {reason}")),
        other => other,
    })
}

/// A state can be sent to another thread (batches run copies of a world on a thread pool).
#[allow(dead_code)]
fn state_is_send() {
    fn is_send<T: Send + Sync>() {}
    is_send::<WorldState>();
}

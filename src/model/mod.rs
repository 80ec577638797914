//! The compiled model: the world's contents as flat arrays in state order, with handles resolved to indices.
//! It is rebuilt when the world's structure changes and is the `OdeSystem` the integrators step.

mod actors;
pub(crate) mod breaking;
mod dynamics;
mod energy;
mod jacobian;
pub(crate) mod joints;
mod kinematic;
pub(crate) mod kinematics;
pub(crate) mod layout;
mod velocities;

pub(crate) use kinematics::{BodyKin, Kinematics};

pub(crate) use actors::actor_poses;

use crate::body::RigidBody;
use crate::handle::Arena;
use crate::load::{ForceCallback, Load, Target};
use crate::model::layout::{get3, get_quat, set3, set_quat, Layout};
use crate::particle::Particle;
use crate::plan::{Stage, StageCounts};
use crate::spring::{Attachment, BodyHandle, ParticleHandle, Spring};
use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};
use std::collections::HashMap;
use tumble_contact::SpringLaw;

#[derive(Clone)]
pub(crate) struct ParticleProps {
    pub mass: f64,
    pub inv_mass: f64,
    pub damping: f64,
    pub stiffness: f64,
    pub anchor: Vector3<f64>,
}

#[derive(Clone)]
pub(crate) struct BodyProps {
    pub mass: f64,
    pub inv_mass: f64,
    pub inertia: Matrix3<f64>,
    pub inv_inertia: Matrix3<f64>,
    pub linear_damping: f64,
    pub angular_damping: f64,
    /// A kinematic body's path: its blocks of the state hold its velocities (mass and inertia 1 in the model's
    /// kinematics, so P = v and L = w) and its rates of momentum are zero; the contact and joint solves see it as
    /// immovable and moving.
    pub kinematic: Option<std::sync::Arc<crate::keyframes::Keyframes>>,
}

/// A spring end (`Attachment`) resolved against the model: a particle or a dynamic body (a point of it, in its frame
/// about the centre of mass) by its index, or a fixed world point (a static body's points included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ResolvedAttachment {
    Particle(usize),
    Body(usize, Vector3<f64>),
    Point(Vector3<f64>),
}

impl ResolvedAttachment {
    /// The actor it is on (a particle or a dynamic body), if any.
    pub fn actor(&self, l: Layout) -> Option<usize> {
        match *self {
            ResolvedAttachment::Particle(i) => Some(i),
            ResolvedAttachment::Body(j, _) => Some(l.body_actor(j)),
            ResolvedAttachment::Point(_) => None,
        }
    }
}

/// A body resolved against the model: a dynamic body by its index (its pose is in the state), or a fixed pose (a
/// static body's, or the world's: the identity). A joint's ends and a run's bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ResolvedBody {
    Dynamic(usize),
    Fixed(Isometry3<f64>),
}

impl ResolvedBody {
    /// `body`, dynamic at `index` if it has one, else fixed where it is (a static body).
    pub fn of(body: &RigidBody, index: Option<usize>) -> ResolvedBody {
        match index {
            Some(j) => ResolvedBody::Dynamic(j),
            None => ResolvedBody::Fixed(body.pose()),
        }
    }

    /// The dynamic body's index, if it is one.
    pub fn dynamic(&self) -> Option<usize> {
        match *self {
            ResolvedBody::Dynamic(j) => Some(j),
            ResolvedBody::Fixed(_) => None,
        }
    }

    /// The dynamic body's actor index, if it is one.
    pub fn actor(&self, l: Layout) -> Option<usize> {
        self.dynamic().map(|j| l.body_actor(j))
    }
}

/// A spring between two resolved ends.
#[derive(Clone)]
pub(crate) struct CompiledSpring {
    pub a: ResolvedAttachment,
    pub b: ResolvedAttachment,
    pub law: SpringLaw,
}

/// What a load acts on (`Target`) resolved against the model: a particle or a dynamic body by its index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ResolvedTarget {
    Particle(usize),
    Body(usize),
}

#[derive(Clone)]
pub(crate) enum CompiledLoad {
    Force { on: ResolvedTarget, force: Vector3<f64>, at: Option<Vector3<f64>> },
    Torque { body: usize, torque: Vector3<f64> },
    Callback { on: ResolvedTarget, callback: ForceCallback },
}

/// How many times each force loop ran (a loop over nothing is never entered).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ForceCounters {
    /// Right-hand-side evaluations of the world.
    pub evaluations: usize,
    /// Spring force evaluations (one per spring per evaluation).
    pub spring_evaluations: usize,
    /// Constant force and torque evaluations.
    pub load_evaluations: usize,
    /// User callback calls.
    pub callback_calls: usize,
    /// Quaternion renormalisations after accepted steps.
    pub projections: usize,
}

/// What the equations of motion did since an engine last took it: the force loops' counts and the terms that ran.
/// The engine that evaluates them owns it (accurate mode's system, fast mode's engine) and hands it to each
/// evaluation; the model keeps no count.
#[derive(Clone, Debug, Default)]
pub(crate) struct Tally {
    pub forces: ForceCounters,
    pub stages: StageCounts,
}

impl std::ops::AddAssign for ForceCounters {
    fn add_assign(&mut self, o: Self) {
        self.evaluations += o.evaluations;
        self.spring_evaluations += o.spring_evaluations;
        self.load_evaluations += o.load_evaluations;
        self.callback_calls += o.callback_calls;
        self.projections += o.projections;
    }
}

/// How the Jacobian is formed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum JacobianKind {
    /// Particles, springs and constant loads only: analytic sparse blocks.
    Analytic,
    /// Bodies or callbacks: coloured finite differences over the coupling pattern.
    Colored,
}

#[derive(Clone)]
pub(crate) struct Model {
    pub layout: Layout,
    pub gravity: Vector3<f64>,
    pub particles: Vec<ParticleProps>,
    pub bodies: Vec<BodyProps>,
    pub springs: Vec<CompiledSpring>,
    pub loads: Vec<CompiledLoad>,
    /// The terms present (`stages()`, computed once).
    pub terms: Vec<Stage>,
    pub jacobian: JacobianKind,
    /// Use the semidefinite spring blocks (see `jacobian.rs`).
    pub definite_springs: bool,
    pub velocity_dependent: bool,
    /// Joints, with their ends resolved (each engine solves them its own way).
    pub joints: Vec<joints::CompiledJoint>,
}

/// The state's handles: which particle and dynamic body each index of the state is, in state order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct StateHandles {
    pub particles: Vec<ParticleHandle>,
    pub bodies: Vec<BodyHandle>,
}

/// A compiled model with its state's handles.
#[derive(Clone)]
pub(crate) struct Compiled {
    pub model: Model,
    pub handles: StateHandles,
}

pub(crate) fn compile(
    gravity: Vector3<f64>,
    particles: &Arena<Particle>,
    bodies: &Arena<RigidBody>,
    springs: &Arena<Spring>,
    loads: &Arena<Load>,
    joints: &Arena<crate::joint::Joint>,
) -> Compiled {
    let particle_handles: Vec<ParticleHandle> = particles.iter().map(|(h, _)| h).collect();
    let body_handles: Vec<BodyHandle> = bodies.iter().filter(|(_, b)| !b.is_static).map(|(h, _)| h).collect();
    let p_index: HashMap<ParticleHandle, usize> = particle_handles.iter().enumerate().map(|(i, &h)| (h, i)).collect();
    let b_index: HashMap<BodyHandle, usize> = body_handles.iter().enumerate().map(|(i, &h)| (h, i)).collect();
    let layout = Layout { particles: particle_handles.len(), bodies: body_handles.len() };
    let end = |a: &Attachment| match *a {
        Attachment::Particle(h) => ResolvedAttachment::Particle(p_index[&h]),
        Attachment::Body(h, local) => match b_index.get(&h) {
            Some(&j) => ResolvedAttachment::Body(j, local),
            None => ResolvedAttachment::Point(bodies.get(h).expect("validated on insertion").world_point(local)),
        },
        Attachment::Point(p) => ResolvedAttachment::Point(p),
    };
    let on = |t: Target| match t {
        Target::Particle(h) => ResolvedTarget::Particle(p_index[&h]),
        Target::Body(h) => ResolvedTarget::Body(b_index[&h]),
    };
    let particle_props: Vec<ParticleProps> = particles
        .iter()
        .map(|(_, p)| ParticleProps {
            mass: p.mass,
            inv_mass: 1.0 / p.mass,
            damping: p.damping,
            stiffness: p.stiffness,
            anchor: p.anchor,
        })
        .collect();
    let body_props: Vec<BodyProps> = body_handles
        .iter()
        .map(|&h| {
            let b = bodies.get(h).expect("live");
            match &b.kinematic {
                Some(k) => BodyProps {
                    mass: 1.0,
                    inv_mass: 1.0,
                    inertia: Matrix3::identity(),
                    inv_inertia: Matrix3::identity(),
                    linear_damping: 0.0,
                    angular_damping: 0.0,
                    kinematic: Some(k.path.clone()),
                },
                None => BodyProps {
                    mass: b.mass,
                    inv_mass: 1.0 / b.mass,
                    inertia: b.inertia,
                    inv_inertia: b.inv_inertia,
                    linear_damping: b.linear_damping,
                    angular_damping: b.angular_damping,
                    kinematic: None,
                },
            }
        })
        .collect();
    let compiled_springs: Vec<CompiledSpring> = springs
        .iter()
        .map(|(_, s)| CompiledSpring {
            a: end(&s.a),
            b: end(&s.b),
            law: SpringLaw { stiffness: s.stiffness, damping: s.damping, rest_length: s.rest_length },
        })
        .collect();
    let compiled_loads: Vec<CompiledLoad> = loads
        .iter()
        .map(|(_, l)| match l {
            Load::Force { target, force, at } => CompiledLoad::Force { on: on(*target), force: *force, at: *at },
            Load::Torque { body, torque } => CompiledLoad::Torque { body: b_index[body], torque: *torque },
            Load::Callback { target, callback } => {
                CompiledLoad::Callback { on: on(*target), callback: callback.clone() }
            }
        })
        .collect();
    let has_callbacks = compiled_loads.iter().any(|l| matches!(l, CompiledLoad::Callback { .. }));
    let velocity_dependent = has_callbacks
        || particle_props.iter().any(|p| p.damping > 0.0)
        || body_props.iter().any(|b| b.linear_damping > 0.0 || b.angular_damping > 0.0)
        || compiled_springs.iter().any(|s| s.law.damping > 0.0);
    let mut model = Model {
        layout,
        gravity,
        particles: particle_props,
        bodies: body_props,
        springs: compiled_springs,
        loads: compiled_loads,
        terms: Vec::new(),
        jacobian: if layout.bodies > 0 || has_callbacks { JacobianKind::Colored } else { JacobianKind::Analytic },
        definite_springs: false,
        velocity_dependent,
        joints: joints::compile_joints(joints, bodies, &b_index),
    };
    model.terms = model.stages();
    Compiled { model, handles: StateHandles { particles: particle_handles, bodies: body_handles } }
}

impl Model {
    /// The terms of the equations of motion this model evaluates, in pipeline order.
    pub(crate) fn stages(&self) -> Vec<Stage> {
        let l = self.layout;
        let mut out = Vec::new();
        let mut add = |on: bool, s: Stage| {
            if on {
                out.push(s)
            }
        };
        add(l.particles > 0, Stage::Particles);
        add(l.bodies > 0, Stage::RigidBodies);
        add(l.bodies > 0, Stage::Rotation);
        add(l.dim() > 0 && self.gravity != Vector3::zeros(), Stage::Gravity);
        add(self.has_damping(), Stage::Damping);
        add(!self.springs.is_empty(), Stage::Springs);
        add(self.loads.iter().any(|l| !matches!(l, CompiledLoad::Callback { .. })), Stage::Loads);
        add(self.loads.iter().any(|l| matches!(l, CompiledLoad::Callback { .. })), Stage::Callbacks);
        add(self.has_joints(), Stage::Joints);
        out
    }

    /// Whether each dynamic body is an end of a joint (empty without joints).
    pub(crate) fn jointed_bodies(&self) -> Vec<bool> {
        if !self.joints.is_empty() {
            let mut out = vec![false; self.bodies.len()];
            for (_, j) in self.holding_joints() {
                for end in [j.a, j.b] {
                    if let ResolvedBody::Dynamic(i) = end {
                        out[i] = true;
                    }
                }
            }
            return out;
        }
        Vec::new()
    }

    /// Whether the model has joints that hold (broken ones hold nothing: a world whose joints all broke is
    /// planned, stepped and put to sleep as one without joints).
    pub(crate) fn has_joints(&self) -> bool {
        self.holding_joints().next().is_some()
    }

    /// Whether any particle has damping or a restoring term, or any body damping.
    pub(crate) fn has_damping(&self) -> bool {
        self.particles.iter().any(|p| p.damping > 0.0 || p.stiffness > 0.0)
            || self.bodies.iter().any(|b| b.linear_damping > 0.0 || b.angular_damping > 0.0)
    }

    /// How the Jacobian is formed, by name.
    pub(crate) fn jacobian_name(&self) -> &'static str {
        match (self.jacobian, self.definite_springs) {
            (JacobianKind::Analytic, false) => "analytic-sparse",
            (JacobianKind::Analytic, true) => "analytic-sparse-definite",
            (JacobianKind::Colored, _) => "colored-finite-differences",
        }
    }
}

impl StateHandles {
    /// The layout of a state of these particles and bodies.
    pub fn layout(&self) -> Layout {
        Layout { particles: self.particles.len(), bodies: self.bodies.len() }
    }

    /// The state vector of the arenas' current contents.
    pub fn pack(&self, particles: &Arena<Particle>, bodies: &Arena<RigidBody>) -> Vec<f64> {
        let l = self.layout();
        let mut y = vec![0.0; l.dim()];
        for (i, &h) in self.particles.iter().enumerate() {
            let p = particles.get(h).expect("live");
            set3(&mut y, l.px(i), &p.position);
            set3(&mut y, l.pv(i), &p.velocity);
        }
        for (j, &h) in self.bodies.iter().enumerate() {
            let b = bodies.get(h).expect("live");
            set3(&mut y, l.bx(j), &b.position);
            set_quat(&mut y, l.bq(j), &b.orientation);
            match &b.kinematic {
                Some(k) => {
                    set3(&mut y, l.bp(j), &k.velocity);
                    set3(&mut y, l.bl(j), &k.angular_velocity);
                }
                None => {
                    set3(&mut y, l.bp(j), &b.momentum);
                    set3(&mut y, l.bl(j), &b.angular_momentum);
                }
            }
        }
        y
    }

    /// Writes a state vector back into the arenas.
    pub fn unpack(&self, y: &[f64], particles: &mut Arena<Particle>, bodies: &mut Arena<RigidBody>) {
        let l = self.layout();
        for (i, &h) in self.particles.iter().enumerate() {
            let p = particles.get_mut(h).expect("live");
            p.position = get3(y, l.px(i));
            p.velocity = get3(y, l.pv(i));
        }
        for (j, &h) in self.bodies.iter().enumerate() {
            let b = bodies.get_mut(h).expect("live");
            b.position = get3(y, l.bx(j));
            b.orientation = UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
            match &mut b.kinematic {
                Some(k) => (k.velocity, k.angular_velocity) = (get3(y, l.bp(j)), get3(y, l.bl(j))),
                None => (b.momentum, b.angular_momentum) = (get3(y, l.bp(j)), get3(y, l.bl(j))),
            }
        }
    }
}

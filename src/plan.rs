//! The stages a world can run, and the plan: which of them a world runs, decided from its contents, so a scene
//! pays only for what it uses. Engines list the stages they will run (`Engine::stages`) and count the ones that
//! ran (`StageCounts`), so a report shows whether the plan was kept.

use std::fmt;

/// One stage of a world's step: a term of the equations of motion or a stage of an engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// Closed meshes of moving bodies decomposed into convex pieces (when the bodies were added).
    MeshDecomposition,
    /// The particles' equations of motion.
    Particles,
    /// The rigid bodies' equations of motion.
    RigidBodies,
    /// Quaternion rates of rigid bodies.
    Rotation,
    /// Gravity.
    Gravity,
    /// Damping and restoring terms.
    Damping,
    /// Spring forces.
    Springs,
    /// Constant forces and torques.
    Loads,
    /// User force callbacks.
    Callbacks,
    /// Joints: constraint forces in the equations of motion (accurate mode) or rows of the soft step (fast mode).
    Joints,
    /// Broad and narrow phase (both contact modes).
    CollisionDetection,
    /// Collision times located by bisection (accurate mode).
    Bisection,
    /// Collision impulses (accurate mode).
    Impulses,
    /// Resting-contact forces from the QP inside the equations of motion (accurate mode).
    RestingContact,
    /// One velocity-level conic program per island (fast mode's exact solver, accurate mode's contact steps).
    ContactConeProgram,
    /// The soft step: substeps of an iterative, warm-started solve of soft contacts (fast mode's default solver).
    ContactSoftStep,
    /// Resting islands put to sleep (fast mode).
    Sleeping,
    /// The integrator's steps (fast mode: positions from the new velocities).
    Integrate,
    /// Jacobians formed for an implicit method.
    Jacobian,
}

impl Stage {
    /// Every stage, in pipeline order.
    pub const ALL: [Stage; 19] = [
        Stage::MeshDecomposition,
        Stage::Particles,
        Stage::RigidBodies,
        Stage::Rotation,
        Stage::Gravity,
        Stage::Damping,
        Stage::Springs,
        Stage::Loads,
        Stage::Callbacks,
        Stage::Joints,
        Stage::CollisionDetection,
        Stage::Bisection,
        Stage::Impulses,
        Stage::RestingContact,
        Stage::ContactConeProgram,
        Stage::ContactSoftStep,
        Stage::Sleeping,
        Stage::Integrate,
        Stage::Jacobian,
    ];

    /// The stage's name, as plans and reports show it.
    pub fn name(self) -> &'static str {
        match self {
            Stage::MeshDecomposition => "mesh-decomposition",
            Stage::Particles => "particles",
            Stage::RigidBodies => "rigid-bodies",
            Stage::Rotation => "rotation",
            Stage::Gravity => "gravity",
            Stage::Damping => "damping",
            Stage::Springs => "springs",
            Stage::Loads => "loads",
            Stage::Callbacks => "callbacks",
            Stage::Joints => "joints",
            Stage::CollisionDetection => "collision-detection",
            Stage::Bisection => "bisection",
            Stage::Impulses => "impulses",
            Stage::RestingContact => "resting-contact",
            Stage::ContactConeProgram => "contact-cone-program",
            Stage::ContactSoftStep => "contact-soft-step",
            Stage::Sleeping => "sleeping",
            Stage::Integrate => "integrate",
            Stage::Jacobian => "jacobian",
        }
    }
}

/// How many times each stage ran (a fixed array in pipeline order: no hashing, cheap to count into).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StageCounts([usize; Stage::ALL.len()]);

impl StageCounts {
    /// Counts one run of `stage`.
    #[inline]
    pub(crate) fn mark(&mut self, stage: Stage) {
        self.0[stage as usize] += 1;
    }

    /// Counts `n` runs of `stage`.
    #[inline]
    pub(crate) fn add(&mut self, stage: Stage, n: usize) {
        self.0[stage as usize] += n;
    }

    /// How many times `stage` ran.
    pub fn get(&self, stage: Stage) -> usize {
        self.0[stage as usize]
    }

    /// The stages that ran at least once, in pipeline order.
    pub fn ran(&self) -> Vec<&'static str> {
        Stage::ALL.iter().filter(|&&s| self.get(s) > 0).map(|s| s.name()).collect()
    }
}

impl std::ops::AddAssign for StageCounts {
    fn add_assign(&mut self, o: Self) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }
}

/// The stages a world runs and the length of its state vector.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    /// Active stages in pipeline order: "mesh-decomposition" (done once, as bodies with meshes were added), "particles", "rigid-bodies", "rotation", "gravity", "damping",
    /// "springs", "loads", "callbacks", "joints", then with colliders that can touch "collision-detection" and either
    /// (accurate mode) "bisection", "impulses", "resting-contact" or (fast mode) "contact-soft-step" (or "contact-cone-program") and
    /// "sleeping"; then "integrate", "jacobian".
    pub stages: Vec<&'static str>,
    /// Length of the state vector (6 a particle, 13 a dynamic body).
    pub state_len: usize,
    /// "accurate" or "fast".
    pub mode: &'static str,
    /// The integration method.
    pub method: &'static str,
    /// How the Jacobian is formed, when the method needs one: "analytic-sparse", "analytic-sparse-definite" (the
    /// springs' semidefinite approximation) or "colored-finite-differences".
    pub jacobian: Option<&'static str>,
}

impl Plan {
    /// Whether a stage is active (its name with hyphens or spaces: "mesh-decomposition" or "mesh decomposition").
    pub fn has(&self, stage: &str) -> bool {
        let stage = stage.replace(' ', "-");
        self.stages.iter().any(|s| *s == stage)
    }
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ({} state variables, {} mode, method {}",
            self.stages.join(" -> "),
            self.state_len,
            self.mode,
            self.method
        )?;
        if let Some(j) = self.jacobian {
            write!(f, ", jacobian {j}")?;
        }
        write!(f, ")")
    }
}

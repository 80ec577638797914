//! How a world treats contact: accurate (event-driven, the chapter's scheme) or fast (time stepping), and the
//! settings of each.

use crate::error::WorldError;
use crate::limits;

/// How a world steps when bodies touch.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Mode {
    /// Event-driven with error-controlled contact steps (the default): the integrator and its error control carry
    /// free motion; collisions are located in time by bisection and resolved by impulses; while bodies touch,
    /// convex contact steps with Coulomb friction under step-doubling error control carry them.
    Accurate(AccurateSettings),
    /// Time stepping at a fixed step: contacts found at the start of each step with a margin, then the soft step's
    /// substeps (or, with `FastSolver::Exact`, one velocity-level conic program per island and positions from the
    /// new velocities); resting islands sleep.
    Fast(FastSettings),
}

impl Default for Mode {
    fn default() -> Self {
        Mode::Accurate(AccurateSettings::default())
    }
}

impl Mode {
    /// Fast mode at step `dt` with the other settings at their defaults.
    pub fn fast(dt: f64) -> Mode {
        Mode::Fast(FastSettings::new(dt))
    }

    /// The mode's name: "accurate" or "fast".
    pub fn name(&self) -> &'static str {
        match self {
            Mode::Accurate(_) => "accurate",
            Mode::Fast(_) => "fast",
        }
    }

    pub(crate) fn check(&self) -> Result<(), WorldError> {
        match self {
            Mode::Accurate(a) => a.check(),
            Mode::Fast(f) => f.check(),
        }
    }
}

/// How accurate mode carries contacts that persist.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Persistent {
    /// Convex contact steps with Coulomb friction, their size set by step doubling against `contact_tolerance`
    /// (the default).
    ContactSteps,
    /// The chapter's resting contact: frictionless forces from a QP inside the equations of motion, so the
    /// integrator's own order carries resting bodies; contacts with friction are refused, and scenes whose contacts
    /// keep re-colliding end in an error.
    RestingForces,
}

/// Settings of the accurate mode.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub struct AccurateSettings {
    /// Time tolerance of the collision-time bisection (s); 1e-10 by default.
    pub time_tolerance: f64,
    /// Distance within which two shapes count as touching (m); 1e-7 by default.
    pub contact_distance: f64,
    /// Relative normal speed below which a contact rests instead of bouncing (m/s); `None` picks
    /// 1e-3 sqrt(2 g L) for the scene's size L (a bounce slower than that would rise less than 1e-6 L).
    pub resting_speed: Option<f64>,
    /// Error allowed in one contact step (m): positions, turns at the radius of gyration, velocity differences
    /// times the step. `None` picks 1e-4 of the scene's size.
    pub contact_tolerance: Option<f64>,
    /// How contacts that persist are carried.
    pub persistent: Persistent,
    /// Whether resting islands sleep (`engine/accurate/sleep.rs`): an island whose actors have all moved slower
    /// than the resting speed for `sleep_time` is frozen until something awake reaches it or the state is set;
    /// true by default (worlds with joints do not sleep).
    #[serde(default = "yes")]
    pub sleep: bool,
    /// How long an island must stay slower than the resting speed before it sleeps (s); 0.5 by default.
    #[serde(default = "half_a_second")]
    pub sleep_time: f64,
    /// The contact steps' solver; the Newton method by default.
    #[serde(default)]
    pub solver: AccurateSolver,
    /// Whether groups of actors that cannot meet before the next frame go on their own clocks
    /// (`engine/accurate/clocks.rs`; worlds of up to 64 actors without joints); true by default. False keeps one
    /// clock for every actor (the reference the own clocks are tested against).
    #[serde(default = "yes")]
    pub island_clocks: bool,
}

fn yes() -> bool {
    true
}

fn half_a_second() -> f64 {
    0.5
}

/// How accurate mode's contact steps solve their programs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AccurateSolver {
    /// tumble's own: the multiplier method with Newton's method on the velocities, warm started from the last
    /// step; islands it cannot answer go to clarabel (the default).
    #[default]
    Newton,
    /// clarabel's interior point for every island (the reference the Newton method is tested against).
    Clarabel,
}

impl AccurateSolver {
    /// The solver by name: "newton" or "clarabel".
    pub fn from_name(name: &str) -> Result<AccurateSolver, WorldError> {
        match name {
            "newton" => Ok(AccurateSolver::Newton),
            "clarabel" => Ok(AccurateSolver::Clarabel),
            other => Err(WorldError::invalid(
                "solver",
                format!("accurate mode's solver is \"newton\" or \"clarabel\", got {other:?}"),
            )),
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            AccurateSolver::Newton => "newton",
            AccurateSolver::Clarabel => "clarabel",
        }
    }
}

impl Default for AccurateSettings {
    fn default() -> Self {
        AccurateSettings {
            time_tolerance: 1e-10,
            contact_distance: 1e-7,
            resting_speed: None,
            contact_tolerance: None,
            persistent: Persistent::ContactSteps,
            sleep: true,
            sleep_time: 0.5,
            solver: AccurateSolver::Newton,
            island_clocks: true,
        }
    }
}

impl AccurateSettings {
    fn check(&self) -> Result<(), WorldError> {
        limits::positive("time_tolerance", self.time_tolerance, 1.0, "s")?;
        limits::positive("contact_distance", self.contact_distance, 1.0, "m")?;
        if let Some(v) = self.resting_speed {
            limits::positive("resting_speed", v, limits::SPEED, "m/s")?;
        }
        if let Some(v) = self.contact_tolerance {
            limits::positive("contact_tolerance", v, limits::COORDINATE, "m")?;
        }
        limits::non_negative("sleep_time", self.sleep_time, limits::TIME, "s")?;
        // clarabel's programs, in a build without it (the Newton method and the convex steps are always there)
        let without = |what: &str| format!("{what} needs tumble built with the `clarabel` feature");
        if !cfg!(feature = "clarabel") && self.persistent == Persistent::RestingForces {
            return Err(WorldError::invalid("persistent", without("resting_forces (the chapter's QP)")));
        }
        if !cfg!(feature = "clarabel") && self.solver == AccurateSolver::Clarabel {
            return Err(WorldError::invalid("solver", without("the clarabel solver")));
        }
        Ok(())
    }
}

/// Friction in fast mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum FastFriction {
    /// Each contact's friction bounded by mu times its previous step's normal impulse: Coulomb's deceleration and
    /// no hop while sliding (the default).
    Lagged,
    /// Anitescu's cone: one convex program, but a sliding contact separates at mu |v_t| and slides 1/(1 + mu^2) too
    /// slowly.
    Cone,
}

/// Fast mode's contact solver.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum FastSolver {
    /// Catto's soft step (the default): substeps, warm-started impulses, soft contacts in hertz, iterative; as fast
    /// as the game engines, with a small penetration under load (about g / (2 pi hertz)^2 per body weight carried).
    Soft(SoftSolver),
    /// clarabel's exact velocity-level cone program per island: no penetration and exact contact conditions each
    /// step, many times slower (docs/benchmarks.md measures it); for verification and small scenes.
    Exact {
        /// Fraction of an interpenetration removed per step, in [0, 1]; 0.2 by default.
        erp: f64,
        /// The friction model.
        friction: FastFriction,
    },
}

impl FastSolver {
    /// The exact solver with its defaults (erp 0.2, lagged friction).
    pub fn exact() -> FastSolver {
        FastSolver::Exact { erp: 0.2, friction: FastFriction::Lagged }
    }

    /// The solver's name: "soft" or "exact".
    pub fn name(&self) -> &'static str {
        match self {
            FastSolver::Soft(_) => "soft",
            FastSolver::Exact { .. } => "exact",
        }
    }
}

impl Default for FastSolver {
    fn default() -> Self {
        FastSolver::Soft(SoftSolver::default())
    }
}

/// Settings of the soft step.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub struct SoftSolver {
    /// Substeps per step; 8 by default. More substeps make contacts stiffer (the stiffness is capped at a quarter of
    /// the substep rate) and stacks sink less.
    pub substeps: usize,
    /// Sweeps over the contacts in each pass of a substep; 2 by default.
    pub iterations: usize,
    /// Contact stiffness (Hz) between moving bodies, twice it against static ones; infinity (the default) is the
    /// cap, a quarter of the substep rate.
    #[serde(with = "tumble_integrate::float_serde")]
    pub contact_hertz: f64,
    /// Damping ratio of the contacts; 10 by default.
    pub damping_ratio: f64,
    /// Largest speed at which overlaps are pushed out (m/s); 3 by default.
    pub max_push_out: f64,
}

impl Default for SoftSolver {
    fn default() -> Self {
        SoftSolver { substeps: 8, iterations: 2, contact_hertz: f64::INFINITY, damping_ratio: 10.0, max_push_out: 3.0 }
    }
}

/// Settings of the fast mode.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub struct FastSettings {
    /// The step (s).
    pub dt: f64,
    /// Extra distance within which separated pairs become contacts (m), on top of how far they can move in a step;
    /// 1e-3 by default.
    pub margin: f64,
    /// Contacts closing slower than this do not bounce (m/s); 0.1 by default.
    pub bounce_threshold: f64,
    /// Whether resting islands sleep; true by default.
    pub sleep: bool,
    /// An island sleeps after all its points have moved slower than this (m/s) ...
    pub sleep_speed: f64,
    /// ... for this long (s); 0.05 m/s and 0.5 s by default.
    pub sleep_time: f64,
    /// The contact solver; the soft step by default.
    pub solver: FastSolver,
    /// Estimate each step's error by step doubling: the step is also taken as two halves from the same start and
    /// the difference (m: positions, turns at the radius of gyration, velocity differences times the step) is
    /// reported as `step_error`; the run follows the whole steps, unchanged. Triples the cost; false by default.
    pub step_doubling: bool,
}

impl FastSettings {
    /// Defaults for step `dt`.
    pub fn new(dt: f64) -> FastSettings {
        FastSettings {
            dt,
            margin: 1e-3,
            bounce_threshold: 0.1,
            sleep: true,
            sleep_speed: 0.05,
            sleep_time: 0.5,
            solver: FastSolver::default(),
            step_doubling: false,
        }
    }

    fn check(&self) -> Result<(), WorldError> {
        limits::positive("dt", self.dt, 1.0, "s")?;
        limits::non_negative("margin", self.margin, limits::COORDINATE, "m")?;
        match self.solver {
            FastSolver::Exact { erp, .. } => {
                if !(0.0..=1.0).contains(&erp) {
                    return Err(WorldError::invalid("erp", format!("must be in [0, 1], got {erp}")));
                }
            }
            FastSolver::Soft(soft) => {
                for (name, n) in [("substeps", soft.substeps), ("iterations", soft.iterations)] {
                    if !(1..=1000).contains(&n) {
                        return Err(WorldError::invalid(name, format!("must be 1..=1000, got {n}")));
                    }
                }
                if !(soft.contact_hertz > 0.0) {
                    return Err(WorldError::invalid(
                        "contact_hertz",
                        format!("must be > 0 (infinity: the stiffest), got {}", soft.contact_hertz),
                    ));
                }
                limits::non_negative("damping_ratio", soft.damping_ratio, 1e6, "")?;
                limits::positive("max_push_out", soft.max_push_out, limits::SPEED, "m/s")?;
            }
        }
        limits::non_negative("bounce_threshold", self.bounce_threshold, limits::SPEED, "m/s")?;
        limits::non_negative("sleep_speed", self.sleep_speed, limits::SPEED, "m/s")?;
        limits::non_negative("sleep_time", self.sleep_time, limits::TIME, "s")?;
        Ok(())
    }
}

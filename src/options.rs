//! Options as users name them (the Python module's keywords), with their defaults and decision rules in one
//! place: the integrator from a method name and tolerances, a body's mass from a shape and a density or a mass,
//! and a world from its mode. An option that does not apply to the chosen mode is an error naming it.

use crate::body::RigidBodyBuilder;
use crate::error::WorldError;
use crate::mode::{AccurateSettings, AccurateSolver, FastSettings, FastSolver, Mode, SoftSolver};
use crate::world::World;
use nalgebra::{Matrix3, Vector3};
use tumble_collide::Shape;
use tumble_integrate::{LinearSolver, Method, NewtonMode, Settings};

/// Density of a body given by its shape alone (kg/m^3, about water's).
pub const DEFAULT_DENSITY: f64 = 1000.0;
/// Step of fixed-step methods and of fast mode when none is given (s).
pub const DEFAULT_DT: f64 = 1.0 / 240.0;
/// Tolerances of adaptive methods when none are given.
pub const DEFAULT_RTOL: f64 = 1e-6;
/// Absolute tolerance of adaptive methods when none is given.
pub const DEFAULT_ATOL: f64 = 1e-9;
/// Per-step error of step doubling and the variable-step Euler when none is given.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;
/// Method when none is given.
pub const DEFAULT_METHOD: Method = Method::Dopri5;

/// The integrator as named by keywords. `None` and `false` mean "not given".
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IntegratorOptions {
    /// A method name ("dopri5", "rk4", ...); dopri5 by default.
    pub integrator: Option<String>,
    /// Relative tolerance of an adaptive method.
    pub rtol: Option<f64>,
    /// Absolute tolerance of an adaptive method.
    pub atol: Option<f64>,
    /// A fixed method's step, or an adaptive method's first step.
    pub dt: Option<f64>,
    /// Wrap a one-step method in the chapter's step doubling; in fast mode, estimate each step's error by step doubling
    /// (`FastSettings::step_doubling`).
    pub step_doubling: bool,
    /// Per-step error of step doubling and the variable-step Euler.
    pub tolerance: Option<f64>,
    /// "direct" (sparse LU, the default) or "iterative" (BiCGSTAB) for implicit Euler's systems.
    pub linear_solver: Option<String>,
    /// Iterate implicit Euler's Newton steps to convergence.
    pub newton: bool,
    /// A budget of steps per call.
    pub max_steps: Option<usize>,
}

impl IntegratorOptions {
    /// The options given, by name (for "does not apply" errors).
    fn given(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        let mut add = |on: bool, name| {
            if on {
                out.push(name)
            }
        };
        add(self.integrator.is_some(), "integrator");
        add(self.rtol.is_some(), "rtol");
        add(self.atol.is_some(), "atol");
        add(self.step_doubling, "step_doubling");
        add(self.tolerance.is_some(), "tolerance");
        add(self.linear_solver.is_some(), "linear_solver");
        add(self.newton, "newton");
        add(self.max_steps.is_some(), "max_steps");
        out
    }

    /// Every number given is one the settings can use: tolerances finite and not negative, the step and the
    /// per-step error finite and positive (each error names the keyword).
    fn check_numbers(&self) -> Result<(), WorldError> {
        for (name, v) in [("rtol", self.rtol), ("atol", self.atol)] {
            if let Some(v) = v {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(WorldError::invalid(name, format!("must be finite and >= 0, got {v}")));
                }
            }
        }
        if let Some(dt) = self.dt {
            crate::limits::positive("dt", dt, crate::limits::TIME, "s")?;
        }
        if let Some(t) = self.tolerance {
            crate::limits::positive("tolerance", t, 1e100, "")?;
        }
        Ok(())
    }

    /// An error naming rtol or atol if either is given to a control that has no use for them (`what`).
    fn no_tolerances(&self, what: &str) -> Result<(), WorldError> {
        match (self.rtol.is_some(), self.atol.is_some()) {
            (false, false) => Ok(()),
            (rtol, _) => {
                Err(WorldError::invalid(if rtol { "rtol" } else { "atol" }, format!("does not apply to {what}")))
            }
        }
    }

    /// The settings: step doubling if asked (one-step methods only), the variable-step Euler by its tolerance,
    /// adaptive methods by rtol/atol (dt is then the first step) unless only dt is given, else fixed steps of dt.
    pub fn settings(&self) -> Result<Settings, WorldError> {
        let method: Method = match &self.integrator {
            Some(name) => name.parse()?,
            None => DEFAULT_METHOD,
        };
        self.check_numbers()?;
        let (rtol, atol, dt) = (self.rtol, self.atol, self.dt);
        let mut s = if self.step_doubling {
            if !method.is_one_step() {
                return Err(WorldError::invalid("step_doubling", format!("needs a one-step method, not {method}")));
            }
            self.no_tolerances("step doubling, whose per-step error is `tolerance`")?;
            Settings::step_doubling(method, self.tolerance.unwrap_or(DEFAULT_TOLERANCE), dt.unwrap_or(1e-3))
        } else if method == Method::EulerVariable {
            self.no_tolerances("euler-variable, whose per-step error is `tolerance`")?;
            if dt.is_some() {
                return Err(WorldError::invalid("dt", "euler-variable chooses its own steps from `tolerance`"));
            }
            Settings::euler_variable(self.tolerance.unwrap_or(DEFAULT_TOLERANCE))
        } else if method.has_error_estimate() && (dt.is_none() || rtol.is_some() || atol.is_some()) {
            let s = Settings::tolerances(method, rtol.unwrap_or(DEFAULT_RTOL), atol.unwrap_or(DEFAULT_ATOL));
            match dt {
                Some(h) => s.initial_step(h),
                None => s,
            }
        } else {
            if rtol.is_some() || atol.is_some() {
                let name = if rtol.is_some() { "rtol" } else { "atol" };
                return Err(WorldError::invalid(
                    name,
                    format!("{method} is a fixed-step method: give dt, or step_doubling=True"),
                ));
            }
            Settings::fixed(method, dt.unwrap_or(DEFAULT_DT))
        };
        if self.tolerance.is_some() && !(self.step_doubling || method == Method::EulerVariable) {
            return Err(WorldError::invalid("tolerance", "applies to step doubling and euler-variable only"));
        }
        s = s.linear_solver(match self.linear_solver.as_deref() {
            None | Some("direct") => LinearSolver::Direct,
            Some("iterative") => LinearSolver::Iterative { rtol: 1e-6, max_iter: 2000 },
            Some(other) => {
                return Err(WorldError::invalid(
                    "linear_solver",
                    format!("expected \"direct\" or \"iterative\", got {other:?}"),
                ))
            }
        });
        if self.newton {
            s = s.newton(NewtonMode::Newton { tol: 1e-9, max_iter: 10 });
        }
        if let Some(n) = self.max_steps {
            s = s.max_steps(n);
        }
        Ok(s)
    }
}

/// The options of a contact mode, by name; `None` takes the default. `dt` and `substeps` apply to fast mode only,
/// `contact_tolerance` to accurate mode only; `sleep` to both; `solver` names each mode's own solvers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModeOptions {
    /// Fast mode's step (s; default 1/240).
    pub dt: Option<f64>,
    /// Whether resting islands sleep (default true).
    pub sleep: Option<bool>,
    /// Accurate mode's error allowed in one contact step (m; default 1e-4 of the scene's size).
    pub contact_tolerance: Option<f64>,
    /// The contact solver: fast mode's "soft" (the default) or "exact"; accurate mode's "newton" (the default) or
    /// "clarabel".
    pub solver: Option<String>,
    /// The soft solver's substeps a step (default 8).
    pub substeps: Option<usize>,
}

/// The contact mode from its name ("accurate" or "fast") and its options; an option of the other mode is an error
/// naming it.
pub fn mode_from(name: &str, o: &ModeOptions) -> Result<Mode, WorldError> {
    match name {
        "accurate" => {
            if o.dt.is_some() {
                return Err(WorldError::invalid(
                    "dt",
                    "accurate mode takes its steps from the integrator: give dt with the integrator",
                ));
            }
            if o.substeps.is_some() {
                return Err(WorldError::invalid("substeps", "applies to fast mode's soft solver only"));
            }
            let d = AccurateSettings::default();
            let mode = Mode::Accurate(AccurateSettings {
                contact_tolerance: o.contact_tolerance,
                sleep: o.sleep.unwrap_or(d.sleep),
                solver: o.solver.as_deref().map_or(Ok(d.solver), AccurateSolver::from_name)?,
                ..d
            });
            mode.check()?;
            Ok(mode)
        }
        "fast" => {
            if o.contact_tolerance.is_some() {
                return Err(WorldError::invalid(
                    "contact_tolerance",
                    "only accurate mode controls its contact steps' error; fast mode steps by dt",
                ));
            }
            let solver = match o.solver.as_deref() {
                None | Some("soft") => {
                    let mut soft = SoftSolver::default();
                    if let Some(n) = o.substeps {
                        soft.substeps = n;
                    }
                    FastSolver::Soft(soft)
                }
                Some("exact") => {
                    if o.substeps.is_some() {
                        return Err(WorldError::invalid("substeps", "applies to the soft solver only"));
                    }
                    FastSolver::exact()
                }
                Some(other) => {
                    return Err(WorldError::invalid("solver", format!("expected \"soft\" or \"exact\", got {other:?}")))
                }
            };
            let mode = Mode::Fast(FastSettings {
                sleep: o.sleep.unwrap_or(true),
                solver,
                ..FastSettings::new(o.dt.unwrap_or(DEFAULT_DT))
            });
            mode.check()?;
            Ok(mode)
        }
        other => Err(WorldError::invalid("mode", format!("expected \"accurate\" or \"fast\", got {other:?}"))),
    }
}

/// A world as named by keywords.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WorldOptions {
    /// Gravity; (0, 0, -9.81) by default.
    pub gravity: Option<Vector3<f64>>,
    /// "accurate" (the default) or "fast".
    pub mode: Option<String>,
    /// Whether resting islands sleep (default true).
    pub sleep: Option<bool>,
    /// Threads of the contact solves (0: one per core, the default).
    pub threads: Option<usize>,
    /// Accurate mode: the error allowed in one contact step (m; default 1e-4 of the scene's size).
    pub contact_tolerance: Option<f64>,
    /// The contact solver: fast mode's "soft" (the default) or "exact", accurate mode's "newton" (the default) or
    /// "clarabel".
    pub solver: Option<String>,
    /// Fast mode's soft solver: substeps a step (default 8).
    pub substeps: Option<usize>,
    /// The integrator (accurate mode); its `dt` is fast mode's step in fast mode.
    pub integrator: IntegratorOptions,
    /// How two surfaces' frictions and restitutions combine where neither names its own rule ("average",
    /// "geometric_mean", "min", "product", "max"); the geometric mean and the larger by default.
    pub friction_combine: Option<String>,
    pub restitution_combine: Option<String>,
}

impl WorldOptions {
    fn mode_options(&self) -> ModeOptions {
        ModeOptions {
            dt: None,
            sleep: self.sleep,
            contact_tolerance: self.contact_tolerance,
            solver: self.solver.clone(),
            substeps: self.substeps,
        }
    }

    /// The world these options describe. In fast mode every integrator option but `dt` is an error naming it.
    pub fn build(&self) -> Result<World, WorldError> {
        let name = self.mode.as_deref().unwrap_or("accurate");
        let mut world = World::new();
        if let Some(g) = self.gravity {
            world.set_gravity(g)?;
        }
        if let Some(n) = self.threads {
            world.set_threads(n)?;
        }
        let mut rules = world.combine_rules();
        if let Some(f) = &self.friction_combine {
            rules.friction = crate::collider::Combine::parse("friction_combine", f)?;
        }
        if let Some(r) = &self.restitution_combine {
            rules.restitution = crate::collider::Combine::parse("restitution_combine", r)?;
        }
        world.set_combine_rules(rules);
        if name == "fast" {
            // step_doubling in fast mode estimates each step's error (it does not control the step)
            if let Some(first) = self.integrator.given().into_iter().find(|n| *n != "step_doubling") {
                return Err(WorldError::invalid(
                    first,
                    "does not apply to fast mode, which steps by semi-implicit Euler at its dt",
                ));
            }
            let mut mode = mode_from(name, &ModeOptions { dt: self.integrator.dt, ..self.mode_options() })?;
            if let Mode::Fast(f) = &mut mode {
                f.step_doubling = self.integrator.step_doubling;
            }
            world.set_mode(mode)?;
        } else {
            let mode = mode_from(name, &self.mode_options())?;
            world.set_integrator(self.integrator.settings()?)?;
            world.set_mode(mode)?;
        }
        Ok(world)
    }
}

/// A body as named by keywords: a shape with a density or a total mass, or a mass and an inertia tensor (a shape
/// then only collides), or static.
#[derive(Clone, Debug, Default)]
pub struct BodyOptions {
    /// The body's shape (its mass properties when no inertia is given).
    pub shape: Option<Shape>,
    /// Density (kg/m^3); 1000 when a dynamic body has a shape and nothing else.
    pub density: Option<f64>,
    /// Total mass (kg).
    pub mass: Option<f64>,
    /// Inertia tensor about the centre of mass (body frame), with `mass`.
    pub inertia: Option<Matrix3<f64>>,
    /// A static body: no density, mass or inertia.
    pub is_static: bool,
    /// A kinematic body's path: no density, mass or inertia either.
    pub keyframes: Option<crate::Keyframes>,
}

impl BodyOptions {
    /// The builder these options describe (position, velocities and material are set on it after).
    pub fn builder(self) -> Result<RigidBodyBuilder, WorldError> {
        let BodyOptions { shape, density, mass, inertia, is_static, keyframes } = self;
        if let Some(path) = keyframes {
            if is_static {
                return Err(WorldError::invalid("keyframes", "a static body does not move: it has no keyframes"));
            }
            for (name, given) in
                [("density", density.is_some()), ("mass", mass.is_some()), ("inertia", inertia.is_some())]
            {
                if given {
                    return Err(WorldError::invalid(name, "a kinematic body follows its keyframes: it has no mass"));
                }
            }
            return Ok(RigidBodyBuilder::kinematic(shape, path));
        }
        if is_static {
            if density.is_some() || mass.is_some() || inertia.is_some() {
                return Err(WorldError::invalid("static", "a static body has no density, mass or inertia"));
            }
            return Ok(RigidBodyBuilder::fixed(shape));
        }
        match (shape, density, mass, inertia) {
            (shape, None, Some(m), Some(i)) => {
                let b = RigidBodyBuilder::new(m, i);
                Ok(match shape {
                    Some(s) => b.shape(s),
                    None => b,
                })
            }
            (Some(s), Some(d), None, None) => Ok(RigidBodyBuilder::from_shape(s, d)),
            (Some(s), None, Some(m), None) => Ok(RigidBodyBuilder::from_shape_with_mass(s, m)),
            (Some(s), None, None, None) => Ok(RigidBodyBuilder::from_shape(s, DEFAULT_DENSITY)),
            (_, Some(_), Some(_), _) => Err(WorldError::invalid("density", "give either density or mass, not both")),
            (_, Some(_), None, Some(_)) => Err(WorldError::invalid("inertia", "an inertia tensor needs a mass")),
            (_, None, None, Some(_)) => Err(WorldError::invalid("inertia", "an inertia tensor needs a mass")),
            (None, _, _, None) => {
                Err(WorldError::invalid("shape", "a dynamic body needs a shape, or a mass and an inertia"))
            }
        }
    }
}

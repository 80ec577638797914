//! What a world's steps cost: the integrator's report, how often each force loop ran, and the contact counters
//! (zero while a scene has no contact stage, or a stage never ran).

use crate::model::ForceCounters;
use crate::plan::StageCounts;
use std::fmt;
use tumble_integrate::Report;

/// The cost and accuracy of a world's steps.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldReport {
    /// The integrator's report: steps, rejections, evaluations, Jacobians, factorizations, time, error estimate.
    pub integrator: Report,
    /// How often each force loop ran.
    pub forces: ForceCounters,
    /// Contact programs solved (QPs and conic programs: the Newton method's or clarabel's).
    pub qp_solves: usize,
    /// Collisions resolved: contacts that met closing faster than the resting (accurate) or bounce (fast) speed.
    pub collisions: usize,
    /// Contacts that received an impulse.
    pub impulses: usize,
    /// Bisection steps spent locating collision times (accurate mode).
    pub bisection_steps: usize,
    /// Narrow-phase pair tests (pairs whose boxes overlapped).
    pub collision_checks: usize,
    /// Contact islands solved.
    pub islands: usize,
    /// Actors asleep at the end of the last step (either mode).
    pub sleepers: usize,
    /// Largest penetration seen (m).
    pub max_penetration: f64,
    /// Largest residual of fast mode's soft step (m/s): how far a step's end was from the exact contact conditions
    /// (a touching contact's approach speed, a pushing one's separation, a sticking one's slip); zero with the
    /// exact solver, which meets them to its tolerance.
    pub contact_residual: f64,
    /// Fast mode with step doubling: the largest difference between a step and its two halves (m); `None` without.
    pub step_error: Option<f64>,
    /// The change of mechanical energy (kinetic, gravity's and the springs' potential) over the calls reported (J):
    /// restitution below one, friction and damping take energy out, so without loads that do work a rise is the
    /// method's error.
    pub energy_change: f64,
    /// Fast mode: the largest rise of mechanical energy over one step (J), the energy a step added (zero when no
    /// step added any); `None` in the other modes.
    pub energy_gain: Option<f64>,
    /// Wall time of the calls reported (s): everything the engine did, the integrator's share
    /// (`integrator.wall_seconds`), finding contacts and solving them included.
    pub wall_seconds: f64,
    /// Wall time spent finding contacts (s).
    pub collision_seconds: f64,
    /// Wall time spent in contact solves (s).
    pub contact_seconds: f64,
    /// Of `contact_seconds`, the time spent building the contact programs (s): accurate mode's rows and
    /// Jacobians, the Newton method's sparse Hessian structure and clarabel's matrices; fast mode's soft rows (the
    /// constraint axes and effective masses of every contact, joint and spring), summed over islands (on several
    /// threads it can pass the wall time).
    pub program_seconds: f64,
    /// Contact steps accepted (accurate mode while bodies touch).
    pub contact_steps: usize,
    /// Contact steps rejected by their error estimate.
    pub contact_rejected: usize,
    /// Largest error estimate of an accepted contact step (m).
    pub contact_error: f64,
    /// Accurate mode: the contact tolerance in force (m), the settings' or the default from the scene's size (what
    /// `contact_error` is held within); `None` before contacts were set up, and in the other modes.
    pub contact_tolerance: Option<f64>,
    /// Smallest accepted contact step (s; infinite before any).
    pub contact_min_step: f64,
    /// Rows the joints gave at the last step measured.
    pub joint_rows: usize,
    /// Largest joint position error seen (m): fast mode after every step, accurate mode at the end of every call.
    pub joint_error: f64,
    /// Largest joint angle error seen (rad), as `joint_error`.
    pub joint_angle_error: f64,
    /// How many times each stage ran.
    pub stages: StageCounts,
    /// Convex pieces of the moving bodies' decomposed meshes.
    pub mesh_pieces: usize,
    /// Seconds their decompositions took (each the first time its mesh was decomposed in the process, or as saved).
    pub decomposition_seconds: f64,
}

/// One field of a report, for bindings and tables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReportValue {
    /// A count.
    Count(usize),
    /// A number.
    Number(f64),
    /// A number that is absent (a step size before any step, an estimate of a method without one).
    Optional(Option<f64>),
    /// A name.
    Text(&'static str),
}

impl WorldReport {
    pub(crate) fn new(method: &'static str) -> Self {
        WorldReport {
            integrator: Report::empty(method),
            forces: ForceCounters::default(),
            qp_solves: 0,
            collisions: 0,
            impulses: 0,
            bisection_steps: 0,
            collision_checks: 0,
            islands: 0,
            sleepers: 0,
            max_penetration: 0.0,
            contact_residual: 0.0,
            step_error: None,
            energy_change: 0.0,
            energy_gain: None,
            wall_seconds: 0.0,
            collision_seconds: 0.0,
            contact_seconds: 0.0,
            program_seconds: 0.0,
            contact_steps: 0,
            contact_rejected: 0,
            contact_error: 0.0,
            contact_tolerance: None,
            contact_min_step: f64::INFINITY,
            joint_rows: 0,
            joint_error: 0.0,
            joint_angle_error: 0.0,
            stages: StageCounts::default(),
            mesh_pieces: 0,
            decomposition_seconds: 0.0,
        }
    }

    /// Every field of the report by name, in a fixed order: the integrator's counters, the contact counters, the
    /// force loops'. The one list bindings and tables are made from.
    pub fn fields(&self) -> Vec<(&'static str, ReportValue)> {
        use ReportValue::{Count, Number, Optional, Text};
        let i = &self.integrator;
        let f = &self.forces;
        let stepped = |h: f64| Optional((i.steps > 0).then_some(h));
        vec![
            ("method", Text(i.method)),
            ("steps", Count(i.steps)),
            ("rejected", Count(i.rejected)),
            ("rhs_evals", Count(i.rhs_evals)),
            ("jacobians", Count(i.jacobians)),
            ("factorizations", Count(i.factorizations)),
            ("linear_solves", Count(i.linear_solves)),
            ("newton_iterations", Count(i.newton_iterations)),
            ("krylov_iterations", Count(i.krylov_iterations)),
            ("min_step", stepped(i.min_step)),
            ("max_step", stepped(i.max_step)),
            ("wall_seconds", Number(self.wall_seconds)),
            ("integrator_seconds", Number(i.wall_seconds)),
            ("error_estimate", Optional(i.error_estimate)),
            ("qp_solves", Count(self.qp_solves)),
            ("collisions", Count(self.collisions)),
            ("impulses", Count(self.impulses)),
            ("bisection_steps", Count(self.bisection_steps)),
            ("collision_checks", Count(self.collision_checks)),
            ("islands", Count(self.islands)),
            ("sleepers", Count(self.sleepers)),
            ("max_penetration", Number(self.max_penetration)),
            ("contact_residual", Number(self.contact_residual)),
            ("step_error", Optional(self.step_error)),
            ("energy_change", Number(self.energy_change)),
            ("energy_gain", Optional(self.energy_gain)),
            ("collision_seconds", Number(self.collision_seconds)),
            ("contact_seconds", Number(self.contact_seconds)),
            ("program_seconds", Number(self.program_seconds)),
            ("contact_steps", Count(self.contact_steps)),
            ("contact_rejected", Count(self.contact_rejected)),
            ("contact_error", Optional((self.contact_steps > 0).then_some(self.contact_error))),
            ("contact_tolerance", Optional(self.contact_tolerance)),
            ("contact_min_step", Optional((self.contact_steps > 0).then_some(self.contact_min_step))),
            ("joint_rows", Count(self.joint_rows)),
            ("joint_error", Number(self.joint_error)),
            ("joint_angle_error", Number(self.joint_angle_error)),
            ("evaluations", Count(f.evaluations)),
            ("spring_evaluations", Count(f.spring_evaluations)),
            ("load_evaluations", Count(f.load_evaluations)),
            ("callback_calls", Count(f.callback_calls)),
            ("projections", Count(f.projections)),
            ("mesh_pieces", Count(self.mesh_pieces)),
            ("decomposition_seconds", Number(self.decomposition_seconds)),
        ]
    }

    pub(crate) fn merge(&mut self, o: &WorldReport) {
        self.integrator.merge(&o.integrator);
        self.forces += o.forces;
        self.merge_contact(o);
        self.islands += o.islands;
        self.sleepers = o.sleepers;
        self.energy_change += o.energy_change;
        self.wall_seconds += o.wall_seconds;
        self.stages += o.stages;
    }

    /// Adds the contact counters of `o` (collisions, impulses, bisection steps, checks, QP solves, penetration,
    /// times), leaving the integrator's, the force loops', islands and sleepers alone.
    pub(crate) fn merge_contact(&mut self, o: &WorldReport) {
        self.qp_solves += o.qp_solves;
        self.collisions += o.collisions;
        self.impulses += o.impulses;
        self.bisection_steps += o.bisection_steps;
        self.collision_checks += o.collision_checks;
        self.max_penetration = self.max_penetration.max(o.max_penetration);
        self.contact_residual = self.contact_residual.max(o.contact_residual);
        let largest = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        self.step_error = largest(self.step_error, o.step_error);
        self.energy_gain = largest(self.energy_gain, o.energy_gain);
        self.collision_seconds += o.collision_seconds;
        self.contact_seconds += o.contact_seconds;
        self.program_seconds += o.program_seconds;
        self.contact_steps += o.contact_steps;
        self.contact_rejected += o.contact_rejected;
        self.contact_error = self.contact_error.max(o.contact_error);
        self.contact_tolerance = o.contact_tolerance.or(self.contact_tolerance);
        self.contact_min_step = self.contact_min_step.min(o.contact_min_step);
        self.joint_rows = if o.joint_rows > 0 { o.joint_rows } else { self.joint_rows };
        self.joint_error = self.joint_error.max(o.joint_error);
        self.joint_angle_error = self.joint_angle_error.max(o.joint_angle_error);
    }

    /// Books joint errors (m, rad) measured at a state with `rows` joint rows.
    pub(crate) fn book_joints(&mut self, rows: usize, (position, angle): (f64, f64)) {
        self.joint_rows = rows;
        self.joint_error = self.joint_error.max(position);
        self.joint_angle_error = self.joint_angle_error.max(angle);
    }
}

impl WorldReport {
    /// Whether fast mode made it.
    fn fast(&self) -> bool {
        self.integrator.method.starts_with("fast")
    }

    /// The line that says which mode ran and when to pick the other.
    fn mode_line(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.fast() {
            writeln!(
                f,
                "mode             fast: fixed steps, Catto's soft step, an error estimated only with step_doubling \
                 (mode=\"accurate\", the default, holds every step to a tolerance and puts impacts where they happen)"
            )
        } else {
            writeln!(
                f,
                "mode             accurate ({}): every step held to a tolerance, impacts where they happen \
                 (mode=\"fast\" takes fixed steps: for piles of hundreds of bodies, many times faster)",
                self.integrator.method
            )
        }
    }

    /// The one error line: in metres where the mode can say, against what was asked.
    fn error_line(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "error            ")?;
        if self.fast() {
            return match self.step_error {
                Some(e) => writeln!(f, "a step differs from its two halves by at most {e:.3e} m (step doubling)"),
                None => writeln!(f, "not estimated (fixed steps; step_doubling=True measures each against two halves)"),
            };
        }
        let mut said = false;
        if self.contact_steps > 0 {
            write!(f, "contact steps at most {:.3e} m each", self.contact_error)?;
            if let Some(t) = self.contact_tolerance {
                write!(f, " (asked: {t:.3e} m, contact_tolerance)")?;
            }
            said = true;
        }
        match self.integrator.error_estimate {
            Some(e) if self.integrator.steps > 0 => {
                let sep = if said { "; " } else { "" };
                write!(f, "{sep}free flight {e:.3e} (its steps' local error estimates summed, metres for positions)")?;
            }
            _ if !said => write!(f, "none estimated (the method has no estimate)")?,
            _ => {}
        }
        writeln!(f)
    }
}

impl fmt::Display for WorldReport {
    /// The report a person reads: which mode ran (and when to pick the other), one error line in metres, the steps,
    /// contact, energy and wall time. The alternate form (`{:#}`) adds what a maintainer reads: the integrator's
    /// counters, the force loops, the time's split, the soft step's residual and the stages that ran.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let i = &self.integrator;
        self.mode_line(f)?;
        self.error_line(f)?;
        write!(f, "steps            {} accepted, {} rejected", i.steps, i.rejected)?;
        if i.steps > 0 {
            write!(f, ", {:.3e} .. {:.3e} s", i.min_step, i.max_step)?;
        }
        if self.contact_steps > 0 {
            write!(
                f,
                "; contact steps {} accepted, {} rejected, smallest {:.3e} s",
                self.contact_steps, self.contact_rejected, self.contact_min_step
            )?;
        }
        writeln!(f)?;
        writeln!(
            f,
            "contact          {} collisions met by impulses, deepest penetration {:.3e} m, {} bodies asleep, {} contact \
             programs solved over {} islands, {} narrow-phase pair tests",
            self.collisions, self.max_penetration, self.sleepers, self.qp_solves, self.islands, self.collision_checks
        )?;
        write!(f, "energy           changed by {:.3e} J", self.energy_change)?;
        if let Some(g) = self.energy_gain {
            write!(f, ", the largest rise over one step {g:.3e} J")?;
        }
        if self.joint_rows > 0 {
            write!(
                f,
                "\njoints           {} rows, largest error {:.3e} m and {:.3e} rad",
                self.joint_rows, self.joint_error, self.joint_angle_error
            )?;
        }
        if self.mesh_pieces > 0 {
            write!(
                f,
                "\nmeshes           {} convex pieces, decomposed in {:.3} s",
                self.mesh_pieces, self.decomposition_seconds
            )?;
        }
        write!(f, "\nwall time        {:.6} s", self.wall_seconds)?;
        if !f.alternate() {
            return Ok(());
        }
        write!(
            f,
            " in all: {:.6} s integrating, {:.6} s finding contacts, {:.6} s solving them ({:.6} s building their \
             programs)",
            i.wall_seconds, self.collision_seconds, self.contact_seconds, self.program_seconds
        )?;
        write!(f, "\n{i}")?;
        let c = &self.forces;
        write!(
            f,
            "\nforce loops      {} evaluations: {} spring, {} load, {} callback; {} quaternion projections",
            c.evaluations, c.spring_evaluations, c.load_evaluations, c.callback_calls, c.projections
        )?;
        write!(
            f,
            "\ncontact work     {} contacts given an impulse, {} bisection steps",
            self.impulses, self.bisection_steps
        )?;
        if self.contact_residual > 0.0 {
            write!(
                f,
                "\nsoft step        residual {:.1e} m/s: the largest speed a contact was left off its exact condition \
                 after the step's iterations (approach at a touching contact, slip at a sticking one), which the soft \
                 contacts then take up over the next steps; not an error of the motion",
                self.contact_residual
            )?;
        }
        write!(f, "\nstages ran       {}", self.stages.ran().join(" -> "))
    }
}

//! What a run is asked to do: duration, output step and integrator, and the bounds that make
//! every run end.

use crate::integrate::{ErrorNorm, Limits};
use crate::model::Model;

/// Time integration method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Dormand–Prince 8(5,3), adaptive, 7th-order dense output.
    Dop853 {
        /// Relative tolerance per state component.
        rtol: f64,
        /// Absolute tolerance per state component (m, m/s, rad/s, quaternion units).
        atol: f64,
    },
    /// Dormand–Prince 5(4), adaptive, 4th-order dense output.
    Dopri5 {
        /// Relative tolerance per state component.
        rtol: f64,
        /// Absolute tolerance per state component.
        atol: f64,
    },
    /// SDIRK4, L-stable implicit (for stiff hinges), adaptive, with the hinge-graph-sparse
    /// Newton matrix of [`crate::dynamics::newton`]; cubic Hermite dense output.
    Sdirk4 {
        /// Relative tolerance per component.
        rtol: f64,
        /// Absolute tolerance per component.
        atol: f64,
    },
    /// DOP853 while it pays, an implicit method where stiffness limits DOP853's steps
    /// (adaptive generalized-α, or SDIRK4 with contact), and back: the default
    /// (docs/scenario.md; [`super::switching`]).
    Auto {
        /// Relative tolerance per component.
        rtol: f64,
        /// Absolute tolerance per component.
        atol: f64,
    },
    /// Generalized-α (Jansen, Whiting & Hulbert 2000): second order, one implicit stage,
    /// high-frequency damping set by ρ∞ ([`crate::integrate::galpha`]); at a fixed step, or
    /// adaptive with its local error held to rtol and atol in the run's error norm.
    GeneralizedAlpha {
        /// Fixed step, s; `None` for adaptive steps.
        step: Option<f64>,
        /// Spectral radius at infinite frequency, in [0, 1] (1: no numerical damping).
        rho_inf: f64,
        /// Relative tolerance per component: of the Newton iterations at a fixed step, of
        /// the local error (and the Newton iterations) with adaptive steps.
        rtol: f64,
        /// Absolute tolerance per component, as `rtol`.
        atol: f64,
    },
    /// Classical fourth-order Runge–Kutta with a fixed step.
    Rk4 {
        /// Step, s.
        step: f64,
    },
}

/// The relative tolerance below which an adaptive run ends its steps where contact points
/// enter or leave contact (docs/contact.md, *Energy*): from there the error of a step
/// straddling the contact law's bend, which the error estimate does not see, is what limits
/// the energy balance (4.6e-6 relative on the contact z-fold at rtol 1e-8, 1.4e-6 at 1e-11
/// without; 6e-9 at 1e-11 with, at 1.7× the cost). Looser runs keep their speed (3× the
/// cost at rtol 1e-8).
pub const LOCATE_CONTACT_RTOL: f64 = 1e-9;

impl Integrator {
    /// Whether the run ends its steps at contact changes ([`LOCATE_CONTACT_RTOL`]): an
    /// adaptive method at a relative tolerance below it.
    pub fn locates_contact_changes(&self) -> bool {
        match *self {
            Integrator::Dop853 { rtol, .. }
            | Integrator::Dopri5 { rtol, .. }
            | Integrator::Sdirk4 { rtol, .. }
            | Integrator::Auto { rtol, .. } => rtol < LOCATE_CONTACT_RTOL,
            Integrator::GeneralizedAlpha { .. } | Integrator::Rk4 { .. } => false,
        }
    }

    /// Name as written in scenario files.
    pub fn name(&self) -> &'static str {
        match self {
            Integrator::Dop853 { .. } => "dop853",
            Integrator::Dopri5 { .. } => "dopri5",
            Integrator::Sdirk4 { .. } => "sdirk4",
            Integrator::Auto { .. } => "auto",
            Integrator::Rk4 { .. } => "rk4",
            Integrator::GeneralizedAlpha { .. } => "generalized-alpha",
        }
    }
}

/// How long to run and how often to output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings {
    /// Simulated time, s (> 0).
    pub duration: f64,
    /// Interval between output rows, s (> 0). Rows are at `k · output_step` and at `duration`.
    pub output_step: f64,
    /// Integration method.
    pub integrator: Integrator,
    /// How the implicit steps (SDIRK4, adaptive generalized-α, `auto`'s implicit spans) weigh each component's
    /// error (`run.error_norm`): the rates by the step (the default of `auto`), or every
    /// component as it is (the default of `sdirk4`).
    pub error_norm: ErrorNorm,
    /// Solve for every lock from the start, rather than engaging each once it carries load
    /// (see [`crate::dynamics::Dynamics::disengage_locks`]): the same motion at a higher
    /// cost, for comparison. Not a scenario key; false from a scenario.
    pub engage_locks_at_start: bool,
    /// Most integration steps, accepted and rejected (`run.max_steps`); `None` for the
    /// default of [`default_step_budget`].
    pub max_steps: Option<usize>,
    /// Holds the initial (stowed) state with a restraint until this time, s (`run.release_at`,
    /// 0 < t < duration): every tree hinge is locked where it starts, so the structure turns
    /// as one rigid body; then the restraint lets go.
    pub release_at: Option<f64>,
    /// Add the reactions of locked directions to the hinge loads of every output row
    /// (`Observation::hinge_force_in_a0`, `hinge_torque_in_a`): one more evaluation with every
    /// lock solved for per row, so only when a hinge-load column is written or measured (set
    /// from [`crate::observe::Selection::has_hinge_loads`]).
    pub hinge_loads: bool,
    /// The largest error asked in any body's centre of mass over the output rows, m
    /// (`run.position_tolerance`): the run is made at tolerances the error estimate of
    /// [`super::accuracy`] chooses, the integrator's rtol and atol replaced. `None`: the
    /// integrator's own tolerances.
    pub position_tolerance: Option<f64>,
}

/// The most output rows a run writes (`duration / output_step`): ten million rows of even the
/// smallest structure are gigabytes, more than anyone reads back.
pub const MAX_OUTPUT_ROWS: f64 = 1e7;

/// The tightest relative tolerance accepted: 10 units of round-off (Hairer's bound: no step
/// can meet a tighter one).
pub const MIN_RTOL: f64 = 10.0 * f64::EPSILON;

/// The step floor, as a fraction of the run's duration: a step-size control that wants
/// smaller steps stops the run (explicit methods need steps of ~3 / the fastest hinge rate;
/// below 1e-12 of the duration the run would take more than 1e12 steps).
pub const MIN_STEP_OF_DURATION: f64 = 1e-12;

/// The default step budget per radian of the fastest hinge motion over the run (see
/// [`default_step_budget`]).
pub const STEPS_PER_RADIAN: f64 = 10.0;

/// The smallest default step budget.
pub const MIN_STEP_BUDGET: f64 = 1e6;

/// A default step budget beyond this many steps is refused when a scenario is loaded,
/// unless `run.max_steps` is given: at a microsecond per step and hinge it would run for
/// weeks.
pub const MAX_DEFAULT_STEP_BUDGET: f64 = 1e9;

/// The default step budget of a run of `duration` s: `max(1e6, 10 × duration × rate)` with
/// `rate` the fastest hinge rate ([`crate::model::rates::HingeRate`], an upper bound on how
/// fast any hinge direction can move). An explicit method needs about `duration × rate / 3`
/// steps where the stiffest hinge limits it, so the budget is ~30 times what a run can need;
/// a run that takes more has left the physics (a singular motion, tolerances beyond f64).
pub fn default_step_budget(model: &Model, duration: f64) -> f64 {
    let rate = model.fastest_hinge().map_or(0.0, |r| r.rate);
    (STEPS_PER_RADIAN * duration * rate).max(MIN_STEP_BUDGET)
}

impl RunSettings {
    /// The bounds the run holds its integrator to: steps no shorter than
    /// [`MIN_STEP_OF_DURATION`] × duration, and at most `max_steps` of them.
    pub fn limits(&self, model: &Model) -> Limits {
        // A fixed step asks for duration / step steps: the budget leaves room for twice that
        // (cuts to land on breaks, halvings where Newton fails) whatever the hinges' rates.
        let fixed = match self.integrator {
            Integrator::Rk4 { step } | Integrator::GeneralizedAlpha { step: Some(step), .. } => {
                2.0 * self.duration / step
            }
            _ => 0.0,
        };
        let max_steps = self.max_steps.unwrap_or_else(|| {
            default_step_budget(model, self.duration).max(fixed).min(MAX_DEFAULT_STEP_BUDGET) as usize
        });
        Limits { min_step: MIN_STEP_OF_DURATION * self.duration, max_steps, ..Limits::default() }
    }
}

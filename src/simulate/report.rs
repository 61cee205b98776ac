//! What a run reports when it finishes, and why it stops when it does not.

use crate::dynamics::LawEvent;
use crate::dynamics::locks::Lock;
use thiserror::Error;

/// Largest departures from the initial values over all output rows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Drift {
    /// max |P(t) − P(0)|, kg·m/s.
    pub momentum: f64,
    /// max Σ m_i |Ṙ_i| over the run, kg·m/s (scale for a relative figure).
    pub momentum_scale: f64,
    /// max |H(t) − H(0)|, kg·m²/s.
    pub angular_momentum: f64,
    /// max Σ (|R_i × m_i Ṙ_i| + |I_i ω_i|) over the run, kg·m²/s.
    pub angular_momentum_scale: f64,
    /// max |R_c(t) − (R_c(0) + P(0) t / M)|, m: the departure from the uniform motion that
    /// the initial momentum gives the barycenter (zero for a system at rest).
    pub barycenter: f64,
    /// max |E(t) − E(0)|, J.
    pub energy: f64,
    /// E(0), J.
    pub energy_initial: f64,
    /// E at the last row minus E(0), J.
    pub energy_final_change: f64,
    /// Energy dissipated by the hinges by the last row, J.
    pub dissipated: f64,
    /// max |(E + D)(t) − (E + D)(0)|: the energy balance, J.
    pub energy_balance: f64,
    /// Number of locked directions.
    pub locks: usize,
    /// max |δ_k(t) − δ_k(0)| over the output rows and the locked translations, m (A0
    /// components).
    pub locked_translation: f64,
    /// max |θ_k(t) − θ_k(0)| over the output rows and the locked rotations, rad (3-2-1 Euler
    /// angles of `[A A0]`).
    pub locked_rotation: f64,
}

/// A span of a run under `integrator = "auto"` taken by one method.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodSpan {
    /// When the method took over, s.
    pub from: f64,
    /// `"dop853"` or `"sdirk4"`.
    pub method: &'static str,
    /// Why it took over, for a person.
    pub why: String,
    /// The step DOP853 was held to by stability when SDIRK4 took over, s.
    pub stable_step: Option<f64>,
}

/// What a finished run reports.
#[derive(Clone, Debug, PartialEq)]
pub struct RunReport {
    /// Simulated time, s.
    pub simulated: f64,
    /// Wall-clock time of the integration, s.
    pub wall_seconds: f64,
    /// Accepted steps.
    pub steps_accepted: usize,
    /// Rejected steps.
    pub steps_rejected: usize,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// Output rows written.
    pub rows: usize,
    /// Conservation figures.
    pub drift: Drift,
    /// True if every hinge law conserves E (so `drift.energy` should be small).
    pub energy_conserving: bool,
    /// Located stop and latch events (contacts, releases, latches), in time order.
    pub events: Vec<LawEvent>,
    /// First time at which the explicit integrator found its step limited by stability (stiff
    /// hinges), if it did.
    pub stiff_from: Option<f64>,
    /// The methods `integrator = "auto"` used and when it switched (empty for the others).
    pub methods: Vec<MethodSpan>,
    /// Of the rejected steps, those rejected because Newton did not converge (implicit path).
    pub newton_failures: usize,
    /// Newton iterations (implicit path; zero otherwise).
    pub newton_iterations: usize,
    /// Jacobians formed (implicit path).
    pub jacobians: usize,
    /// Refactorizations of the Newton matrix for a new step size (SDIRK4).
    pub refactorizations: usize,
    /// Of those, formed by finite differences because the exact (dual-number) Jacobian does
    /// not cover the model (a hinge law without a dual form; none of the shipped laws).
    pub differenced_jacobians: usize,
    /// Number of other located law events (hysteresis branch changes, table data points
    /// crossed): counted, not kept, so memory stays flat in run length.
    pub branch_events: usize,
    /// Per hinge: energy dissipated over the run, J.
    pub hinge_dissipated: Vec<f64>,
    /// When the restraint that held the initial (stowed) state let go, s (see
    /// [`crate::simulate::RunSettings::release_at`]).
    pub released_at: Option<f64>,
    /// When the structure first reached 90 % of its deployed design radius, from below
    /// (interpolated between output rows), s; `None` if it did not.
    pub deployed_90: Option<f64>,
    /// The deployed fraction (the `deployed` column) at the start, and the largest it
    /// reached; NaN for a structure without panels.
    pub deployed_start: f64,
    /// See [`RunReport::deployed_start`].
    pub deployed_max: f64,
    /// Of `rhs_evaluations`, those that solved for engaged locks.
    pub constrained_evaluations: u64,
    /// Locks that engaged (carried load), with the time from which they were solved for
    /// (s), in time order. A run starts with every lock disengaged: a locked direction with
    /// no load keeps its value without a constraint force, and is checked after every step;
    /// once it drifts, it engages and the step is retaken with it.
    pub lock_engagements: Vec<(Lock, f64)>,
    /// Contact over the run (at accepted steps), when the model has contact.
    pub contact: Option<crate::contact::ContactRecord>,
    /// Every contact episode of every body pair, in the order they started (docs/contact.md).
    pub contact_episodes: Vec<crate::contact::episodes::Episode>,
    /// Energy contact dissipated over the run (damping and friction), J.
    pub contact_dissipated: f64,
    /// What the external loads gave the system by the end (work, impulse, angular impulse),
    /// when the model has loads; the drifts are net of it.
    pub loads: Option<crate::observe::LoadTotals>,
    /// Per actuator of the hub's control (in the model's order), what it did: its largest
    /// effort and momentum, and when its torque or momentum limit cut it.
    pub actuators: Vec<crate::dynamics::actuators::ActuatorRecord>,
    /// With `run.position_tolerance`: what was asked and estimated ([`super::accuracy`]).
    pub position_accuracy: Option<PositionAccuracy>,
}

/// What a run held to `run.position_tolerance` estimated ([`super::accuracy`]).
#[derive(Clone, Debug, PartialEq)]
pub struct PositionAccuracy {
    /// The tolerance asked, m.
    pub asked: f64,
    /// The output run's estimated largest error in any body's centre of mass over its rows, m
    /// (N components).
    pub estimated: f64,
    /// The largest difference between the output run and its check, m.
    pub difference: f64,
    /// The output run's rtol = atol.
    pub rtol: f64,
    /// Its check's rtol = atol: a quarter of `rtol`, or, for an output loosened from a run
    /// far within the tolerance, that run's (docs/scenario.md, *A position tolerance*).
    pub check_rtol: f64,
    /// Every run made, in order: (rtol = atol, wall time s).
    pub runs: Vec<(f64, f64)>,
}

/// Why a run stopped early.
#[derive(Debug, Error)]
pub enum SimError {
    /// The integrator gave up.
    #[error("integration failed at t = {t} s: {message}")]
    Integrator {
        /// Time reached, s.
        t: f64,
        /// Reason.
        message: String,
    },
    /// The physics left the model's domain (e.g. gimbal lock of a hinge's Euler angles).
    #[error("{0}")]
    Physics(String),
    /// The progress callback asked the run to stop (Ctrl-C).
    #[error("interrupted at t = {t} s")]
    Interrupted {
        /// Time reached, s.
        t: f64,
    },
    /// The output sink failed.
    #[error("writing output: {0}")]
    Output(String),
}

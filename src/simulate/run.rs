//! A run: its preparation, the integration over a span of time with the step handler of
//! [`super::stream`], its report, and why it stopped when it did.

use super::pace::ProgressFn;
use super::report::{Drift, RunReport, SimError};
use super::settings::{Integrator, MAX_OUTPUT_ROWS, RunSettings};
use super::stopped::stopped;
use super::stream::{OutputTimes, Restore, RunState, StreamOut, Tracked};
use crate::dynamics::Dynamics;
use crate::dynamics::newton::GraphNewton;
use crate::integrate::{AlphaSteps, Limits, Method, Stats, integrate, integrate_generalized_alpha, integrate_sdirk4};
use crate::kinematics::{InitialConditions, initial_state};
use crate::loads::breaks::Breaks;
use crate::model::Model;
use crate::observe::Observer;
use std::time::Instant;

pub use super::stream::Sink;

/// [`super::simulate`] at the integrator's own tolerances.
pub(super) fn simulate_once(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    sink: &mut dyn Sink,
    progress: Option<&mut ProgressFn<'_>>,
) -> Result<RunReport, SimError> {
    simulate_once_at(model, ic, settings, None, sink, progress)
}

/// A run at the integrator's own tolerances with its rows at `times` (s) instead of every
/// `run.output_step`: each row from the step's dense output at exactly that time, as the
/// grid's rows are (what a fit compares with measurements taken at any times, `crate::fit`).
/// The times must be finite, strictly ascending and within [0, `run.duration`]; the run
/// still goes on to `run.duration`. `run.position_tolerance` is refused: its runs at other
/// tolerances are compared row by row on the grid.
pub fn simulate_at(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    times: &[f64],
    sink: &mut dyn Sink,
) -> Result<RunReport, SimError> {
    if settings.position_tolerance.is_some() {
        return Err(SimError::Physics(
            "run.position_tolerance: rows at chosen times are made at the integrator's own rtol and atol; leave run.position_tolerance out".into(),
        ));
    }
    if times.is_empty() {
        return Err(SimError::Physics("no output times given".into()));
    }
    for (i, t) in times.iter().enumerate() {
        if !(t.is_finite() && *t >= 0.0 && *t <= settings.duration) || (i > 0 && *t <= times[i - 1]) {
            return Err(SimError::Physics(format!(
                "output time {t} s (the {}th): times must be finite, strictly ascending and within the run, 0 to {} s",
                i + 1,
                settings.duration
            )));
        }
    }
    simulate_once_at(model, ic, settings, Some(times), sink, None)
}

fn simulate_once_at(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    times: Option<&[f64]>,
    sink: &mut dyn Sink,
    progress: Option<&mut ProgressFn<'_>>,
) -> Result<RunReport, SimError> {
    if !(settings.duration > 0.0 && settings.output_step > 0.0)
        || settings.duration / settings.output_step > MAX_OUTPUT_ROWS
    {
        return Err(SimError::Physics(format!(
            "run.duration = {} s and run.output_step = {} s: both must be > 0, with at most {MAX_OUTPUT_ROWS:e} rows",
            settings.duration, settings.output_step
        )));
    }
    let (dynamics, y0, mut state) = prepare(model, ic, settings)?;
    if let Some(times) = times {
        state.output_times.list = Some(times.to_vec());
    }
    let mut out = StreamOut { dynamics: &dynamics, sink, progress, s: &mut state };
    let start = Instant::now();
    let mut end = y0.clone();
    let result = integrate_span(&mut out, settings, 0.0, settings.duration, &y0, None, &mut end);
    let wall_seconds = start.elapsed().as_secs_f64();
    let (stats, differenced_jacobians) = result?;
    if state.output_times.peek().is_some() {
        return Err(SimError::Integrator {
            t: state.t_reached,
            message: "the integrator stopped before the end of the run".into(),
        });
    }
    Ok(report(&dynamics, settings, &state, &stats, wall_seconds, differenced_jacobians))
}

/// A run's dynamics, initial state and run state, checked, before its first step.
pub(super) fn prepare<'m>(
    model: &'m Model,
    ic: &InitialConditions,
    settings: &RunSettings,
) -> Result<(Dynamics<'m>, Vec<f64>, RunState), SimError> {
    let (mut y0, theta_refs) = initial_state(model, ic);
    let dynamics = Dynamics::new(model, theta_refs);
    // Contact that starts before the launch restraint lets go is the stowed package's.
    dynamics.set_resting_until(settings.release_at.unwrap_or(0.0));
    dynamics.set_initial_wheels(&mut y0);
    dynamics.initialize_memory(&y0);
    if settings.release_at.is_some() {
        dynamics.restrain_tree_hinges(&y0);
    }
    if let Some(cause) = dynamics.non_finite_cause(&y0) {
        return Err(SimError::Physics(format!("the initial state: {cause}")));
    }
    dynamics.check_locks(&y0).map_err(|(_, m)| SimError::Physics(m))?;
    // Initial rates along locked directions are removed (positions hold by construction).
    dynamics.project(&mut y0, true);
    // Locks are solved for only once they carry load (see `Dynamics::disengage_locks`).
    if !settings.engage_locks_at_start {
        dynamics.disengage_locks();
    }
    let n_events = dynamics.event_count();
    // Where the right-hand side jumps: no step passes these, and the integration restarts
    // at each.
    let breaks = Breaks::new(
        model.loads.iter().flat_map(|l| l.breaks()).chain(model.motors.iter().flat_map(|m| m.breaks())).collect(),
        model.control.as_ref().and_then(|c| c.period),
        settings.duration,
    );
    dynamics.set_breaks(breaks.clone());
    let implicit = matches!(settings.integrator, Integrator::Sdirk4 { .. } | Integrator::GeneralizedAlpha { .. });
    let may_be_implicit = implicit || matches!(settings.integrator, Integrator::Auto { .. });
    let state = RunState {
        total_mass: model.total_mass(),
        observer: Observer::new(model, ic.hub_attitude, &dynamics.momentum_about_barycenter(&y0)),
        output_times: OutputTimes {
            step: settings.output_step,
            end: settings.duration,
            next: 0,
            done: false,
            list: None,
        },
        first: None,
        last: None,
        drift: Drift::default(),
        rows: 0,
        t_reached: 0.0,
        buffer: Vec::new(),
        g_prev: vec![0.0; n_events],
        g_end: vec![0.0; n_events],
        g_change: vec![0.0; n_events],
        events: Vec::new(),
        branch_events: 0,
        lock_engagements: Vec::new(),
        same_instant: (f64::NAN, 0),
        resync_events: false,
        pending: None,
        // The implicit method conserves momentum only to its tolerance, and the projection
        // of locked directions moves positions; a rigid-body velocity correction holds the
        // momenta exactly without touching the internal motion (or the locked rates).
        // (Not with external loads: they change the momenta.)
        momenta: (!model.has_external() && (may_be_implicit || dynamics.has_locks())).then(|| dynamics.momenta(&y0)),
        restore: if implicit { Restore::EveryStep } else { Restore::AfterProjections },
        momentum_scales: [0.0; 2],
        deployed_90: None,
        deployed_range: (f64::NAN, f64::NAN),
        release_at: settings.release_at,
        load_breaks: breaks,
        locate_contacts: settings.integrator.locates_contact_changes(),
        hinge_loads: settings.hinge_loads,
        released_at: None,
        spans: Vec::new(),
        method: match settings.integrator {
            Integrator::Auto { .. } => "dop853",
            other => other.name(),
        },
        steps: 0,
        step_budget: settings.limits(model).max_steps,
        window_longest: 0.0,
        started: Instant::now(),
    };
    Ok((dynamics, y0, state))
}

/// Integrates from `(t0, y0)` to `t1` with the run's step handler `out`, trying
/// `first_step` first when given, and leaves the state reached in `end`. Returns the
/// integrator's figures and how many Jacobians were differenced.
pub(super) fn integrate_span(
    out: &mut StreamOut<'_, '_, '_, '_>,
    settings: &RunSettings,
    t0: f64,
    t1: f64,
    y0: &[f64],
    first_step: Option<f64>,
    end: &mut Vec<f64>,
) -> Result<(Stats, usize), SimError> {
    let dynamics = out.dynamics;
    let model = dynamics.model();
    let limits = Limits { first_step, ..settings.limits(model) };
    end.clone_from_slice(y0);
    if let Integrator::Auto { rtol, atol } = settings.integrator {
        return super::switching::integrate_auto(out, settings, rtol, atol, t0, t1, y0, first_step, end);
    }
    let mut tracked = Tracked { out, end };
    let on_step = |step: &crate::integrate::Step<'_>| tracked.on_step(step);
    let mut differenced_jacobians = 0;
    let result = match settings.integrator {
        Integrator::Sdirk4 { rtol, atol } => {
            let mut newton = GraphNewton::new_exact(dynamics, model, dynamics);
            let r =
                integrate_sdirk4(dynamics, &mut newton, rtol, atol, settings.error_norm, limits, t0, t1, y0, on_step);
            differenced_jacobians = newton.jacobian_counts().1;
            r
        }
        Integrator::GeneralizedAlpha { step, rho_inf, rtol, atol } => {
            let mut newton = GraphNewton::new_exact(dynamics, model, dynamics);
            let r = integrate_generalized_alpha(
                dynamics,
                &mut newton,
                step.map_or(AlphaSteps::Adaptive(settings.error_norm), AlphaSteps::Fixed),
                rho_inf,
                rtol,
                atol,
                limits,
                t0,
                t1,
                y0,
                on_step,
            );
            differenced_jacobians = newton.jacobian_counts().1;
            r
        }
        other => {
            let method = match other {
                Integrator::Dop853 { rtol, atol } => Method::Dop853 { rtol, atol },
                Integrator::Dopri5 { rtol, atol } => Method::Dopri5 { rtol, atol },
                Integrator::Rk4 { step } => Method::Rk4 { step },
                Integrator::Sdirk4 { .. } | Integrator::Auto { .. } | Integrator::GeneralizedAlpha { .. } => {
                    unreachable!("handled above")
                }
            };
            integrate(dynamics, method, limits, t0, t1, y0, on_step)
        }
    };
    let stats = result.map_err(|e| stopped(dynamics, settings, &limits, e))?;
    Ok((stats, differenced_jacobians))
}

/// The report of a run that has reached its end.
pub(super) fn report(
    dynamics: &Dynamics<'_>,
    settings: &RunSettings,
    state: &RunState,
    stats: &Stats,
    wall_seconds: f64,
    differenced_jacobians: usize,
) -> RunReport {
    let model = dynamics.model();
    RunReport {
        simulated: state.t_reached.min(settings.duration),
        wall_seconds,
        steps_accepted: stats.accepted,
        steps_rejected: stats.rejected,
        rhs_evaluations: dynamics.evaluations(),
        rows: state.rows,
        drift: Drift { locks: dynamics.restraint_locks().iter().filter(|r| !**r).count(), ..state.drift },
        released_at: state.released_at,
        energy_conserving: model.hinges.iter().all(|h| h.law.conserves_energy())
            && model.contact.as_ref().is_none_or(|c| c.law.restitution == 1.0 && c.law.friction == 0.0),
        contact: model.contact.as_ref().map(|_| dynamics.contact_record()),
        contact_episodes: dynamics.contact_episodes(),
        contact_dissipated: state.last.as_ref().map_or(0.0, |o| o.contact_dissipated),
        loads: state.last.as_ref().and_then(|o| o.loads),
        actuators: dynamics.actuator_records(),
        hinge_dissipated: state.last.as_ref().map(|o| o.hinge_dissipated.clone()).unwrap_or_default(),
        constrained_evaluations: dynamics.constrained_evaluations(),
        lock_engagements: state.lock_engagements.clone(),
        events: state.events.clone(),
        branch_events: state.branch_events,
        stiff_from: stats.stiff_from,
        methods: state.spans.clone(),
        deployed_90: state.deployed_90,
        deployed_start: state.deployed_range.0,
        deployed_max: state.deployed_range.1,
        newton_iterations: stats.newton_iterations,
        newton_failures: stats.newton_failures,
        jacobians: stats.jacobians,
        refactorizations: stats.refactorizations,
        differenced_jacobians,
        position_accuracy: None,
    }
}

//! A run advanced piece by piece, for a controller outside foldsim (a user's flight software,
//! from Python): `advance(dt)` integrates exactly to `t + dt` with the run's adaptive
//! integrator and every handler of a whole run (output rows, law events, locks, breaks,
//! momentum restoration); commands set between pieces act from there on, constant until
//! changed, like the scenario's own loads (docs/gnc.md).
//!
//! Nothing is lost between pieces: the state, the laws' memory, the angle references, the
//! contact memory, the rows' bookkeeping and the step size the integrator had reached (the
//! next piece starts with it). Each piece is an integration of its own, so its first stage
//! is evaluated afresh (one right-hand side) and, for SDIRK4, its Newton matrix is set up
//! again: a piece costs about one step more than the steps it contains.

use super::report::{RunReport, SimError};
use super::run::{integrate_span, prepare, report};
use super::settings::RunSettings;
use super::stream::{RunState, StreamOut};
use crate::dynamics::Dynamics;
use crate::integrate::Stats;
use crate::kinematics::InitialConditions;
use crate::loads::LoadFrame;
use crate::math::Vec3;
use crate::model::Model;
use crate::observe::Observation;

/// A run advanced piece by piece.
pub struct Stepper<'m> {
    dynamics: Dynamics<'m>,
    settings: RunSettings,
    state: RunState,
    /// Time reached, s.
    t: f64,
    /// The state reached.
    y: Vec<f64>,
    /// The step the integrator proposed last, s.
    next_step: Option<f64>,
    stats: Stats,
    wall_seconds: f64,
    differenced_jacobians: usize,
    /// Output rows so far (at the scenario's output times).
    rows: Vec<Observation>,
}

impl<'m> Stepper<'m> {
    /// Starts a run of `model` from `ic` at t = 0. The run's horizon is `settings.duration`;
    /// rows come at its output times. Commands for bodies need a model made
    /// [`Model::commandable`] before it is built into a run.
    pub fn start(model: &'m Model, ic: &InitialConditions, settings: &RunSettings) -> Result<Self, SimError> {
        if let Some(p) = settings.position_tolerance {
            return Err(SimError::Physics(format!(
                "run.position_tolerance = {p:e} m holds a whole run to it by running it again tighter; a stepped run cannot be: set run.rtol and run.atol instead"
            )));
        }
        let (dynamics, y, state) = prepare(model, ic, settings)?;
        Ok(Self {
            dynamics,
            settings: *settings,
            state,
            t: 0.0,
            y,
            next_step: None,
            stats: Stats::default(),
            wall_seconds: 0.0,
            differenced_jacobians: 0,
            rows: Vec::new(),
        })
    }

    /// The time reached, s.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The model.
    pub fn model(&self) -> &'m Model {
        self.dynamics.model()
    }

    /// The equations of motion, with the run's memory (laws, locks, contact, actuators).
    pub fn dynamics(&self) -> &Dynamics<'m> {
        &self.dynamics
    }

    /// The state vector reached (crate::state).
    pub fn state(&self) -> &[f64] {
        &self.y
    }

    /// Integrates to exactly `t + dt` (s). Fails for `dt ≤ 0`, past the run's duration, or
    /// as a whole run fails (the state stays where the failure left it).
    pub fn advance(&mut self, dt: f64) -> Result<(), SimError> {
        let t1 = self.t + dt;
        let end = self.settings.duration;
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SimError::Physics(format!("advance(dt): dt must be a finite number > 0 s, got {dt}")));
        }
        if t1 > end * (1.0 + 1e-12) {
            return Err(SimError::Physics(format!(
                "advance({dt}) from t = {} s passes run.duration = {end} s, the run's horizon: give the scenario a longer run.duration",
                self.t
            )));
        }
        let t1 = t1.min(end);
        let rows = &mut self.rows;
        let mut sink = |o: &Observation| -> Result<(), String> {
            rows.push(o.clone());
            Ok(())
        };
        let mut out = StreamOut { dynamics: &self.dynamics, sink: &mut sink, progress: None, s: &mut self.state };
        let mut y = self.y.clone();
        let start = std::time::Instant::now();
        let result = integrate_span(&mut out, &self.settings, self.t, t1, &self.y, self.next_step, &mut y);
        self.wall_seconds += start.elapsed().as_secs_f64();
        let (stats, differenced) = result?;
        self.stats.absorb(&stats);
        self.differenced_jacobians += differenced;
        if stats.next_step > 0.0 {
            self.next_step = Some(stats.next_step);
        }
        self.t = t1;
        self.y = y;
        Ok(())
    }

    /// Every output quantity at the time reached (an output row at `t`, whether or not `t`
    /// is an output time), the hinge loads with their locked directions' reactions.
    pub fn current(&mut self) -> Observation {
        let (contact, touched) = match self.dynamics.row_contact(&self.y) {
            Some((summary, touched)) => (Some(summary), touched),
            None => (None, Vec::new()),
        };
        let mut o = self.state.observer.observe(
            self.dynamics.model(),
            self.t,
            &self.y,
            &self.dynamics.theta_refs(),
            &self.dynamics.memories(),
            contact,
        );
        o.touched = touched;
        o.actuators = self.dynamics.actuator_reading(self.t, &self.y);
        // The hinge-load quantities are whole, as a run's rows that write them: the locked
        // directions' reactions join the laws' (one more evaluation, with locks only).
        if self.dynamics.has_locks() {
            for r in self.dynamics.lock_reactions(&self.y) {
                o.hinge_force_in_a0[r.hinge] += r.force_in_a0;
                o.hinge_torque_in_a[r.hinge] += r.torque_in_a;
            }
        }
        o
    }

    /// Makes and keeps no output rows from now on (a host that reads [`Stepper::current`]
    /// after each piece: an FMU, the C library), so a long stepped run's memory does not
    /// grow and no piece pays for rows nobody reads. The report's summaries that rows feed
    /// (the contact summary) then cover the rows made before.
    pub fn discard_rows(&mut self) {
        self.rows = Vec::new();
        // No rows are made at all from now on (each would cost an observation: 1.8 % of the
        // instructions of the three-panel case's stepping at 10 ms pieces, valgrind).
        self.state.output_times.done = true;
    }

    /// The output rows so far.
    pub fn rows(&self) -> &[Observation] {
        &self.rows
    }

    /// The run's report so far.
    pub fn report(&self) -> RunReport {
        report(&self.dynamics, &self.settings, &self.state, &self.stats, self.wall_seconds, self.differenced_jacobians)
    }

    /// Sets the torque on `body` (index) from now on, N·m in `frame`, replacing the one set
    /// before (crate::dynamics::Dynamics::command_torque).
    pub fn set_torque(&mut self, body: usize, torque: Vec3, frame: LoadFrame) -> Result<(), String> {
        finite("set_torque: the torque, N·m", torque.as_slice())?;
        self.dynamics.command_torque(body, torque, frame)
    }

    /// Sets the force on `body` (index) from now on, N in `frame`, at `point_in_body` (m from
    /// its centre of mass, body frame), replacing the one set before.
    pub fn set_force(&mut self, body: usize, force: Vec3, point_in_body: Vec3, frame: LoadFrame) -> Result<(), String> {
        finite("set_force: the force, N", force.as_slice())?;
        finite("set_force: the point, m", point_in_body.as_slice())?;
        self.dynamics.command_force(body, force, point_in_body, frame)
    }

    /// Sets motor `motor`'s (index) effort from now on (N or N·m); `None` gives it back to
    /// its drive.
    pub fn set_motor(&mut self, motor: usize, effort: Option<f64>) -> Result<(), String> {
        if let Some(e) = effort {
            finite("set_motor: the effort, N or N·m", &[e])?;
        }
        self.dynamics.command_motor(motor, effort)
    }

    /// Sets the control's actuator efforts from now on (N·m, one per wheel or torque
    /// source); `None` gives them back to the control law.
    pub fn set_actuators(&mut self, efforts: Option<Vec<f64>>) -> Result<(), String> {
        if let Some(u) = &efforts {
            finite("set_wheel_torque: the torques, N·m", u)?;
        }
        self.dynamics.command_actuators(efforts)
    }
}

/// A command refused at the call when any of its numbers is not finite (the next step would
/// otherwise fail and blame the hinges).
fn finite(what: &str, values: &[f64]) -> Result<(), String> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(format!("{what}: every number must be finite, got {v}")),
        None => Ok(()),
    }
}

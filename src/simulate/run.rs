//! A run: the integrator, output rows at the output times from its dense output, located
//! law events, lock engagement, momentum restoration, and the conservation figures.

use super::report::{Drift, RunReport, SimError};
use super::settings::{Integrator, MAX_OUTPUT_ROWS, MIN_STEP_BUDGET, RunSettings};
use crate::dynamics::newton::GraphNewton;
use crate::dynamics::{Dynamics, LawEvent};
use crate::integrate::{Control, Limits, Method, OdeError, Step, integrate, integrate_sdirk4};
use crate::kinematics::{InitialConditions, initial_state};
use crate::law::EventKind;
use crate::model::Model;
use crate::observe::{Observation, Observer};
use crate::state::BODY_STATE_LEN;
use std::ops::ControlFlow;
use std::time::Instant;

/// Receives output rows in time order.
pub trait Sink {
    /// Takes one row.
    fn record(&mut self, observation: &Observation) -> Result<(), String>;
}

impl<F: FnMut(&Observation) -> Result<(), String>> Sink for F {
    fn record(&mut self, observation: &Observation) -> Result<(), String> {
        self(observation)
    }
}

struct StreamOut<'d, 'm, 's, 'p> {
    dynamics: &'d Dynamics<'m>,
    /// Σ m_i, kg.
    total_mass: f64,
    observer: Observer,
    sink: &'s mut dyn Sink,
    progress: Option<&'p mut dyn FnMut(f64) -> ControlFlow<()>>,
    output_times: OutputTimes,
    first: Option<Observation>,
    last: Option<Observation>,
    drift: Drift,
    rows: usize,
    t_reached: f64,
    buffer: Vec<f64>,
    /// Event function values at the start of the current step.
    g_prev: Vec<f64>,
    g_end: Vec<f64>,
    /// Per event function, how much it changed over the last accepted step: a function
    /// nearer zero than that at both ends of a step may have dipped below it inside.
    g_change: Vec<f64>,
    events: Vec<LawEvent>,
    branch_events: usize,
    lock_engagements: Vec<(crate::dynamics::locks::Lock, f64)>,
    /// Time of the last event and how many events happened at exactly that time.
    same_instant: (f64, usize),
    /// An event located inside the last step, which the integrator is retaking to end there.
    pending: Option<(usize, f64)>,
    /// Initial momenta, restored after every step (the implicit path) or after every drift
    /// projection of locked directions (which moves positions at fixed velocities, and so
    /// changes the angular momentum by up to the drift times the momenta).
    momenta: Option<(crate::math::Vec3, crate::math::Vec3)>,
    /// Whether the momenta are restored after every step, output rows included (the implicit
    /// path), rather than only after projections.
    restore_every_step: bool,
    /// When the deployed fraction first reached 0.9 (from below), s.
    deployed_90: Option<f64>,
    /// The deployed fraction at the first row, and the largest of any row (NaN without panels).
    deployed_range: (f64, f64),
    /// When the restraint is to let go, s, until it has.
    release_at: Option<f64>,
    /// Times at which an external load switches or its table bends, s, ascending, those not
    /// yet reached: a step ends at each (crate::loads::Load::breaks).
    load_breaks: std::collections::VecDeque<f64>,
    /// Whether rows carry the locks' reactions in the hinge loads (`RunSettings::hinge_loads`).
    hinge_loads: bool,
    /// When it let go, s.
    released_at: Option<f64>,
}

/// Output times `k · step` below `end`, then `end`.
#[derive(Clone, Copy, Debug)]
struct OutputTimes {
    step: f64,
    end: f64,
    next: u64,
    done: bool,
}

impl OutputTimes {
    fn peek(&self) -> Option<f64> {
        if self.done {
            return None;
        }
        let t = self.next as f64 * self.step;
        Some(if t < self.end - 1e-9 * self.step { t } else { self.end })
    }
    fn advance(&mut self) {
        if let Some(t) = self.peek() {
            if t == self.end {
                self.done = true;
            }
            self.next += 1;
        }
    }
}

impl StreamOut<'_, '_, '_, '_> {
    fn emit(&mut self, t: f64, y: &[f64]) -> Result<(), SimError> {
        let (contact, touched) = match self.dynamics.row_contact(y) {
            Some((summary, touched)) => (Some(summary), touched),
            None => (None, Vec::new()),
        };
        let mut o = self.observer.observe(
            self.dynamics.model(),
            t,
            y,
            &self.dynamics.theta_refs(),
            &self.dynamics.memories(),
            contact,
        );
        o.touched = touched;
        o.actuators = self.dynamics.actuator_reading(t, y);
        // Locked directions carry loads too: their reactions join the law's in the wrench
        // columns (dynamics/reactions.rs), when those are asked for.
        if self.hinge_loads {
            for r in self.dynamics.lock_reactions(y) {
                o.hinge_force_in_a0[r.hinge] += r.force_in_a0;
                o.hinge_torque_in_a[r.hinge] += r.torque_in_a;
            }
        }
        if let Some(first) = &self.first {
            let d = &mut self.drift;
            // Less what the external loads gave (crate::loads), when there are any.
            let given = o.loads.unwrap_or_default();
            d.momentum = d.momentum.max((o.momentum_in_n - first.momentum_in_n - given.impulse_in_n).norm());
            d.angular_momentum = d
                .angular_momentum
                .max((o.angular_momentum_in_n - first.angular_momentum_in_n - given.angular_impulse_in_n).norm());
            // The barycenter moves uniformly with the initial momentum, Rc(0) + P(0) t / M,
            // and by the loads' impulse integrated once more over M.
            let uniform = first.barycenter_in_n
                + (first.momentum_in_n * (o.t - first.t) + given.impulse_moment_in_n) / self.total_mass;
            d.barycenter = d.barycenter.max((o.barycenter_in_n - uniform).norm());
            d.energy = d.energy.max((o.energy() - first.energy()).abs());
            d.energy_final_change = o.energy() - first.energy();
            d.dissipated = o.dissipated();
            let balance = o.energy() + o.dissipated() - o.work() - first.energy() - first.dissipated() + first.work();
            d.energy_balance = d.energy_balance.max(balance.abs());
        } else {
            self.drift.energy_initial = o.energy();
            self.first = Some(o.clone());
        }
        if self.last.is_none() {
            self.deployed_range = (o.deployed_fraction, o.deployed_fraction);
        }
        self.deployed_range.1 = self.deployed_range.1.max(o.deployed_fraction);
        // The first time the structure is 90 % deployed, between the rows that cross it.
        if self.deployed_90.is_none()
            && let Some(last) = &self.last
            && last.deployed_fraction < 0.9
            && o.deployed_fraction >= 0.9
        {
            let s = (0.9 - last.deployed_fraction) / (o.deployed_fraction - last.deployed_fraction);
            self.deployed_90 = Some(last.t + s * (o.t - last.t));
        }
        let restraint = self.dynamics.restraint_locks();
        for lock in self.dynamics.locks().iter().zip(restraint.iter()).filter(|(_, r)| !**r).map(|(l, _)| l) {
            let d = &mut self.drift;
            if lock.direction < 3 {
                let q = o.hinge_delta_in_a0[lock.hinge][lock.direction];
                d.locked_translation = d.locked_translation.max((q - lock.target).abs());
            } else {
                let q = o.hinge_theta[lock.hinge].as_vector()[crate::dynamics::locks::euler_index(lock.direction)];
                d.locked_rotation = d.locked_rotation.max((q - lock.target).abs());
            }
        }
        self.drift.momentum_scale = self.drift.momentum_scale.max(o.momentum_scale);
        self.drift.angular_momentum_scale = self.drift.angular_momentum_scale.max(o.angular_momentum_scale);
        self.sink.record(&o).map_err(SimError::Output)?;
        self.rows += 1;
        self.last = Some(o);
        Ok(())
    }

    /// Emits every output row up to `t_end` (inclusive) from the step's dense output.
    fn emit_until(&mut self, step: &Step<'_>, t_end: f64, y_end: &[f64]) -> Result<(), SimError> {
        let tol = 1e-12 * t_end.abs().max(1.0);
        let corrected = self.restore_every_step || self.dynamics.has_locks();
        while let Some(t_out) = self.output_times.peek() {
            if t_out > t_end + tol {
                break;
            }
            if (t_out - t_end).abs() <= tol && !corrected {
                self.emit(t_out, y_end)?;
            } else {
                // Rows get the correction the integrator restarts from (made after the rows
                // are out), and interpolated rows the same: the implicit path's rigid-body
                // momentum correction, and the projection onto the locked directions (the
                // dense output drifts off them by up to the local error, 1e-8 m at rtol
                // 1e-8, where the projected row holds them to 1e-11).
                let mut y = std::mem::take(&mut self.buffer);
                if (t_out - t_end).abs() <= tol {
                    y.clear();
                    y.extend_from_slice(y_end);
                } else {
                    y.resize(step.y.len(), 0.0);
                    step.interpolate(t_out, &mut y);
                }
                if corrected {
                    self.correct(&mut y);
                }
                let r = self.emit(t_out, &y);
                self.buffer = y;
                r?;
            }
            self.output_times.advance();
        }
        Ok(())
    }

    /// The earliest zero crossing of a law event function inside the step, if any:
    /// `(index, t*)` with t* just past the crossing (function already negative).
    ///
    /// A function negative at the step's end has crossed. One positive at both ends may
    /// still have dipped below zero and back inside the step (a tape spring's brief slide in
    /// a vibration, missed at one tolerance and found at the next, changes the rest of the
    /// run): where it is nearer zero at either end than it changes over a step, it is also
    /// sampled at three points inside the step.
    fn locate_event(&mut self, step: &Step<'_>) -> Option<(usize, f64)> {
        if self.g_prev.is_empty() || step.t == step.t_prev {
            return None;
        }
        self.dynamics.event_values(step.y, &mut self.g_end);
        let mut best: Option<(usize, f64)> = None;
        let mut y = Vec::new();
        let (t0, h) = (step.t_prev, step.t - step.t_prev);
        for k in 0..self.g_prev.len() {
            let (g0, g1) = (self.g_prev[k], self.g_end[k]);
            if g0.is_nan() || g0 < 0.0 {
                continue;
            }
            let near = g1 >= 0.0 && g0.min(g1) < self.g_change[k].max((g1 - g0).abs());
            if !(g1 < 0.0 || near) {
                continue;
            }
            y.resize(step.y.len(), 0.0);
            // The event function at time t of the dense output, from the hinge's two bodies
            // only (the rest of y is not read).
            let (parent, child) = self.dynamics.event_bodies(k);
            let body = |b: usize| BODY_STATE_LEN * b..BODY_STATE_LEN * (b + 1);
            let dynamics = self.dynamics;
            let mut g_at = |t: f64| {
                step.interpolate_range(t, body(parent), &mut y);
                step.interpolate_range(t, body(child), &mut y);
                dynamics.event_value(k, &y)
            };
            // A bracket [a, b] with g(a) ≥ 0 > g(b).
            let (mut a, mut ga) = (t0, g0);
            let (mut b, mut gb) = (step.t, g1);
            if near {
                let Some((ta, ga_, tb, gb_)) = [0.25, 0.5, 0.75].iter().find_map(|&f| {
                    let t = t0 + f * h;
                    let g = g_at(t);
                    if g < 0.0 {
                        Some((a, ga, t, g))
                    } else {
                        (a, ga) = (t, g);
                        None
                    }
                }) else {
                    continue;
                };
                (a, ga, b, gb) = (ta, ga_, tb, gb_);
            }
            // Illinois regula falsi on the bracket.
            let tol = 1e-13 * b.abs().max(1.0);
            let mut side = 0;
            for _ in 0..100 {
                if b - a <= tol {
                    break;
                }
                let mut c = b - gb * (b - a) / (gb - ga);
                if !(c > a && c < b) {
                    c = 0.5 * (a + b);
                }
                let gc = g_at(c);
                if gc < 0.0 {
                    b = c;
                    gb = gc;
                    if side == -1 {
                        ga *= 0.5;
                    }
                    side = -1;
                } else {
                    a = c;
                    ga = gc;
                    if side == 1 {
                        gb *= 0.5;
                    }
                    side = 1;
                }
            }
            if best.is_none_or(|(_, t)| b < t) {
                best = Some((k, b));
            }
        }
        best
    }

    /// Applies law event `k` at `(t, y)` and resets the event functions' reference values.
    /// Values a round-off below zero in the new memory count as zero (the state sits on the
    /// switching surface); a crossing soon after is then found at the next step's start. Many
    /// events at one instant mean the switching chatters, which is reported.
    fn apply_event(&mut self, k: usize, t: f64, y: &[f64]) -> Result<(), SimError> {
        let event = self.dynamics.apply_event(k, t, y);
        self.same_instant = if self.same_instant.0 == t { (t, self.same_instant.1 + 1) } else { (t, 1) };
        if self.same_instant.1 >= 100 {
            let h = &self.dynamics.model().hinges[event.hinge];
            return Err(SimError::Physics(format!(
                "hinge '{}' switches without end at t = {t:.9} s ({}): its events chatter at one instant",
                h.name, event.description
            )));
        }
        if event.kind == EventKind::Branch {
            self.branch_events += 1;
        } else {
            self.events.push(event);
        }
        self.dynamics.event_values(y, &mut self.g_prev);
        for g in &mut self.g_prev {
            *g = g.max(0.0);
        }
        Ok(())
    }

    /// Handles an accepted step: outputs, law events (which restart the integration at the
    /// event), angle references and checks.
    ///
    /// An event inside a step makes the integrator retake the step to end at the event (so
    /// no step straddles the change of the right-hand side); at the end of that step the
    /// law's memory changes and the integration restarts there.
    fn on_step(&mut self, step: &Step<'_>) -> Result<Control, SimError> {
        let tiny = 1e-12 * step.t.abs().max(1.0);
        let engaged = if step.t > step.t_prev { self.dynamics.engage_drifted_locks(step.y) } else { Vec::new() };
        if !engaged.is_empty() {
            // Locks that drifted over the step carry load from now on: they are engaged and
            // the step is retaken with them (an event it straddled is found again).
            let locks = self.dynamics.locks();
            self.lock_engagements.extend(engaged.into_iter().map(|k| (locks[k], step.t_prev)));
            self.pending = None;
            let mut y = vec![0.0; step.y.len()];
            step.interpolate(step.t_prev, &mut y);
            return Ok(Control::Restart { t: step.t_prev, y });
        }
        let pending = self.pending.take();
        let event = match pending {
            // The retaken step ends at the located root (to round-off): the event happens here.
            Some((k, t)) if (step.t - t).abs() <= tiny => Some(k),
            _ => match self.locate_event(step) {
                // At the very start of the step (a round-off past the previous step's end):
                // apply it there rather than take a step too short for the integrator.
                Some((k, t)) if t - step.t_prev <= 1e-10 * step.t.abs().max(1.0) => {
                    let mut y = vec![0.0; step.y.len()];
                    step.interpolate(step.t_prev, &mut y);
                    self.apply_event(k, step.t_prev, &y)?;
                    return Ok(Control::Restart { t: step.t_prev, y });
                }
                Some((k, t)) if t < step.t - tiny => {
                    self.pending = Some((k, t));
                    return Ok(Control::Truncate { t });
                }
                Some((k, _)) => Some(k),
                None => None,
            },
        };
        if let Some(tr) = self.release_at
            && step.t > tr + tiny
            && step.t_prev < tr - tiny
        {
            // The step passes the release: take it again to end there.
            self.pending = None;
            return Ok(Control::Truncate { t: tr });
        }
        while self.load_breaks.front().is_some_and(|&b| b <= step.t_prev + tiny) {
            self.load_breaks.pop_front();
        }
        if let Some(&b) = self.load_breaks.front()
            && step.t > b + tiny
        {
            // The step passes a load's switch or a bend of its table: take it again to end
            // there, so that no step straddles the kink.
            self.pending = None;
            return Ok(Control::Truncate { t: b });
        }
        if let Some(k) = event {
            self.emit_until(step, step.t, step.y)?;
            self.dynamics.accept(step.t, step.y).map_err(SimError::Physics)?;
            self.apply_event(k, step.t, step.y)?;
            self.t_reached = step.t;
            self.report_progress(step.t)?;
            let mut y = step.y.to_vec();
            self.correct(&mut y);
            return Ok(Control::Restart { t: step.t, y });
        }
        self.emit_until(step, step.t, step.y)?;
        self.dynamics.accept(step.t, step.y).map_err(SimError::Physics)?;
        for ((c, g0), g1) in self.g_change.iter_mut().zip(&self.g_prev).zip(&self.g_end) {
            *c = (g1 - g0).abs();
        }
        std::mem::swap(&mut self.g_prev, &mut self.g_end);
        if step.t == step.t_prev {
            self.dynamics.event_values(step.y, &mut self.g_prev);
        }
        self.t_reached = step.t;
        self.report_progress(step.t)?;
        if self.release_at.is_some_and(|tr| (step.t - tr).abs() <= tiny) {
            // The restraint lets go at the end of this step (which was cut to end there).
            self.release_at = None;
            self.released_at = Some(step.t);
            self.dynamics.release_restraint();
            return Ok(Control::Restart { t: step.t, y: step.y.to_vec() });
        }
        if self.load_breaks.front().is_some_and(|&b| (step.t - b).abs() <= tiny) {
            // A load switches here: the integrator starts afresh from this state.
            self.load_breaks.pop_front();
            return Ok(Control::Restart { t: step.t, y: step.y.to_vec() });
        }
        if step.t > step.t_prev && (self.dynamics.has_locks() || self.momenta.is_some()) {
            let mut y = step.y.to_vec();
            if self.correct(&mut y) {
                return Ok(Control::Restart { t: step.t, y });
            }
        }
        Ok(Control::Continue)
    }

    /// Tells the progress callback the time reached; stops the run if it asks to.
    fn report_progress(&mut self, t: f64) -> Result<(), SimError> {
        match self.progress.as_mut().map(|p| p(t)) {
            Some(ControlFlow::Break(())) => Err(SimError::Interrupted { t }),
            _ => Ok(()),
        }
    }

    /// Holds locked directions on their constraints once they drift, and the momenta where
    /// that or the integrator moved them. Returns whether `y` changed.
    fn correct(&self, y: &mut [f64]) -> bool {
        let projected = self.dynamics.project(y, false);
        let mut changed = projected;
        if let Some((p0, h0)) = &self.momenta
            && (projected || self.restore_every_step)
        {
            changed |= self.dynamics.restore_momentum(y, p0, h0) > 1e-15;
        }
        changed
    }
}

/// Runs a simulation from `ic`, streaming every output row to `sink`. `progress` is called
/// with the simulated time after each accepted step; returning `ControlFlow::Break` stops the
/// run with [`SimError::Interrupted`] (how a Ctrl-C reaches it).
pub fn simulate(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    sink: &mut dyn Sink,
    progress: Option<&mut dyn FnMut(f64) -> ControlFlow<()>>,
) -> Result<RunReport, SimError> {
    if !(settings.duration > 0.0 && settings.output_step > 0.0)
        || settings.duration / settings.output_step > MAX_OUTPUT_ROWS
    {
        return Err(SimError::Physics(format!(
            "run.duration = {} s and run.output_step = {} s: both must be > 0, with at most {MAX_OUTPUT_ROWS:e} rows",
            settings.duration, settings.output_step
        )));
    }
    let (mut y0, theta_refs) = initial_state(model, ic);
    let dynamics = Dynamics::new(model, theta_refs);
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
    let mut breaks: Vec<f64> = model
        .loads
        .iter()
        .flat_map(|l| l.breaks())
        .chain(model.motors.iter().flat_map(|m| m.breaks()))
        .chain(model.control.iter().flat_map(|c| c.sample_times(settings.duration)))
        .filter(|&t| t > 0.0)
        .collect();
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    dynamics.set_breaks(breaks.clone());
    let implicit = matches!(settings.integrator, Integrator::Sdirk4 { .. });
    let mut out = StreamOut {
        dynamics: &dynamics,
        total_mass: model.total_mass(),
        observer: Observer::new(model, ic.hub_attitude, &dynamics.momentum_about_barycenter(&y0)),
        sink,
        progress,
        output_times: OutputTimes { step: settings.output_step, end: settings.duration, next: 0, done: false },
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
        pending: None,
        // The implicit method conserves momentum only to its tolerance, and the projection
        // of locked directions moves positions; a rigid-body velocity correction holds the
        // momenta exactly without touching the internal motion (or the locked rates).
        // (Not with external loads: they change the momenta.)
        momenta: (!model.has_external() && (implicit || dynamics.has_locks())).then(|| dynamics.momenta(&y0)),
        restore_every_step: implicit,
        deployed_90: None,
        deployed_range: (f64::NAN, f64::NAN),
        release_at: settings.release_at,
        load_breaks: breaks.into(),
        hinge_loads: settings.hinge_loads,
        released_at: None,
    };
    let limits = settings.limits(model);
    let start = Instant::now();
    let mut differenced_jacobians = 0;
    let result = match settings.integrator {
        Integrator::Sdirk4 { rtol, atol } => {
            let mut newton = GraphNewton::new_exact(&dynamics, model, &dynamics);
            let r = integrate_sdirk4(&dynamics, &mut newton, rtol, atol, limits, 0.0, settings.duration, &y0, |step| {
                out.on_step(step)
            });
            differenced_jacobians = newton.jacobian_counts().1;
            r
        }
        other => {
            let method = match other {
                Integrator::Dop853 { rtol, atol } => Method::Dop853 { rtol, atol },
                Integrator::Dopri5 { rtol, atol } => Method::Dopri5 { rtol, atol },
                Integrator::Rk4 { step } => Method::Rk4 { step },
                Integrator::Sdirk4 { .. } => unreachable!("handled above"),
            };
            integrate(&dynamics, method, limits, 0.0, settings.duration, &y0, |step| out.on_step(step))
        }
    };
    let wall_seconds = start.elapsed().as_secs_f64();
    let stats = result.map_err(|e| stopped(&dynamics, settings, &limits, e))?;
    if out.output_times.peek().is_some() {
        return Err(SimError::Integrator {
            t: out.t_reached,
            message: "the integrator stopped before the end of the run".into(),
        });
    }
    Ok(RunReport {
        simulated: settings.duration,
        wall_seconds,
        steps_accepted: stats.accepted,
        steps_rejected: stats.rejected,
        rhs_evaluations: dynamics.evaluations(),
        rows: out.rows,
        drift: Drift { locks: dynamics.restraint_locks().iter().filter(|r| !**r).count(), ..out.drift },
        released_at: out.released_at,
        energy_conserving: model.hinges.iter().all(|h| h.law.conserves_energy())
            && model.contact.as_ref().is_none_or(|c| c.law.restitution == 1.0 && c.law.friction == 0.0),
        contact: model.contact.as_ref().map(|_| dynamics.contact_record()),
        contact_dissipated: out.last.as_ref().map_or(0.0, |o| o.contact_dissipated),
        loads: out.last.as_ref().and_then(|o| o.loads),
        actuators: dynamics.actuator_records(),
        hinge_dissipated: out.last.map(|o| o.hinge_dissipated).unwrap_or_default(),
        constrained_evaluations: dynamics.constrained_evaluations(),
        lock_engagements: out.lock_engagements,
        events: out.events,
        branch_events: out.branch_events,
        stiff_from: stats.stiff_from,
        deployed_90: out.deployed_90,
        deployed_start: out.deployed_range.0,
        deployed_max: out.deployed_range.1,
        newton_iterations: stats.newton_iterations,
        newton_failures: stats.newton_failures,
        jacobians: stats.jacobians,
        refactorizations: stats.refactorizations,
        differenced_jacobians,
    })
}

/// Why the integrator stopped, in the user's terms: what it could not do, the hinge or body
/// responsible (the fastest hinge direction, or the body whose state or acceleration is not
/// finite), and what to change.
fn stopped(dynamics: &Dynamics<'_>, settings: &RunSettings, limits: &Limits, e: OdeError<SimError>) -> SimError {
    let model = dynamics.model();
    let rate = model.fastest_hinge();
    let fastest = rate.map(|r| format!(" The fastest hinge is {}.", r.describe(model))).unwrap_or_default();
    let heading =
        |y: &[f64]| dynamics.fastest_body(y).map(|b| format!(" At the last accepted state {b}.")).unwrap_or_default();
    // Steps near the fastest hinge's period mean stiffness; steps far below it mean the
    // tolerances ask for more than f64 gives, or the motion is singular.
    let advice = |h: f64| {
        if rate.is_some_and(|r| h.abs() * r.rate > 1e-2) {
            " Make that hinge softer or its bodies heavier, or use integrator = \"sdirk4\", which steps over stiff vibrations."
        } else {
            " The steps are far shorter than any hinge's period: the tolerances (run.rtol, run.atol) may ask for more than f64 resolves (1e-13 and looser are usual), or the motion is near a singular configuration."
        }
    };
    match e {
        OdeError::Callback(e) => e,
        OdeError::NonFinite { t, y } => SimError::Integrator {
            t,
            message: match dynamics.non_finite_cause(&y) {
                Some(cause) => format!("the state became non-finite: {cause}"),
                None => "the state became non-finite".into(),
            },
        },
        OdeError::StepTooSmall { t, h, non_finite, y } => {
            let message = match (non_finite, dynamics.non_finite_cause(&y)) {
                (_, Some(cause)) => format!("the state became non-finite: {cause}"),
                (true, None) => format!(
                    "every step tried from here overflowed (non-finite values inside the step, down to steps of {h:.3e} s).{}{fastest}",
                    heading(&y)
                ),
                (false, None) => format!(
                    "the step size fell to {h:.3e} s, below the run's floor of {:.3e} s (1e-12 of its duration) or the round-off of t: the motion is faster than the run can follow.{fastest}{}{}",
                    limits.min_step,
                    heading(&y),
                    advice(h)
                ),
            };
            SimError::Integrator { t, message }
        }
        OdeError::SingularNewton { t, h } => SimError::Integrator {
            t,
            message: format!(
                "the implicit integrator's Newton matrix I − hγJ could not be factored at a step of {h:.3e} s (a singular pivot block): a structure whose locked directions are redundant (locks closing a loop of locked hinges) does this; otherwise it is a fault in foldsim, please report it with the scenario. integrator = \"dop853\" does not need the matrix"
            ),
        },
        OdeError::TooManySteps { t, h, steps, y } => {
            let budget = if settings.max_steps.is_some() {
                "run.max_steps".to_string()
            } else {
                format!(
                    "by default 10 × duration × the fastest hinge rate, at least {MIN_STEP_BUDGET:e}; set run.max_steps to change it"
                )
            };
            SimError::Integrator {
                t,
                message: format!(
                    "the run took {steps} steps, its budget ({budget}), with steps of {h:.3e} s at the end: at that pace it needs {:.1e} more.{fastest}{}{}",
                    (settings.duration - t) / h.abs().max(f64::MIN_POSITIVE),
                    heading(&y),
                    advice(h)
                ),
            }
        }
    }
}

//! A run's step handler: output rows at the output times from the integrator's dense output,
//! located law events, lock engagement, breaks of the right-hand side, momentum restoration,
//! and the conservation figures, with the state a run keeps between its steps.

use super::contact_entry::{illinois, locate_contact_change, locate_entry_speeds};
use super::pace::{Progress, ProgressFn};
use super::report::{Drift, SimError};
use crate::dynamics::{Dynamics, LawEvent};
use crate::integrate::{Control, Step};
use crate::law::EventKind;
use crate::observe::{Observation, Observer};
use crate::state::BODY_STATE_LEN;
use std::ops::ControlFlow;

/// The momentum drift (relative to the largest momentum scales seen, the run report's) past
/// which a step of a method that does not restore the momenta at every step (`auto`'s DOP853
/// spans) has them restored: a hundredth of the 1e-10 the thick flashers are held to, and far
/// above the round-off of the sums. The restoration restarts DOP853 (one right-hand side), so
/// it comes when the drift asks for it, not at every step; without it, a thick starshade run
/// whose `auto` handed back to DOP853 35 times ended with H 1.2e-10 of its scale off
/// (2026-12-01).
pub(super) const MOMENTUM_DRIFT: f64 = 1e-12;

/// When a run restores its initial momenta (`Dynamics::restore_momentum`); after every
/// projection of locked directions in any case, since that moves positions at fixed
/// velocities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Restore {
    /// After every step, output rows included: the implicit methods, which conserve the
    /// momenta only to their tolerance.
    EveryStep,
    /// Once they drift past [`MOMENTUM_DRIFT`] of their largest scales seen: `auto`'s DOP853
    /// spans, which hand over to and from the implicit method.
    OnDrift,
    /// Only after projections: a run under an explicit method alone, whose momenta measure
    /// its accuracy.
    AfterProjections,
}

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

/// What a run keeps between its steps (and a stepped run between its spans): the observer,
/// the output times, the drift figures, events, breaks.
pub(super) struct RunState {
    /// Σ m_i, kg.
    pub(super) total_mass: f64,
    pub(super) observer: Observer,
    pub(super) output_times: OutputTimes,
    pub(super) first: Option<Observation>,
    pub(super) last: Option<Observation>,
    pub(super) drift: Drift,
    pub(super) rows: usize,
    pub(super) t_reached: f64,
    pub(super) buffer: Vec<f64>,
    /// Event function values at the start of the current step.
    pub(super) g_prev: Vec<f64>,
    pub(super) g_end: Vec<f64>,
    /// Per event function, how much it changed over the last accepted step: a function
    /// nearer zero than that at both ends of a step may have dipped below it inside.
    pub(super) g_change: Vec<f64>,
    pub(super) events: Vec<LawEvent>,
    pub(super) branch_events: usize,
    pub(super) lock_engagements: Vec<(crate::dynamics::locks::Lock, f64)>,
    /// Time of the last event and how many events happened at exactly that time.
    pub(super) same_instant: (f64, usize),
    /// Whether the step being handled went across a table's point without its event (see
    /// `Tracked::on_step`): the event functions are then taken afresh at its end.
    pub(super) resync_events: bool,
    /// An event located inside the last step, which the integrator is retaking to end there.
    pub(super) pending: Option<(usize, f64)>,
    /// Initial momenta, restored after every step (the implicit path) or after every drift
    /// projection of locked directions (which moves positions at fixed velocities, and so
    /// changes the angular momentum by up to the drift times the momenta).
    pub(super) momenta: Option<(crate::math::Vec3, crate::math::Vec3)>,
    /// When the momenta are restored (besides after every projection of locked directions).
    pub(super) restore: Restore,
    /// The largest momentum scales seen at the steps (kg·m/s, kg·m²/s; see
    /// `Dynamics::momentum_drift`), which [`MOMENTUM_DRIFT`] is relative to.
    pub(super) momentum_scales: [f64; 2],
    /// When the deployed fraction first reached 0.9 (from below), s.
    pub(super) deployed_90: Option<f64>,
    /// The deployed fraction at the first row, and the largest of any row (NaN without panels).
    pub(super) deployed_range: (f64, f64),
    /// When the restraint is to let go, s, until it has.
    pub(super) release_at: Option<f64>,
    /// Times at which an external load switches or its table bends, s, ascending, those not
    /// yet reached: a step ends at each (crate::loads::Load::breaks).
    pub(super) load_breaks: crate::loads::breaks::Breaks,
    /// Whether steps end where contact points enter or leave contact
    /// ([`super::settings::Integrator::locates_contact_changes`]).
    pub(super) locate_contacts: bool,
    /// Whether rows carry the locks' reactions in the hinge loads (`RunSettings::hinge_loads`).
    pub(super) hinge_loads: bool,
    /// When it let go, s.
    pub(super) released_at: Option<f64>,
    /// The methods `integrator = "auto"` used, in order.
    pub(super) spans: Vec<super::report::MethodSpan>,
    /// The method taking the steps (under `auto`, the one in use).
    pub(super) method: &'static str,
    /// Accepted steps so far.
    pub(super) steps: usize,
    /// The run's step budget (`RunSettings::limits`), and the longest step of the current
    /// window of [`PACE_WINDOW`] steps, s: a run whose pace cannot finish within the budget
    /// stops early and says so.
    pub(super) step_budget: usize,
    pub(super) window_longest: f64,
    /// When the run started (for the projected wall time of a run stopped for its pace).
    pub(super) started: std::time::Instant,
}

/// Steps between checks of a run's pace against its step budget.
pub const PACE_WINDOW: usize = 10_000;

/// A run's step handler: the dynamics, where rows go, the progress callback, and the run's
/// state.
pub(super) struct StreamOut<'a, 'm, 'x, 'y> {
    pub(super) dynamics: &'a Dynamics<'m>,
    pub(super) sink: &'a mut (dyn Sink + 'x),
    pub(super) progress: Option<&'a mut ProgressFn<'y>>,
    pub(super) s: &'a mut RunState,
}

/// What the progress callback is told after `step` of a run in state `s`.
fn progress_at<'p, 'm>(s: &RunState, dynamics: &'p Dynamics<'m>, step: &Step<'p>) -> Progress<'p, 'm> {
    Progress {
        t: step.t,
        step: step.t - step.t_prev,
        method: s.method,
        dynamics,
        y: step.y,
        events: s.events.len() + s.lock_engagements.len(),
        steps: s.steps,
    }
}

/// Output times `k · step` below `end`, then `end`; or, with `list`, those times alone
/// (ascending, within the run: [`super::run::simulate_at`]).
#[derive(Clone, Debug)]
pub(super) struct OutputTimes {
    pub(super) step: f64,
    pub(super) end: f64,
    pub(super) next: u64,
    pub(super) done: bool,
    pub(super) list: Option<Vec<f64>>,
}

impl OutputTimes {
    pub(super) fn peek(&self) -> Option<f64> {
        if self.done {
            return None;
        }
        if let Some(list) = &self.list {
            return list.get(self.next as usize).copied();
        }
        let t = self.next as f64 * self.step;
        Some(if t < self.end - 1e-9 * self.step { t } else { self.end })
    }
    fn advance(&mut self) {
        if let Some(list) = &self.list {
            self.next += 1;
            self.done = self.next as usize >= list.len();
            return;
        }
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
        let mut o = self.s.observer.observe(
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
        if self.s.hinge_loads {
            for r in self.dynamics.lock_reactions(y) {
                o.hinge_force_in_a0[r.hinge] += r.force_in_a0;
                o.hinge_torque_in_a[r.hinge] += r.torque_in_a;
            }
        }
        if let Some(first) = &self.s.first {
            let d = &mut self.s.drift;
            // Less what the external loads gave (crate::loads), when there are any.
            let given = o.loads.unwrap_or_default();
            d.momentum = d.momentum.max((o.momentum_in_n - first.momentum_in_n - given.impulse_in_n).norm());
            d.angular_momentum = d
                .angular_momentum
                .max((o.angular_momentum_in_n - first.angular_momentum_in_n - given.angular_impulse_in_n).norm());
            // The barycenter moves uniformly with the initial momentum, Rc(0) + P(0) t / M,
            // and by the loads' impulse integrated once more over M.
            let uniform = first.barycenter_in_n
                + (first.momentum_in_n * (o.t - first.t) + given.impulse_moment_in_n) / self.s.total_mass;
            d.barycenter = d.barycenter.max((o.barycenter_in_n - uniform).norm());
            d.energy = d.energy.max((o.energy() - first.energy()).abs());
            d.energy_final_change = o.energy() - first.energy();
            d.dissipated = o.dissipated();
            let balance = o.energy() + o.dissipated() - o.work() - first.energy() - first.dissipated() + first.work();
            d.energy_balance = d.energy_balance.max(balance.abs());
        } else {
            self.s.drift.energy_initial = o.energy();
            self.s.first = Some(o.clone());
        }
        if self.s.last.is_none() {
            self.s.deployed_range = (o.deployed_fraction, o.deployed_fraction);
        }
        self.s.deployed_range.1 = self.s.deployed_range.1.max(o.deployed_fraction);
        // The first time the structure is 90 % deployed, between the rows that cross it.
        if self.s.deployed_90.is_none()
            && let Some(last) = &self.s.last
            && last.deployed_fraction < 0.9
            && o.deployed_fraction >= 0.9
        {
            let s = (0.9 - last.deployed_fraction) / (o.deployed_fraction - last.deployed_fraction);
            self.s.deployed_90 = Some(last.t + s * (o.t - last.t));
        }
        let restraint = self.dynamics.restraint_locks();
        for lock in self.dynamics.locks().iter().zip(restraint.iter()).filter(|(_, r)| !**r).map(|(l, _)| l) {
            let d = &mut self.s.drift;
            if lock.direction < 3 {
                let q = o.hinge_delta_in_a0[lock.hinge][lock.direction];
                d.locked_translation = d.locked_translation.max((q - lock.target).abs());
            } else {
                let q = o.hinge_theta[lock.hinge].as_vector()[crate::dynamics::locks::euler_index(lock.direction)];
                d.locked_rotation = d.locked_rotation.max((q - lock.target).abs());
            }
        }
        self.s.drift.momentum_scale = self.s.drift.momentum_scale.max(o.momentum_scale);
        self.s.drift.angular_momentum_scale = self.s.drift.angular_momentum_scale.max(o.angular_momentum_scale);
        self.sink.record(&o).map_err(SimError::Output)?;
        self.s.rows += 1;
        self.s.last = Some(o);
        Ok(())
    }

    /// Emits every output row up to `t_end` (inclusive) from the step's dense output.
    fn emit_until(&mut self, step: &Step<'_>, t_end: f64, y_end: &[f64]) -> Result<(), SimError> {
        let tol = 1e-12 * t_end.abs().max(1.0);
        let corrected = self.s.restore == Restore::EveryStep || self.dynamics.has_locks();
        while let Some(t_out) = self.s.output_times.peek() {
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
                let mut y = std::mem::take(&mut self.s.buffer);
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
                self.s.buffer = y;
                r?;
            }
            self.s.output_times.advance();
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
    /// sampled at three points inside the step. Event `skip` is not looked for.
    fn locate_event(&mut self, step: &Step<'_>, skip: Option<usize>) -> Option<(usize, f64)> {
        if self.s.g_prev.is_empty() || step.t == step.t_prev {
            return None;
        }
        self.dynamics.event_values(step.y, &mut self.s.g_end);
        let mut best: Option<(usize, f64)> = None;
        let mut y = Vec::new();
        let (t0, h) = (step.t_prev, step.t - step.t_prev);
        for k in 0..self.s.g_prev.len() {
            if skip == Some(k) {
                continue;
            }
            let (g0, g1) = (self.s.g_prev[k], self.s.g_end[k]);
            if g0.is_nan() || g0 < 0.0 {
                continue;
            }
            let near = g1 >= 0.0 && g0.min(g1) < self.s.g_change[k].max((g1 - g0).abs());
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
            let b = illinois(&mut g_at, |g| g < 0.0, (a, ga), (b, gb), 1e-13 * b.abs().max(1.0), 100);
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
        self.s.same_instant = if self.s.same_instant.0 == t { (t, self.s.same_instant.1 + 1) } else { (t, 1) };
        if self.s.same_instant.1 >= 100 {
            let h = &self.dynamics.model().hinges[event.hinge];
            return Err(SimError::Physics(format!(
                "hinge '{}' switches without end at t = {t:.9} s ({}): its events chatter at one instant",
                h.name, event.description
            )));
        }
        if event.kind == EventKind::Branch {
            self.s.branch_events += 1;
        } else {
            self.s.events.push(event);
        }
        self.dynamics.event_values(y, &mut self.s.g_prev);
        for g in &mut self.s.g_prev {
            *g = g.max(0.0);
        }
        Ok(())
    }

    /// Applies law event `k` at the start of `step` and restarts the integration there.
    fn apply_at_start(&mut self, k: usize, step: &Step<'_>) -> Result<Control, SimError> {
        let mut y = vec![0.0; step.y.len()];
        step.interpolate(step.t_prev, &mut y);
        self.apply_event(k, step.t_prev, &y)?;
        Ok(Control::Restart { t: step.t_prev, y })
    }

    /// Handles an accepted step: outputs, law events (which restart the integration at the
    /// event), angle references and checks.
    ///
    /// An event inside a step makes the integrator retake the step to end at the event (so
    /// no step straddles the change of the right-hand side); at the end of that step the
    /// law's memory changes and the integration restarts there.
    pub(super) fn on_step(&mut self, step: &Step<'_>) -> Result<Control, SimError> {
        let tiny = 1e-12 * step.t.abs().max(1.0);
        let engaged = if step.t > step.t_prev { self.dynamics.engage_drifted_locks(step.y) } else { Vec::new() };
        if !engaged.is_empty() {
            // Locks that drifted over the step carry load from now on: they are engaged and
            // the step is retaken with them (an event it straddled is found again).
            let locks = self.dynamics.locks();
            self.s.lock_engagements.extend(engaged.into_iter().map(|k| (locks[k], step.t_prev)));
            self.s.pending = None;
            let mut y = vec![0.0; step.y.len()];
            step.interpolate(step.t_prev, &mut y);
            return Ok(Control::Restart { t: step.t_prev, y });
        }
        let pending = self.s.pending.take();
        // Within round-off of the step's start (1e-10 relative), right after events at that
        // very instant.
        let at_start = |t: f64| t - step.t_prev <= 1e-10 * step.t.abs().max(1.0);
        let repeated = self.s.same_instant.0 == step.t_prev && self.s.same_instant.1 >= 2;
        let event = match pending {
            // The retaken step ends at the located root (to round-off): the event happens here.
            Some((k, t)) if (step.t - t).abs() <= tiny => Some(k),
            _ => {
                let mut found = self.locate_event(step, None);
                // A slip element's mode switched back at the step's start right after
                // switches at that very instant: the two modes' motions each cross the
                // other's switching surface at once (a latched tape spring's rate at zero to
                // the integration's error: the z-fold with reaction wheels under DOP853 at
                // rtol 4e-3 to 4e-5 chattered so). The force is continuous across the switch
                // (the slip force is zero, or the gap, at either side of it), so the step is
                // taken in the mode it started in and the switch made at its end, if its
                // event function is still below zero there; any other event in the step is
                // looked for without it and handled as usual (the switch, due still, is
                // found again after it).
                let mut deferred = None;
                if let Some((k, t)) = found
                    && at_start(t)
                    && repeated
                    && self.dynamics.slip_event(k)
                {
                    deferred = Some(k);
                    found = self.locate_event(step, Some(k));
                }
                match found {
                    // A table's point crossed at the step's start right after events at that
                    // very instant (the coordinate turns on the point, and its two crossings
                    // would alternate there without end): the step goes across it, and the
                    // piece is brought up to date at the accepted state
                    // (`HingeLaw::sync_memory`; the force is continuous across the point).
                    Some((k, t)) if at_start(t) && repeated && self.dynamics.bookkeeping_event(k) => {
                        self.s.resync_events = true;
                        None
                    }
                    // At the very start of the step (a round-off past the previous step's
                    // end): apply it there rather than take a step too short for the
                    // integrator.
                    Some((k, t)) if at_start(t) => return self.apply_at_start(k, step),
                    Some((k, t)) if t < step.t - tiny => {
                        self.s.pending = Some((k, t));
                        return Ok(Control::Truncate { t });
                    }
                    Some((k, _)) => Some(k),
                    None => deferred.filter(|&k| self.s.g_end[k] < 0.0),
                }
            }
        };
        if let Some(tr) = self.s.release_at
            && step.t > tr + tiny
            && step.t_prev < tr - tiny
        {
            // The step passes the release: take it again to end there.
            self.s.pending = None;
            return Ok(Control::Truncate { t: tr });
        }
        if event.is_none()
            && self.s.locate_contacts
            && let Some(t) = locate_contact_change(self.dynamics, step)
        {
            // A contact point enters or leaves inside the step: take it again to end there.
            self.s.pending = None;
            return Ok(Control::Truncate { t });
        }
        let next_break = self.s.load_breaks.next_after(step.t_prev + tiny);
        if let Some(b) = next_break
            && step.t > b + tiny
        {
            // The step passes a load's switch or a bend of its table: take it again to end
            // there, so that no step straddles the kink.
            self.s.pending = None;
            return Ok(Control::Truncate { t: b });
        }
        locate_entry_speeds(self.dynamics, step);
        if let Some(k) = event {
            self.emit_until(step, step.t, step.y)?;
            self.dynamics.accept(step.t, step.y).map_err(SimError::Physics)?;
            self.apply_event(k, step.t, step.y)?;
            self.s.t_reached = step.t;
            self.report_progress(step)?;
            let mut y = step.y.to_vec();
            self.correct(&mut y);
            return Ok(Control::Restart { t: step.t, y });
        }
        self.emit_until(step, step.t, step.y)?;
        self.dynamics.accept(step.t, step.y).map_err(SimError::Physics)?;
        for ((c, g0), g1) in self.s.g_change.iter_mut().zip(&self.s.g_prev).zip(&self.s.g_end) {
            *c = (g1 - g0).abs();
        }
        std::mem::swap(&mut self.s.g_prev, &mut self.s.g_end);
        if step.t == step.t_prev {
            self.dynamics.event_values(step.y, &mut self.s.g_prev);
        }
        if std::mem::take(&mut self.s.resync_events) {
            // After a step across a table's point: at the piece the accepted state synced to
            // (a value a round-off below zero counts as zero, as after an event).
            self.dynamics.event_values(step.y, &mut self.s.g_prev);
            for g in &mut self.s.g_prev {
                *g = g.max(0.0);
            }
        }
        self.s.t_reached = step.t;
        self.report_progress(step)?;
        if self.s.release_at.is_some_and(|tr| (step.t - tr).abs() <= tiny) {
            // The restraint lets go at the end of this step (which was cut to end there).
            self.s.release_at = None;
            self.s.released_at = Some(step.t);
            self.dynamics.release_restraint();
            return Ok(Control::Restart { t: step.t, y: step.y.to_vec() });
        }
        if next_break.is_some_and(|b| (step.t - b).abs() <= tiny) {
            // A load switches here: the integrator starts afresh from this state.
            return Ok(Control::Restart { t: step.t, y: step.y.to_vec() });
        }
        if step.t > step.t_prev && (self.dynamics.has_locks() || self.s.momenta.is_some()) {
            let mut y = step.y.to_vec();
            if self.correct(&mut y) {
                return Ok(Control::Correct { y });
            }
        }
        Ok(Control::Continue)
    }

    /// Tells the progress callback the time reached; stops the run if it asks to.
    fn report_progress(&mut self, step: &Step<'_>) -> Result<(), SimError> {
        if step.t > step.t_prev {
            self.s.steps += 1;
            self.s.window_longest = self.s.window_longest.max(step.t - step.t_prev);
            if self.s.steps.is_multiple_of(PACE_WINDOW) {
                self.check_pace(step)?;
            }
        }
        let Some(callback) = self.progress.as_mut() else { return Ok(()) };
        let progress = progress_at(self.s, self.dynamics, step);
        match callback(&progress) {
            ControlFlow::Break(()) => Err(SimError::Interrupted { t: step.t }),
            ControlFlow::Continue(()) => Ok(()),
        }
    }

    /// Stops a run that cannot finish within its step budget at its pace: even at the longest
    /// step of the last [`PACE_WINDOW`], the time left needs more steps than the budget has
    /// left (a run that would otherwise crawl for hours before failing). Deterministic: it
    /// counts steps, not seconds.
    fn check_pace(&mut self, step: &Step<'_>) -> Result<(), SimError> {
        let (longest, left) = (self.s.window_longest, self.s.output_times.end - step.t);
        self.s.window_longest = 0.0;
        let needed = left / longest;
        // (A NaN `needed`, a window without steps, never stops a run.)
        if self.s.steps as f64 + needed <= self.s.step_budget as f64 || needed.is_nan() {
            return Ok(());
        }
        let wall = self.s.started.elapsed().as_secs_f64();
        let projected = wall * (self.s.steps as f64 + needed) / self.s.steps as f64;
        let pace = progress_at(self.s, self.dynamics, step).pace();
        Err(SimError::Integrator {
            t: step.t,
            message: format!(
                "stopped early: at its pace the run cannot finish. None of the last {PACE_WINDOW} steps was longer than {longest:.3e} s, so the {left:.4} s left need at least {needed:.2e} more steps, beyond the run's budget of {:e} (run.max_steps; by default 10 × duration × the fastest hinge rate), about {} of wall time on this machine. What holds the steps back: {pace}",
                self.s.step_budget as f64,
                super::pace::human_seconds(projected)
            ),
        })
    }

    /// Holds locked directions on their constraints once they drift, and the momenta where
    /// that or the integrator moved them. Returns whether `y` changed.
    fn correct(&mut self, y: &mut [f64]) -> bool {
        let projected = self.dynamics.project(y, false);
        let mut changed = projected;
        if let Some((p0, h0)) = self.s.momenta
            && (projected
                || match self.s.restore {
                    Restore::EveryStep => true,
                    Restore::OnDrift => self.drifted(y, &p0, &h0),
                    Restore::AfterProjections => false,
                })
        {
            changed |= self.dynamics.restore_momentum(y, &p0, &h0) > 1e-15;
        }
        changed
    }

    /// Whether the momenta of `y` have drifted from `(p0, h0)` by more than
    /// [`MOMENTUM_DRIFT`] of the largest scales seen so far (which this brings up to date).
    fn drifted(&mut self, y: &[f64], p0: &crate::math::Vec3, h0: &crate::math::Vec3) -> bool {
        let (drift, scales) = self.dynamics.momentum_drift(y, p0, h0);
        let seen = &mut self.s.momentum_scales;
        for k in 0..2 {
            seen[k] = seen[k].max(scales[k]);
        }
        (0..2).any(|k| drift[k] > MOMENTUM_DRIFT * seen[k])
    }
}

/// The run's step handler with the state the integration goes on from after each step
/// (corrected, or restarted), kept for a stepped run's next piece and for `auto`'s next
/// method.
pub(super) struct Tracked<'t, 'a, 'm, 'x, 'y> {
    pub(super) out: &'t mut StreamOut<'a, 'm, 'x, 'y>,
    pub(super) end: &'t mut Vec<f64>,
}

impl Tracked<'_, '_, '_, '_, '_> {
    /// Handles an accepted step and records the state the integration goes on from.
    pub(super) fn on_step(&mut self, step: &Step<'_>) -> Result<Control, SimError> {
        let control = self.out.on_step(step)?;
        match &control {
            Control::Continue | Control::Stop => self.end.clone_from_slice(step.y),
            Control::Restart { y, .. } | Control::Correct { y } => self.end.clone_from_slice(y),
            Control::Truncate { .. } => {}
        }
        Ok(control)
    }
}

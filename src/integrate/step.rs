//! What every integrator shares: the system it integrates, the accepted step it hands out
//! with its dense output, its statistics and its errors.

/// A first-order system `ẏ = f(t, y)`.
pub trait OdeSystem {
    /// Writes `f(t, y)` into `dydt`.
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]);

    /// The first time after `t` at which `f` may jump (a load switched, a table's corner, a
    /// controller's sample), if any: no step passes it; a step lands on it exactly, as
    /// CVODE's `tstop` does, rather than shrinking towards a jump it cannot cross.
    fn next_break(&self, _t: f64) -> Option<f64> {
        None
    }

    /// Marks in `rates` (all false on entry, one per component) the components that are
    /// rates of others (velocities of a second-order system). An implicit method weighs
    /// their error by the step h: the displacement that error makes over a step, in the
    /// units of the components it drives (Hairer & Wanner, *Solving ODEs II*, §VII.3 and
    /// §VII.8, scale the error of a DAE's higher-index components by h in the same way).
    /// The stiff, lightly damped vibrations whose rates the positions never show then
    /// stop setting the step (docs/scenario.md, `run.error_norm`).
    fn mark_rates(&self, _rates: &mut [bool]) {}
}

/// Integration method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Dormand–Prince 8(5,3), adaptive, 7th-order dense output.
    Dop853 {
        /// Relative tolerance per component.
        rtol: f64,
        /// Absolute tolerance per component.
        atol: f64,
    },
    /// Dormand–Prince 5(4), adaptive, 4th-order dense output.
    Dopri5 {
        /// Relative tolerance per component.
        rtol: f64,
        /// Absolute tolerance per component.
        atol: f64,
    },
    /// Classical RK4 with a fixed step (s); cubic Hermite dense output.
    Rk4 {
        /// Step, in the units of t.
        step: f64,
    },
}

/// Counters of one integration.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Of the rejected steps, those whose Newton iteration did not converge (implicit
    /// methods); the others failed the error test.
    pub newton_failures: usize,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: usize,
    /// First time at which DOP853 found its step limited by stability rather than accuracy
    /// (Hairer's test: h·|λ| > 6.1 on 15 accepted steps in a row), if it did.
    pub stiff_from: Option<f64>,
    /// Newton iterations (implicit methods).
    pub newton_iterations: usize,
    /// Jacobians formed (implicit methods).
    pub jacobians: usize,
    /// Factorizations of the Newton matrix for a new step size with the Jacobian kept
    /// (implicit methods).
    pub refactorizations: usize,
    /// The step the step-size control proposed after the last accepted step (for a later
    /// integration that goes on from there: [`Limits::first_step`]).
    pub next_step: f64,
    /// Where the integration stopped before its end, if it did (s): the callback's
    /// [`Control::Stop`], [`Limits::stop_when_stiff`] or [`Limits::hand_back_below`].
    pub stopped_at: Option<f64>,
    /// The last accepted step, s.
    pub last_step: f64,
}

impl Stats {
    /// Adds a later integration's counters to these (a run made of several integrations:
    /// a stepped run's pieces, `auto`'s spans); the first stiffness time is kept, the step
    /// sizes are the later one's.
    pub fn absorb(&mut self, s: &Stats) {
        self.accepted += s.accepted;
        self.rejected += s.rejected;
        self.newton_failures += s.newton_failures;
        self.rhs_evaluations += s.rhs_evaluations;
        self.newton_iterations += s.newton_iterations;
        self.jacobians += s.jacobians;
        self.refactorizations += s.refactorizations;
        self.stiff_from = self.stiff_from.or(s.stiff_from);
        self.next_step = s.next_step;
        self.last_step = s.last_step;
        self.stopped_at = None;
    }

    /// Refactors `newton` for `h_gamma`, counting it.
    pub(crate) fn refactor(&mut self, newton: &mut dyn crate::integrate::NewtonMatrix, h_gamma: f64) -> bool {
        self.refactorizations += 1;
        newton.refactor(h_gamma)
    }
}

/// Bounds that make every integration end, whatever the system does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Smallest step the step-size control may take, in the units of t (steps cut short to
    /// land on an event or on the end are exempt). Below it the integration stops with
    /// [`OdeError::StepTooSmall`].
    pub min_step: f64,
    /// Most steps, accepted and rejected together; beyond it the integration stops with
    /// [`OdeError::TooManySteps`].
    pub max_steps: usize,
    /// The step to try first, instead of the method's starting rule (an integration that
    /// goes on from where another stopped: [`Stats::next_step`]).
    pub first_step: Option<f64>,
    /// Explicit methods (DOP853): stop once the stiffness test finds the step limited by
    /// stability ([`Stats::stiff_from`]), but not before this many accepted steps, for an
    /// implicit method to go on.
    pub stop_when_stiff: Option<usize>,
    /// Implicit methods: stop once this many accepted steps in a row were shorter than
    /// the given step (s), for an explicit method to go on (`(steps, h)`).
    pub hand_back_below: Option<(usize, f64)>,
}

impl Default for Limits {
    /// No bound beyond round-off.
    fn default() -> Self {
        Self { min_step: 0.0, max_steps: usize::MAX, first_step: None, stop_when_stiff: None, hand_back_below: None }
    }
}

/// Why an integration stopped early.
#[derive(Debug, PartialEq)]
pub enum OdeError<E> {
    /// The step size fell below [`Limits::min_step`] or to the round-off level of t.
    StepTooSmall {
        /// Time reached.
        t: f64,
        /// Step size at failure.
        h: f64,
        /// Whether the last steps tried were rejected because their stages were not finite
        /// (an overflow) rather than for their error.
        non_finite: bool,
        /// The last accepted state.
        y: Vec<f64>,
    },
    /// More steps than [`Limits::max_steps`].
    TooManySteps {
        /// Time reached.
        t: f64,
        /// The last step size.
        h: f64,
        /// Steps taken, accepted and rejected.
        steps: usize,
        /// The last accepted state.
        y: Vec<f64>,
    },
    /// The implicit method's Newton matrix `I − hγJ` could not be factored (a singular
    /// pivot block) at the step size tried.
    SingularNewton {
        /// Time reached.
        t: f64,
        /// Step size tried.
        h: f64,
        /// The block whose pivot was singular ([`crate::integrate::NewtonMatrix::singular_block`]).
        block: Option<usize>,
    },
    /// The right-hand side produced a non-finite value.
    NonFinite {
        /// Time reached.
        t: f64,
        /// The state there (the non-finite one where the method has it, else the last
        /// accepted one).
        y: Vec<f64>,
    },
    /// The step callback stopped the run.
    Callback(E),
}

impl Control {
    /// [`Control::Correct`] as a restart at `t` (the step's end), for the explicit methods;
    /// every other request as it is.
    pub fn restart_if_corrected(self, t: f64) -> Self {
        match self {
            Control::Correct { y } => Control::Restart { t, y },
            other => other,
        }
    }
}

/// What the step callback asks the integrator to do next.
#[derive(Clone, Debug, PartialEq)]
pub enum Control {
    /// Go on from the end of the accepted step.
    Continue,
    /// Go on from `(t, y)` instead (for example after an event that changes the right-hand
    /// side at the end of the step). The first derivative is re-evaluated there.
    Restart {
        /// Time to restart from.
        t: f64,
        /// State to restart from.
        y: Vec<f64>,
    },
    /// Go on from `y` at the step's end: a small correction of the state the step reached
    /// (locked directions projected back onto their constraints, the momenta restored), the
    /// right-hand side unchanged. An explicit method restarts there (its first stage is f
    /// at the state); the implicit ones go on from it with the derivative they hold (SDIRK4's
    /// last stage's, which only starts its next first stage; generalized-α's history).
    Correct {
        /// The corrected state.
        y: Vec<f64>,
    },
    /// Discard the step and take it again to end at `t` (inside the step): an event located
    /// by dense output at `t`, so that no step straddles a change of the right-hand side.
    Truncate {
        /// Time the retaken step should end at.
        t: f64,
    },
    /// End the integration at the end of this step, as if it were the last: the caller goes
    /// on from there (with another method, say). [`Stats::stopped_at`] says where.
    Stop,
}

/// How an implicit method weighs the error of each component in its step-size control and
/// its Newton convergence test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorNorm {
    /// The components marked by [`OdeSystem::mark_rates`] (velocities) weighed by the step
    /// h: the error is the displacement a step makes, so tolerances bound positions and
    /// attitudes, and stiff vibrations whose rates the positions never show do not set
    /// the step.
    Displacement,
    /// Every component as it is (Hairer's norm): the rates of stiff vibrations resolved to
    /// the tolerance too, at the cost of steps set by them.
    State,
}

/// The implicit methods' first step without [`Limits::first_step`]: a thousandth of the
/// interval, at most 10 ms (the step control takes it from there).
pub(super) fn first_step_rule(t0: f64, tf: f64) -> f64 {
    (1e-3 * (tf - t0)).min(1e-2)
}

/// The root-mean-square of `v` scaled by the tolerances at `y`, the components marked in
/// `rates` weighed by the step `h` ([`OdeSystem::mark_rates`]).
pub(super) fn norm(v: &[f64], y: &[f64], rates: &[bool], h: f64, rtol: f64, atol: f64) -> f64 {
    let s: f64 = v
        .iter()
        .zip(y)
        .zip(rates)
        .map(|((e, yi), &rate)| {
            let e = if rate { e * h } else { *e };
            (e / (atol + rtol * yi.abs())).powi(2)
        })
        .sum();
    (s / v.len().max(1) as f64).sqrt()
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum DenseKind {
    Hermite,
    Dopri5,
    Dop853,
}

/// An accepted step, with its dense output.
pub struct Step<'a> {
    /// Start of the step.
    pub t_prev: f64,
    /// End of the step.
    pub t: f64,
    /// State at `t`.
    pub y: &'a [f64],
    pub(super) kind: DenseKind,
    pub(super) cont: &'a [Vec<f64>],
}

impl<'a> Step<'a> {
    /// A step whose dense output is the cubic `c0 + θ (c1 + (1 − θ)(c2 + θ c3))` with terms
    /// `cont` = [c0, c1, c2, c3], θ the fraction of the step: for a cubic Hermite (RK4,
    /// generalized-α) Hairer's rcont1..4, y_prev, y − y_prev, h f_prev − (y − y_prev),
    /// (y − y_prev) − h f − that; generalized-α its quadratic through three steps' ends
    /// (c2 = −κ, c3 = 0) or, for the rates on a first step, the straight line (c2 = c3 = 0);
    /// SDIRK4 its stage-based cubic.
    pub(crate) fn hermite(t_prev: f64, t: f64, y: &'a [f64], cont: &'a [Vec<f64>]) -> Self {
        Step { t_prev, t, y, kind: DenseKind::Hermite, cont }
    }

    /// The dense-output state at `t` in `[t_prev, t]`, written into `out`.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        self.interpolate_range(t, 0..out.len(), out);
    }

    /// The components `range` of the dense-output state at `t` in `[t_prev, t]`, written
    /// into `out[range]` (the rest of `out` is left as it is): for an event function that
    /// reads two bodies of many.
    pub fn interpolate_range(&self, t: f64, range: std::ops::Range<usize>, out: &mut [f64]) {
        let h = self.t - self.t_prev;
        let s = if h != 0.0 { (t - self.t_prev) / h } else { 1.0 };
        let s1 = 1.0 - s;
        let c = self.cont;
        let out = &mut out[range.clone()];
        match self.kind {
            DenseKind::Hermite => {
                for (i, o) in range.zip(out) {
                    *o = c[0][i] + s * (c[1][i] + s1 * (c[2][i] + s * c[3][i]));
                }
            }
            DenseKind::Dopri5 => {
                for (i, o) in range.zip(out) {
                    *o = c[0][i] + s * (c[1][i] + s1 * (c[2][i] + s * (c[3][i] + s1 * c[4][i])));
                }
            }
            DenseKind::Dop853 => {
                for (i, o) in range.zip(out) {
                    let conpar = c[4][i] + s * (c[5][i] + s1 * (c[6][i] + s * c[7][i]));
                    *o = c[0][i] + s * (c[1][i] + s1 * (c[2][i] + s * (c[3][i] + s1 * conpar)));
                }
            }
        }
    }
}

/// Calls `on_step` once at `t0` with a zero-length step at `y` (its [`Control`] is ignored),
/// as every integrator does before its first step.
pub(super) fn announce_start<E>(
    t0: f64,
    y: &[f64],
    on_step: &mut impl FnMut(&Step<'_>) -> Result<Control, E>,
) -> Result<(), OdeError<E>> {
    let n = y.len();
    let cont = vec![y.to_vec(), vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    on_step(&Step { t_prev: t0, t: t0, y, kind: DenseKind::Hermite, cont: &cont }).map_err(OdeError::Callback)?;
    Ok(())
}

/// Cubic Hermite terms shared by all three dense outputs (Hairer's rcont1..rcont4).
pub(super) fn hermite(cont: &mut [Vec<f64>], y: &[f64], y_new: &[f64], f_old: &[f64], f_new: &[f64], h: f64) {
    for i in 0..y.len() {
        let ydiff = y_new[i] - y[i];
        let bspl = h * f_old[i] - ydiff;
        cont[0][i] = y[i];
        cont[1][i] = ydiff;
        cont[2][i] = bspl;
        cont[3][i] = ydiff - h * f_new[i] - bspl;
    }
}

/// Whether a break at `b` (s) ends a step of its own before a span's end `tf`: not when it
/// lies within round-off of `tf` (1e-12 relative, the breaks' own tolerance in the run), where
/// the span's last step ends at `tf` in its stead. A span `t + dt` that lands a round-off past
/// a control sample would otherwise leave a last step of 1e-16 s, below any step floor.
pub fn before_end(b: f64, tf: f64) -> bool {
    b < tf - 1e-12 * tf.abs().max(1.0)
}

/// Whether a step of `h` (s) from `t` that was cut short to end at an event (its end found
/// inside a longer step, `Control::Truncate`) ends on `stop` (the span's end or the next break
/// of the right-hand side) instead: only where it reaches the stop to within 1e-13 relative
/// (below the run's 1e-12 tolerance for an event at a step's end). A step not cut short
/// lands on the stop from within 1 % of it, so as to leave no sliver after it; a cut-short
/// step snapped so would be taken past its event again, to be cut short again, without end:
/// the z-fold with reaction wheels at rtol 4e-5 under DOP853, a hysteresis event 4.7e-5 s
/// before a 10-Hz control sample, spent its million-step budget at that one place.
pub fn cut_short_lands(t: f64, h: f64, stop: f64) -> bool {
    t + h >= stop - 1e-13 * stop.abs().max(1.0)
}

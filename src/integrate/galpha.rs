//! The generalized-α method for first-order systems (Jansen, Whiting & Hulbert, *Comput.
//! Methods Appl. Mech. Engrg.* 190 (2000) 305–319, eqs. 13–17, with the parameters of their
//! eq. 21): one implicit stage per step, second order, and a high-frequency damping set by
//! one number, the spectral radius ρ∞ of the step at infinite frequency (1: none, 0: all).
//!
//! This is the method that lets a fixed-step code such as Exudyn step over a structure's
//! stiff, lightly damped stretch and bending vibrations without resolving them and without
//! damping the slow motion: at ρ∞ = 0.9 a vibration it cannot resolve loses 10 % of its
//! amplitude per step, where SDIRK4 (L-stable) removes it at once. With steps at a fixed `h`
//! (cut only to land on the end or a break of the right-hand side, or halved when Newton
//! fails) the user chooses the accuracy by the step, as with RK4, and the Newton iterations
//! converge to the run's rtol and atol; with adaptive steps ([`AlphaSteps::Adaptive`]) each
//! step's local error is held to them ([`integrate_generalized_alpha`] says how).
//!
//! For `ẏ = f(t, y)`, with `ẏₙ` the method's own derivative (not f(yₙ) after the first step):
//!
//! ```text
//! yₙ₊₁ = yₙ + h ẏₙ + h γ (ẏₙ₊₁ − ẏₙ)
//! ẏₙ + α_m (ẏₙ₊₁ − ẏₙ) = f(tₙ + α_f h, yₙ + α_f (yₙ₊₁ − yₙ))
//! α_m = (3 − ρ∞) / (2 (1 + ρ∞)),  α_f = 1 / (1 + ρ∞),  γ = ½ + α_m − α_f
//! ```
//!
//! Newton on Δ = yₙ₊₁ − yₙ has the matrix `(α_m/(hγ)) I − α_f J`, which is
//! `(α_m/(hγ)) W` with `W = I − h γ (α_f/α_m) J`: the [`NewtonMatrix`] of SDIRK4 with
//! `hγ (α_f/α_m)` in place of its `hγ`.

use super::anderson::{Anderson, SLOW};
use super::newton::NewtonMatrix;
use super::step::{
    Control, ErrorNorm, Limits, OdeError, OdeSystem, Stats, Step, announce_start, before_end, cut_short_lands,
    first_step_rule, norm,
};

/// The method's three parameters from ρ∞ (Jansen, Whiting & Hulbert, eq. 21).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaParameters {
    /// α_m.
    pub alpha_m: f64,
    /// α_f.
    pub alpha_f: f64,
    /// γ.
    pub gamma: f64,
}

impl AlphaParameters {
    /// The second-order parameters with spectral radius `rho_inf` ∈ [0, 1] at infinite
    /// frequency.
    pub fn from_rho_inf(rho_inf: f64) -> Self {
        let alpha_m = 0.5 * (3.0 - rho_inf) / (1.0 + rho_inf);
        let alpha_f = 1.0 / (1.0 + rho_inf);
        Self { alpha_m, alpha_f, gamma: 0.5 + alpha_m - alpha_f }
    }
}

/// ρ∞ of `integrator = "generalized-alpha"` (and of `auto`'s implicit spans) when
/// `run.rho_inf` is not given: Exudyn's default, a tenth of an unresolved vibration's
/// amplitude lost per step.
pub const DEFAULT_RHO_INF: f64 = 0.9;

/// How the steps are chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaSteps {
    /// At a fixed step (s), cut only to land on the end or a break, or halved when Newton
    /// fails; the user chooses the accuracy by the step.
    Fixed(f64),
    /// Adaptive: each step's local error estimated (see [`integrate_generalized_alpha`])
    /// and held to the run's rtol and atol in the given norm.
    Adaptive(ErrorNorm),
}

/// Adaptive steps keep their length (and the factorization of the Newton matrix) while the
/// control asks for a change within this range: a refactorization costs about as much as
/// a step on the starshade flasher, and keeping the step for factors down to 0.9 (a step
/// that used ¾ of its tolerance or more) rather than 1.0 (RADAU5's) cut its refactorizations
/// at rtol 1e-7 from 2,393 to 675 and its time from 6.1 to 3.6 s, the error unchanged.
const KEEP_STEP: (f64, f64) = (0.9, 1.2);

/// A step rejected twice in a row at one instant with an error falling only as h (a jump
/// of f inside it) is taken once it is within this many times the run's step floor
/// (`Limits::min_step`, 1e-12 of the duration: so 1e-7 of the duration). The error
/// estimate sees such jumps where SDIRK4's and DOP853's combinations of stages are blind to
/// those early in a step; the handler locates the events after a step is taken, so a step
/// over an event must be taken first. 1e3 left the latch z-folds under forced
/// generalized-α stopped at their step floor at a latch (4.35 s), 1e4 one of the two; with
/// 1e5 both finish (E + D to 6e-7, fold angles within 4.4e-6 rad of DOP853's at rtol 1e-10).
const JUMP_STEPS: f64 = 1e5;

/// With adaptive steps, a fresh Jacobian after an accepted step whose Newton took more than
/// this many iterations (4 at fixed steps): a stale Jacobian costs iterations, a fresh one
/// a Jacobian and a factorization, which on the starshade cost more (228 and 996 panels,
/// 60 s, rtol 1e-4: 4.45 → 3.78 s and 24.1 → 20.8 s with 6; the 10-s Exudyn case 10–30 %
/// faster at rtol 1e-4 … 1e-7, errors alike; 8 was no better).
const FRESH_AFTER_ADAPTIVE: usize = 6;

/// Newton stops when its increment is below this fraction of the tolerances (scaled norm),
/// at fixed steps (where rtol and atol are Newton's alone).
const KAPPA: f64 = 0.01;
/// The same with adaptive steps, SDIRK4's value: the step's error estimate is held to the
/// tolerance, and Newton's share of it need not be tighter (0.01 cost the starshade 5–45 %
/// more time, the same error within the runs' spread).
const KAPPA_ADAPTIVE: f64 = 0.03;
/// Iterations before Newton gives up on a step (then a fresh Jacobian, then half the step).
const MAX_ITERATIONS: usize = 10;

/// Integrates `system` from `t0` to `tf` with the generalized-α method, at fixed steps or
/// adaptive ones ([`AlphaSteps`]), calling `on_step` after every step with a cubic Hermite
/// dense output (as [`super::integrate`]). Newton converges to `rtol`, `atol` in the
/// root-mean-square norm of every component (fixed steps) or in the error norm (adaptive).
///
/// The adaptive steps' error estimate compares the step with the third-order Adams–Moulton
/// step over the same interval, made of `f` at the accepted states `yₙ₋₁`, `yₙ` and at the
/// new `yₙ₊₁` (one more right-hand side per step). Its local error is O(h⁴), so the
/// difference is the step's own local error to leading order for any problem: the
/// method's error constant differs between problem types (for `y' = g(t)` it is
/// `(a² + 2aγ + γ + b − 1/3)/2` with `a = α_f − α_m`, `b = α_m² − α_m`: −0.041 at ρ∞ = 0.9;
/// for `y' = λy` +0.084), so an estimate scaled from the predictor's difference (Milne's
/// device) was wrong by 2× and in sign on one or the other. The estimate is filtered through
/// `W⁻¹` as SDIRK4's is (Hairer & Wanner's remedy for vibrations beyond the step, which
/// the method damps rather than follows). The step follows a PI control within [0.2, 4]
/// times the last, kept for changes within 0.9–1.2 times it (the factorization then serves).
/// Before a step of a new length ẏₙ is shifted to it (the method's derivative lags the
/// state by `(α_f − α_m) h`, Arnold & Brüls 2007).
#[allow(clippy::too_many_arguments)]
pub fn integrate_generalized_alpha<S: OdeSystem + ?Sized, E>(
    system: &S,
    newton: &mut dyn NewtonMatrix,
    steps: AlphaSteps,
    rho_inf: f64,
    rtol: f64,
    atol: f64,
    limits: Limits,
    t0: f64,
    tf: f64,
    y0: &[f64],
    mut on_step: impl FnMut(&Step<'_>) -> Result<Control, E>,
) -> Result<Stats, OdeError<E>> {
    let params = AlphaParameters::from_rho_inf(rho_inf);
    let AlphaParameters { alpha_m, alpha_f, gamma } = params;
    let n = y0.len();
    let mut rates = vec![false; n];
    // The rates (velocities, angular velocities) whatever the error norm: on a step with no
    // state before it their output rows are interpolated linearly (below).
    let mut rate_components = vec![false; n];
    system.mark_rates(&mut rate_components);
    let fixed = match steps {
        AlphaSteps::Fixed(h) => Some(h),
        AlphaSteps::Adaptive(kind) => {
            if kind == ErrorNorm::Displacement {
                system.mark_rates(&mut rates);
            }
            None
        }
    };
    let kappa = if fixed.is_some() { KAPPA } else { KAPPA_ADAPTIVE };
    let mut stats = Stats::default();
    let mut y = y0.to_vec();
    let mut t = t0;
    // ẏ₀ = f(t₀, y₀); the derivative before it (for the predictor) the same.
    let mut yd = vec![0.0; n];
    system.rhs(t, &y, &mut yd);
    stats.rhs_evaluations += 1;
    let mut yd_prev = yd.clone();
    // Whether ẏₙ₋₁ is the method's own (the predictor is then second order).
    let mut history = false;
    announce_start(t0, &y, &mut on_step)?;
    let newton_h = |h: f64| h * gamma * alpha_f / alpha_m;
    let start = fixed.unwrap_or_else(|| first_step_rule(t0, tf));
    let mut h = limits.first_step.unwrap_or(start).min(fixed.unwrap_or(f64::INFINITY)).min(tf - t0);
    stats.jacobians += 1;
    if !newton.prepare(t, &y, newton_h(h)) {
        return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
    }
    let mut prepared_h = h;
    let mut fresh_jacobian = true;
    let (mut delta, mut y_new, mut y_alpha, mut f_alpha, mut yd_new, mut r) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut err = vec![0.0; n];
    let mut cont = vec![vec![0.0; n]; 4];
    // The step before this one (s), for the rows' quadratic, whose start yₙ₋₁ is still in
    // `cont[0]` (`None`: no such step since the start, an event or a step taken again).
    let mut back: Option<f64> = None;
    let mut accelerate = Anderson::default();
    let mut weights = vec![0.0; n];
    let (mut forced, mut non_finite, mut after_rejection) = (false, false, false);
    let mut short_steps = 0;
    let mut h_prev = h;
    // The step ẏₙ's shift is consistent with (adaptive steps).
    let shift_a = alpha_f - alpha_m;
    let mut h_valid = h;
    // f at the accepted states yₙ₋₁ and yₙ, and at the step's end (adaptive steps).
    let (mut f_back, mut f_here, mut f_new) = (vec![0.0; n], yd.clone(), vec![0.0; n]);
    let mut f_back_valid = false;
    // The last accepted step's error, for the PI control.
    let mut e_last = 1.0f64;
    // The last rejection by the error test: where, its error and step.
    let (mut rejected_at, mut e_rejected, mut h_rejected) = (None, 0.0, 0.0);
    loop {
        let stop = system.next_break(t).filter(|&b| before_end(b, tf)).unwrap_or(tf);
        let landing = if forced { cut_short_lands(t, h, stop) } else { t + 1.01 * h >= stop };
        if landing {
            h = stop - t;
        }
        if h.abs() <= 10.0 * f64::EPSILON * t.abs().max(1.0) || (!landing && !forced && h.abs() < limits.min_step) {
            return Err(OdeError::StepTooSmall { t, h, non_finite, y: y.to_vec() });
        }
        if stats.accepted + stats.rejected >= limits.max_steps {
            return Err(OdeError::TooManySteps { t, h, steps: stats.accepted + stats.rejected, y: y.to_vec() });
        }
        if (h - prepared_h).abs() > 1e-12 * h && !stats.refactor(&mut *newton, newton_h(h)) {
            return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
        }
        prepared_h = h;
        if fixed.is_none() && history && h != h_valid {
            // ẏₙ is `y'(tₙ + a h)` to first order for the step h that made it (Arnold &
            // Brüls, Multibody Syst. Dyn. 18 (2007) 185–202: generalized-α's derivative
            // variable lags by a shift proportional to the step); a new step shifts it by
            // `a (h − h_old) ÿ` to match, else each change of step leaves an error that
            // decays only by (1 − 1/α_m) a step and that the estimate cannot see. ÿ from
            // the method's last two derivatives; the change filtered through W⁻¹ (the stiff
            // components' ẏ is the method's damped vibration, not a derivative to follow).
            // (The next term, `b (h² − h_old²) y'''` with `b = α_m² − α_m`, made no
            // difference beyond the runs' spread on the starshade and the stiff grid.)
            let da = shift_a * (h - h_valid);
            for k in 0..n {
                r[k] = da * (yd[k] - yd_prev[k]) / h_prev;
            }
            newton.solve(&mut r);
            for k in 0..n {
                yd[k] += r[k];
            }
            h_valid = h;
        }
        // Predictor: ẏₙ₊₁ from the last two derivatives, extrapolated linearly.
        let ratio = if history { h / h_prev } else { 0.0 };
        for k in 0..n {
            let yd_guess = yd[k] + ratio * (yd[k] - yd_prev[k]);
            delta[k] = h * yd[k] + h * gamma * (yd_guess - yd[k]);
        }
        let c_m = alpha_m / (h * gamma);
        // Slow iterations are mixed (`anderson.rs`), in the weights of the convergence test.
        accelerate.reset();
        for k in 0..n {
            weights[k] = 1.0 / (atol + rtol * y[k].abs());
        }
        let mut converged = false;
        let mut iterations = 0;
        let mut previous = f64::INFINITY;
        let mut slow = false;
        for iteration in 1..=MAX_ITERATIONS {
            iterations = iteration;
            stats.newton_iterations += 1;
            for k in 0..n {
                y_alpha[k] = y[k] + alpha_f * delta[k];
            }
            system.rhs(t + alpha_f * h, &y_alpha, &mut f_alpha);
            stats.rhs_evaluations += 1;
            // −R (hγ/α_m): R = ẏₙ + (α_m/(hγ)) (Δ − h ẏₙ) − f(y_α).
            for k in 0..n {
                r[k] = -(yd[k] / c_m + (delta[k] - h * yd[k]) - f_alpha[k] / c_m);
            }
            newton.solve(&mut r);
            for k in 0..n {
                y_new[k] = y[k] + delta[k] + r[k];
            }
            // Every component as it is (rates not weighed by the step): an iteration's
            // velocity residual that the error norm would let pass at h × its size is a drift
            // that the steps carry to the end (the starshade's error at rtol 1e-7 was 1.4e-5 m
            // with the rates weighed by h here, 9.2e-7 m with them as they are). (Weighing
            // the marked rates by 1 s is the state norm.)
            let d = norm(&r, &y_new, &rates, 1.0, rtol, atol) / kappa;
            // Converged below kappa (tested first: at a step of a few round-offs of t, taken
            // to land on an event, an increment at round-off level may be twice the last
            // and is still converged); or within the tolerance and no longer contracting
            // (the round-off floor of a tolerance near f64's resolution: halving the step
            // would not lower it).
            if d <= 1.0 || (d <= 1.0 / kappa && d > 0.5 * previous) {
                for k in 0..n {
                    delta[k] += r[k];
                }
                converged = true;
                break;
            }
            if !d.is_finite() || d > 2.0 * previous {
                non_finite = !d.is_finite();
                break;
            }
            // Once an iteration is slow, the rest of this solve mixes its iterates.
            slow = slow || d > SLOW * previous;
            if slow {
                accelerate.advance(&mut delta, &r, &weights);
            } else {
                for k in 0..n {
                    delta[k] += r[k];
                }
            }
            previous = d;
        }
        if !converged {
            stats.rejected += 1;
            stats.newton_failures += 1;
            after_rejection = true;
            if fresh_jacobian {
                h *= 0.5;
                forced = false;
                if !stats.refactor(&mut *newton, newton_h(h)) {
                    return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
                }
            } else {
                fresh_jacobian = true;
                stats.jacobians += 1;
                if !newton.prepare(t, &y, newton_h(h)) {
                    return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
                }
            }
            prepared_h = h;
            continue;
        }
        for k in 0..n {
            yd_new[k] = yd[k] + (delta[k] - h * yd[k]) / (h * gamma);
        }
        let mut factor = 1.0;
        if fixed.is_none() {
            // f(yₙ₊₁): with f(yₙ) and f(yₙ₋₁) at the accepted states, the third-order
            // Adams–Moulton step over the same interval (the quadratic through the three
            // derivatives, integrated; variable steps): its local error is O(h⁴) whatever
            // the problem, so Δ − Δ_AM3 is this step's local error to leading order.
            // Without f(yₙ₋₁) (the first step, or after a restart) the trapezoidal rule's,
            // O(h³) like the step's own.
            system.rhs(t + h, &y_new, &mut f_new);
            stats.rhs_evaluations += 1;
            let (w_back, w_here, w_new) = if f_back_valid {
                let hp = h_prev;
                (
                    -h * h * h / (6.0 * hp * (hp + h)),
                    h * h / (6.0 * hp) + 0.5 * h,
                    h * (2.0 * h + 3.0 * hp) / (6.0 * (h + hp)),
                )
            } else {
                (0.0, 0.5 * h, 0.5 * h)
            };
            for k in 0..n {
                err[k] = delta[k] - (w_back * f_back[k] + w_here * f_here[k] + w_new * f_new[k]);
            }
            newton.solve(&mut err);
            let e = norm(&err, &y_new, &rates, h, rtol, atol);
            let e = if e.is_nan() { f64::INFINITY } else { e.max(1e-10) };
            // Gustafsson's PI control (Hairer & Wanner I, §II.4: exponents 0.7/k and 0.4/k,
            // k = 3): the estimate's step-to-step scatter (stiff vibrations the method damps
            // over several steps) no longer turns into rejections (the stiff grid at rtol
            // 1e-7: 894 rejected of 3,288 with the I controller, 10 of 3,221 with this).
            factor = if history { 0.9 * e.powf(-0.7 / 3.0) * e_last.powf(0.4 / 3.0) } else { 0.9 * e.powf(-1.0 / 3.0) }
                .clamp(0.2, 4.0);
            // A jump of f inside the step (a force that switches on steeply at a state the run
            // does not locate: contact-panel-hub at rtol 1e-9 at 0.85092 s) gives an error
            // that falls only in proportion to h, however short the step: after two such
            // rejections in a row at one instant, with the step within [`JUMP_STEPS`] times the
            // run's floor, the step is taken (its error, h × the jump, a one-off of that
            // size), as a code at its minimum step would, rather than stopping the run there.
            // Where the jump is an event of the laws (a stop's damping taking hold, a latch),
            // the run's handler then ends the step at the event and the step is taken again.
            let jump = e > 1.0
                && rejected_at == Some(t)
                && e / e_rejected > 0.5 * h / h_rejected
                && h < JUMP_STEPS * limits.min_step;
            if e > 1.0 && !jump {
                stats.rejected += 1;
                after_rejection = true;
                (forced, non_finite) = (false, !e.is_finite());
                (rejected_at, e_rejected, h_rejected) = (Some(t), e, h);
                h *= factor.min(1.0);
                continue;
            }
            if jump {
                factor = 1.0;
            }
            // Hairer's DOPRI5 keeps the last error at 1e-4 or more for the PI control: an
            // error far below the tolerance before a normal one would otherwise read as a
            // fast rise and cut the step to a fifth (the latch z-fold under forced
            // generalized-α fell below its step floor that way, after tiny steps at a jump).
            e_last = e.max(1e-4);
            if after_rejection {
                // A step right after a rejection may not grow (as SDIRK4's).
                factor = factor.min(1.0);
            }
        }
        after_rejection = false;
        stats.accepted += 1;
        (forced, non_finite) = (false, false);
        let t_prev = t;
        let back_ratio = back.map(|h_back| h_back / h);
        // The rows between steps: the quadratic through the last three accepted states
        // (yₙ₋₁, yₙ, yₙ₊₁ at their times), third order, formed from step-end values only. Not
        // the cubic Hermite through the method's derivatives ẏₙ, ẏₙ₊₁: in a stiff direction
        // the method steps over (ρ∞ damps it little a step) ẏ is the vibration the tolerance
        // leaves, and h times it put bulges into the rows: the starshade flasher's rows'
        // E + D wandered by 0.66 J of 124 J between steps (0.060 J now) and was back to
        // 0.017 J at their ends, its hinges' rates read metres per second between steps; the
        // positions delivered are the same (docs/architecture.md). The step-end values
        // carry that vibration only at its amplitude, so the quadratic's rows stay within
        // about what the step ends show. With no state before yₙ (the first step, after an
        // event or a step taken again) the Hermite for positions and attitudes and the
        // straight line for the rates.
        for k in 0..n {
            let ydiff = delta[k];
            if let Some(r) = back_ratio {
                // p(s) = yₙ + s Δ + s (s − 1) κ through yₙ₋₁ (the last step's start, still in
                // cont[0]) at s = −r (Hermite form: c₂ = −κ).
                let kappa = (cont[0][k] - y[k] + r * ydiff) / (r * (r + 1.0));
                cont[2][k] = -kappa;
                cont[3][k] = 0.0;
            } else if rate_components[k] {
                cont[2][k] = 0.0;
                cont[3][k] = 0.0;
            } else {
                let bspl = h * yd[k] - ydiff;
                cont[2][k] = bspl;
                cont[3][k] = ydiff - h * yd_new[k] - bspl;
            }
            cont[0][k] = y[k];
            cont[1][k] = ydiff;
        }
        back = Some(h);
        y.copy_from_slice(&y_new);
        yd_prev.copy_from_slice(&yd);
        yd.copy_from_slice(&yd_new);
        history = true;
        h_valid = h;
        if fixed.is_none() {
            std::mem::swap(&mut f_back, &mut f_here);
            std::mem::swap(&mut f_here, &mut f_new);
            f_back_valid = true;
        }
        t = if landing { stop } else { t + h };
        h_prev = t - t_prev;
        stats.last_step = h_prev;
        if let Some((count, below)) = limits.hand_back_below {
            short_steps = if h_prev < below && !landing { short_steps + 1 } else { 0 };
            if short_steps >= count && t < tf {
                stats.stopped_at = Some(t);
            }
        }
        match on_step(&Step::hermite(t_prev, t, &y, &cont)).map_err(OdeError::Callback)? {
            Control::Continue => {}
            Control::Stop => {
                if t < tf {
                    stats.stopped_at = Some(t);
                }
            }
            Control::Restart { t: tr, y: yr } => {
                // A new state (an event changed it): the method starts again from f.
                t = tr;
                y = yr;
                system.rhs(t, &y, &mut yd);
                stats.rhs_evaluations += 1;
                yd_prev.copy_from_slice(&yd);
                history = false;
                f_here.copy_from_slice(&yd);
                back = None;
                f_back_valid = false;
            }
            Control::Correct { y: yc } => {
                // A small correction (the momenta restored, locks projected): the method's
                // derivative goes on. Restarting it from f here every step would leave the
                // method first order for ρ∞ < 1 (the start-up step is consistent only to
                // first order) and re-excite what it damped.
                y = yc;
            }
            Control::Truncate { t: tt } => {
                stats.stopped_at = None;
                y.copy_from_slice(&cont[0]);
                yd.copy_from_slice(&yd_prev);
                t = t_prev;
                stats.accepted -= 1;
                h = tt - t_prev;
                forced = true;
                // The derivative before ẏₙ is gone: the step taken again has no history.
                history = false;
                back = None;
                if fixed.is_none() {
                    std::mem::swap(&mut f_here, &mut f_back);
                    f_back_valid = false;
                }
                continue;
            }
        }
        let next = fixed.unwrap_or(h_prev * factor);
        stats.next_step = next;
        if t >= tf || stats.stopped_at.is_some() {
            stats.rhs_evaluations += newton.evaluations();
            return Ok(stats);
        }
        // Back to the given step after a cut (fixed steps); the step the error asks for,
        // kept for small changes (adaptive).
        match fixed {
            Some(step) => h = step,
            None if !(KEEP_STEP.0..=KEEP_STEP.1).contains(&factor) => h = next,
            None => {}
        }
        // A fresh Jacobian when Newton needed many iterations (the structure has moved on),
        // else the old one serves.
        fresh_jacobian = false;
        if iterations > if fixed.is_some() { 4 } else { FRESH_AFTER_ADAPTIVE } {
            fresh_jacobian = true;
            stats.jacobians += 1;
            if !newton.prepare(t, &y, newton_h(h)) {
                return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
            }
            prepared_h = h;
        }
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod adaptive_tests;

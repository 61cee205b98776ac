//! L-stable implicit integration for stiff hinges: SDIRK4 (Hairer & Wanner, *Solving ODEs
//! II*, §IV.6, Table 6.5: five stages, γ = 1/4, stiffly accurate, order 4 with an embedded
//! order-3 solution) with simplified Newton iterations.
//!
//! The Newton matrix `W = I − hγJ` is supplied by a [`NewtonMatrix`]: how the Jacobian is
//! formed and factored is separate from the method.

use super::anderson::{Anderson, SLOW};
use super::newton::NewtonMatrix;
use super::retries::Retries;
use super::step::{
    Control, ErrorNorm, Limits, OdeError, OdeSystem, Stats, Step, announce_start, before_end, cut_short_lands,
    first_step_rule, norm,
};

const GAMMA: f64 = 0.25;
const C: [f64; 5] = [0.25, 0.75, 11.0 / 20.0, 0.5, 1.0];
const A: [[f64; 5]; 5] = [
    [0.25, 0.0, 0.0, 0.0, 0.0],
    [0.5, 0.25, 0.0, 0.0, 0.0],
    [17.0 / 50.0, -1.0 / 25.0, 0.25, 0.0, 0.0],
    [371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 0.25, 0.0],
    [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0, 0.25],
];
/// Embedded third-order weights.
const B_HAT: [f64; 5] = [59.0 / 48.0, -17.0 / 96.0, 225.0 / 32.0, -85.0 / 12.0, 0.0];

/// Dense output of order 3 from the stage increments `Z_i = Y_i − y`:
/// `y(t + θh) = y + Σ_k θ^k Σ_i DENSE[k−1][i] Z_i`, k = 1, 2, 3. It is `y + h Σ_i b_i(θ) k_i`
/// with weights `b_i(θ)` cubic in θ meeting the order conditions to order 3 at every θ
/// (Σ b_i = θ, Σ b_i c_i = θ²/2, Σ b_i c_i² = θ³/3, Σ b_i (Ac)_i = θ³/6: the continuous
/// Runge–Kutta conditions of Hairer, Nørsett & Wanner I, II.6, applied to the SDIRK4 of Hairer
/// & Wanner II, IV.6) and `b_i(1) = b_i`, written in the
/// stage increments through `h k = A⁻¹ Z` (the least-norm such coefficients, found once with
/// numpy; `dense_output_meets_the_order_conditions` checks them against the tableau). Unlike a
/// cubic Hermite through `f(y)` at both ends, it never multiplies a stiff derivative by h:
/// where the steps stride over a stiff vibration that the method damps, `h f` at a step's ends
/// is large while the stage increments are not, and the Hermite rows between the steps of the
/// thick starshade (steps of ~0.5 s over 1e7-N/m hinge directions) showed those directions
/// moving at 8.7 m/s and 14 J of kinetic energy in a sheet at rest.
const DENSE: [[f64; 5]; 3] = [
    [19.985160796680002, 3.1249507292078382, -4.226854320758467, -7.500985415845956, -0.2647406617357432],
    [-36.1311105443363, -17.439758244646114, 14.112314220130415, 21.204835107081973, 3.7484059449559304],
    [16.145949747656292, 14.314807515438249, -9.885459899371748, -13.703849691236197, -2.4836652832201964],
];

/// Integrates `system` from `t0` to `tf` with SDIRK4, calling `on_step` after every
/// accepted step with its dense output (the stage-based cubic `DENSE`; as
/// [`super::integrate`]).
#[allow(clippy::too_many_arguments)]
pub fn integrate_sdirk4<S: OdeSystem + ?Sized, E>(
    system: &S,
    newton: &mut dyn NewtonMatrix,
    rtol: f64,
    atol: f64,
    error_norm: ErrorNorm,
    limits: Limits,
    t0: f64,
    tf: f64,
    y0: &[f64],
    mut on_step: impl FnMut(&Step<'_>) -> Result<Control, E>,
) -> Result<Stats, OdeError<E>> {
    let n = y0.len();
    let mut rates = vec![false; n];
    if error_norm == ErrorNorm::Displacement {
        system.mark_rates(&mut rates);
    }
    // Accepted steps in a row shorter than `limits.hand_back_below`.
    let mut short_steps = 0;
    let mut stats = Stats::default();
    let mut y = y0.to_vec();
    let mut t = t0;
    let mut f0 = vec![0.0; n];
    system.rhs(t, &y, &mut f0);
    stats.rhs_evaluations += 1;
    announce_start(t0, &y, &mut on_step)?;
    let mut h = limits.first_step.unwrap_or_else(|| first_step_rule(t0, tf)).min(tf - t0);
    let mut fresh_jacobian = true;
    let mut contact_retries = Retries::default();
    // The kind of the retry under way (contact part only or not), if the step is one.
    let mut retried: Option<bool> = None;
    stats.jacobians += 1;
    if !newton.prepare(t, &y, h * GAMMA) {
        return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
    }
    let mut prepared_h = h;
    let mut z: Vec<Vec<f64>> = vec![vec![0.0; n]; 5];
    let mut fz: Vec<Vec<f64>> = vec![vec![0.0; n]; 5];
    let (mut rhs, mut yi, mut delta, mut err) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut cont = vec![vec![0.0; n]; 4];
    let mut accelerate = Anderson::default();
    let mut weights = vec![0.0; n];
    // Newton stops when the increment is below `kappa` in the tolerance-scaled norm, and
    // gives up when it grows (Hairer's rule), or with the displacement norm only when it
    // more than doubles: simplified Newton on lightly damped stiff vibrations contracts
    // unevenly, and giving up at the first increase cost the starshade flasher's 60-s
    // deployment under that norm a rejected step and a Jacobian on most steps (360 of
    // 1,001; 114 of 603 with this bound, 14.7 s → 7.4 s). With every component in the norm
    // the relaxed rule let the tape-latch z-fold's latch chatter at rtol 1e-10.
    // `kappa` is min(0.003, √rtol) (RADAU5's rule, Hairer & Wanner's FNEWT, has 0.03 for
    // 0.003): a tighter stop fails less later. It was chosen while the stages' derivatives
    // were implied by their equations (2026-11-30 to 12-01; they are fresh again, below),
    // with these figures: the thick flasher example at ten tolerances (rtol = atol 0.8–1.25e-4;
    // 2026-11-30): with fresh derivatives and 0.03 (this code until then) E + D 7e-6–6.4e-5
    // relative; implied with 0.03, 3–4e-4 (five tolerances); with 0.01, 2.7e-5–2.2e-4 (three
    // of ten near 2e-4); with 0.003, 1.5e-5–1.7e-4 (two of eleven near 1.6e-4) and fresh
    // derivatives with 0.003 9e-6–1.7e-4 (one of ten): a thick flasher's balance is a matter
    // of its impacts' chance. The thick starshade (60 s, `auto`): Newton failures 4,616 →
    // 1,534, 268 → 92 s (114 s with 0.003 and fresh derivatives; one run each, alone, Intel
    // Xeon 2-core, load ~1). The stiff grid of `tests/generated.rs` at rtol 1e-6 (kappa 1e-3):
    // energy drift 4.2e-6 of E₀ against 6.7e-6 before (3.5e-5 with 0.01 there).
    // A stage also stops when the error its iteration leaves, estimated from the iteration's
    // rate (`newton_error_left`, Hairer & Wanner's (8.10)), is within `kappa_left`, min(kappa,
    // 30 rtol): where the increment itself must be within `kappa`, an iteration contracting
    // at a rate θ is asked for 1/θ times more, one iteration more on most stages. At rtol 1e-4
    // (the thick flashers' default) both bounds are 0.003; tighter, the estimate's bound
    // shrinks with rtol (measured with implied derivatives): the stiff grid at
    // rtol 1e-6 drifted 1.1e-5 of E₀ with the estimate held to 0.001 (the bound is 1e-5),
    // 8.1e-6 with 3e-5 (6.1–6.7e-6 without the estimate; 4.2e-6 for the build before, whose
    // first stages started differently). With the state's correction after each step no longer
    // a restart (below), against the build before (Intel Xeon 2-core, load 1.0–1.3,
    // 2026-11-30, alternated): the thick flasher example at ten tolerances 2.92 → 2.36 s
    // (medians), right-hand sides 30,431–33,337 → 24,684–27,018, E + D 1.5e-5–1.7e-4 →
    // 3.0e-5–1.6e-4 relative (medians 4.9e-5 both); the 6 × 3 thick flasher 33.8 and 35.7 →
    // 30.7 and 28.1 s, 397,648 → 325,350 right-hand sides, E + D 3.1e-5 → 2.2e-5; the thick
    // starshade 92.0 → 76.1 s, 103,875 → 85,434, E + D 5.9e-5 → 6.2e-5.
    let kappa = 0.003_f64.min(rtol.sqrt());
    let kappa_left = kappa.min(30.0 * rtol);
    let diverging = if error_norm == ErrorNorm::Displacement { 2.0 } else { 1.0 };
    // Iterations before Newton gives up on a stage (then a fresh Jacobian, then half the
    // step). With contact a stage often converges linearly at a rate of 0.4-0.6 (the
    // Hunt-Crossley damping of the points touching changes fast with their depth, which the
    // Jacobian at the step's start does not follow), so that 8 gave up on stages that two
    // more iterations would have finished: the thick flasher example at rtol 0.75-1.25e-4
    // (11 runs, for its impacts make one run's time a matter of chance) took 3.99-4.27 s
    // with 10 against 3.98-6.74 s with 8 (medians 4.12 and 4.83 s; 12: 4.27, 16: 4.10); the
    // thick starshade's first 8 s at rtol 0.9-1.2e-4 151-270 s with 10 and 151-698 s with 8
    // (4 runs each, medians 171 and 167 s; the 698-s path made 13,532 Jacobians); the 5 x 2
    // and 6 x 3 thick flashers (defaults, 5 s) the same within 1 % (2-core AMD EPYC, load
    // ~1, 2026-11-28).
    const MAX_ITERATIONS: usize = 10;
    // Whether h was set to land on an event (exempt from the step floor), and whether the
    // last rejection was for a non-finite Newton iteration.
    let (mut forced, mut non_finite) = (false, false);
    // Whether the step before this one was rejected: a step accepted right after a rejection
    // may not grow (Hairer & Wanner's RADAU5 and DOPRI codes), which keeps a step that Newton
    // just failed from growing straight back into the failure.
    let mut after_rejection = false;
    loop {
        // The step lands on the end, or on the next break of the right-hand side.
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
        if (h - prepared_h).abs() > 1e-12 * h && !stats.refactor(&mut *newton, h * GAMMA) {
            return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
        }
        prepared_h = h;
        // Stages: Z_i − hγ f(y + Z_i) = h Σ_{j<i} a_ij f(y + Z_j).
        let mut converged = true;
        let mut max_iterations = 0;
        for i in 0..5 {
            for k in 0..n {
                let mut s = 0.0;
                for j in 0..i {
                    s += A[i][j] * fz[j][k];
                }
                rhs[k] = h * s;
            }
            // Start from the quadratic through 0 and the two stages before, at this stage's
            // abscissa (Z(c) = a c + b c²); the second stage from the first scaled to its
            // abscissa (Z_i ≈ c_i h f to first order), the first from h c_1 f(y).
            // (Extrapolating the previous step's cubic saved no iterations on stiff chains;
            // the quadratic saved 8-21 % of the iterations on the starshade flasher against
            // scaling the stage before.)
            if i > 1 {
                let (done, rest) = z.split_at_mut(i);
                let (c1, c2, c) = (C[i - 2], C[i - 1], C[i]);
                let l1 = c * (c - c2) / (c1 * (c1 - c2));
                let l2 = c * (c - c1) / (c2 * (c2 - c1));
                for ((zi, z1), z2) in rest[0].iter_mut().zip(&done[i - 2]).zip(&done[i - 1]) {
                    *zi = l1 * z1 + l2 * z2;
                }
            } else if i > 0 {
                let (done, rest) = z.split_at_mut(i);
                let scale = C[i] / C[i - 1];
                for (zi, zp) in rest[0].iter_mut().zip(&done[i - 1]) {
                    *zi = scale * zp;
                }
            } else {
                for (zi, f) in z[0].iter_mut().zip(&f0) {
                    *zi = C[0] * h * f;
                }
            }
            let mut previous = f64::INFINITY;
            let mut slow = false;
            let mut ok = false;
            // Slow iterations are mixed (`anderson.rs`), in the weights of the convergence
            // test (the rates scaled by h as it scales them).
            accelerate.reset();
            if i == 0 {
                for k in 0..n {
                    weights[k] = if rates[k] { h } else { 1.0 } / (atol + rtol * y[k].abs());
                }
            }
            for iteration in 1..=MAX_ITERATIONS {
                max_iterations = max_iterations.max(iteration);
                stats.newton_iterations += 1;
                for k in 0..n {
                    yi[k] = y[k] + z[i][k];
                }
                system.rhs(t + C[i] * h, &yi, &mut fz[i]);
                stats.rhs_evaluations += 1;
                for k in 0..n {
                    delta[k] = -(z[i][k] - h * GAMMA * fz[i][k] - rhs[k]);
                }
                newton.solve(&mut delta);
                let d = norm(&delta, &yi, &rates, h, rtol, atol);
                if !d.is_finite() || (previous.is_finite() && d > diverging * previous) {
                    non_finite = !d.is_finite();
                    break;
                }
                let done = d <= kappa || newton_error_left(d, previous) <= kappa_left;
                slow = slow || d > SLOW * previous;
                previous = d;
                if done || !slow {
                    for k in 0..n {
                        z[i][k] += delta[k];
                    }
                    if done {
                        ok = true;
                        break;
                    }
                } else {
                    accelerate.advance(&mut z[i], &delta, &weights);
                }
            }
            if !ok {
                converged = false;
                break;
            }
            // The stage's derivative afresh, f(y + Z_i) at the converged stage, as the method
            // defines it, not implied by the stage's equation, (Z_i − rhs_i)/(hγ) (the Z form of
            // Hairer & Wanner, *Solving Ordinary Differential Equations II*, §IV.8, one
            // evaluation fewer per stage, this code on 2026-11-30 and 12-01): an implied
            // derivative carries the residual Newton leaves in the stage's rates divided by
            // hγ into every later stage, and at kappa 0.003 of an rtol-1e-4 norm over
            // thousands of components that residual outweighed the method's own error. On the
            // thin 6 × 3 flasher under SDIRK4 at rtol 1e-4 (no contact) the panels were up to
            // 0.76 mm off a run at 1e-8 in its first 2 s with implied derivatives and 3.6 µm
            // with fresh ones, in the same steps (3,286 and 3,269); E + D 2.2e-4 → 2.9e-5
            // relative; 32 % more right-hand sides (docs/architecture.md, *Implicit
            // integration*, for the other cases and the cost; `tests/flasher.rs`).
            for k in 0..n {
                yi[k] = y[k] + z[i][k];
            }
            system.rhs(t + C[i] * h, &yi, &mut fz[i]);
            stats.rhs_evaluations += 1;
        }
        if let Some(contact_only) = retried.take() {
            contact_retries.record(contact_only, converged);
        }
        if !converged {
            stats.rejected += 1;
            stats.newton_failures += 1;
            after_rejection = true;
            forced = false;
            if fresh_jacobian {
                // The Jacobian is current: shrink the step.
                h *= 0.5;
                if !stats.refactor(&mut *newton, h * GAMMA) {
                    return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
                }
            } else {
                // Retry with a fresh Jacobian before shrinking the step.
                fresh_jacobian = true;
                stats.jacobians += 1;
                let contact_only = contact_retries.choose();
                retried = Some(contact_only);
                let ok = if contact_only {
                    newton.refresh_contact(t, &y, h * GAMMA)
                } else {
                    newton.prepare(t, &y, h * GAMMA)
                };
                if !ok {
                    return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
                }
            }
            prepared_h = h;
            continue;
        }
        // Error: the difference to the embedded solution, filtered through W⁻¹ (Hairer's
        // remedy for overestimation on stiff components).
        for k in 0..n {
            let mut e = 0.0;
            for j in 0..5 {
                e += (A[4][j] - B_HAT[j]) * fz[j][k];
            }
            err[k] = h * e;
        }
        newton.solve(&mut err);
        // `yi` is y + Z_5 here, the last stage's fresh evaluation formed it: the step's end.
        // A NaN error (an overflow in the stages) rejects the step (`max` would drop it).
        let e = norm(&err, &yi, &rates, h, rtol, atol);
        let e = if e.is_nan() { f64::INFINITY } else { e.max(1e-10) };
        let mut factor = (0.9 * e.powf(-0.25)).clamp(0.2, 4.0);
        if e <= 1.0 {
            if after_rejection {
                factor = factor.min(1.0);
                after_rejection = false;
            }
            stats.accepted += 1;
            (forced, non_finite) = (false, false);
            let t_prev = t;
            // The stage-based cubic (DENSE) y + θ e1 + θ² e2 + θ³ e3 with e1 + e2 + e3 = Z_5,
            // in the Hermite form y + θ (c1 + (1 − θ)(c2 + θ c3)) that `Step` evaluates:
            // c1 = Z_5, c2 = e1 − Z_5, c3 = −e3.
            for k in 0..n {
                let ydiff = z[4][k];
                let (mut e1, mut e3) = (0.0, 0.0);
                for (i, zi) in z.iter().enumerate() {
                    e1 += DENSE[0][i] * zi[k];
                    e3 += DENSE[2][i] * zi[k];
                }
                cont[0][k] = y[k];
                cont[1][k] = ydiff;
                cont[2][k] = e1 - ydiff;
                cont[3][k] = -e3;
            }
            y.copy_from_slice(&yi);
            f0.copy_from_slice(&fz[4]);
            t = if landing { stop } else { t + h };
            stats.last_step = t - t_prev;
            if let Some((count, below)) = limits.hand_back_below {
                short_steps = if t - t_prev < below && !landing { short_steps + 1 } else { 0 };
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
                    t = tr;
                    y = yr;
                    system.rhs(t, &y, &mut f0);
                    stats.rhs_evaluations += 1;
                }
                // A small correction of the state (the momenta restored after every implicit
                // step, locked directions projected): the stages go on from the corrected
                // state, and f0, which only starts the next step's first stage, stays the
                // last stage's derivative (it differs from f at the corrected state by J
                // times the correction). A restart's fresh f0 cost one right-hand side per
                // step, 4–5 % of the thick flasher example's and of the 6 × 3's (2026-11-30).
                Control::Correct { y: yc } => y = yc,
                Control::Truncate { t: tt } => {
                    // Take the step again from its start to end at tt.
                    stats.stopped_at = None;
                    y.copy_from_slice(&cont[0]);
                    t = t_prev;
                    system.rhs(t, &y, &mut f0);
                    stats.rhs_evaluations += 1;
                    stats.accepted -= 1;
                    h = tt - t_prev;
                    forced = true;
                    continue;
                }
            }
            stats.next_step = h * factor;
            if t >= tf || stats.stopped_at.is_some() {
                stats.rhs_evaluations += newton.evaluations();
                return Ok(stats);
            }
            // Keep h (and the factorization) for small changes.
            if !(1.0..=1.2).contains(&factor) {
                h *= factor;
            }
            // A fresh Jacobian only when Newton needed many iterations; otherwise the old one
            // serves (Hairer's strategy for SDIRK codes). "Many" is more than 4: with contact
            // a Jacobian costs ~40 right-hand sides (every point's derivatives), and at 4 the
            // thick flasher example took 4.50-4.55 s against 5.96-6.67 s at 3 (738 Jacobians
            // against 1,209), the 5 × 2 thick flasher the same, the contact z-fold
            // and panel-hub examples under SDIRK4 3-5 % longer; at 5, those two 10 % longer
            // (2-core AMD EPYC, load 1.1-1.5, two alternated rounds). The thick starshade
            // (60 s, `auto`) took 249.7 s against 228.4 s (one run each, load ~1: the same
            // Jacobians, more Newton failures): a trade, kept for the stowed-contact case.
            // Since Newton stops at `kappa` (0.003 of the tolerance, not 0.03: above) its
            // stages take about one iteration more, and "many" is more than 5: the 6 × 3
            // thick flasher 7,580 → 5,405 Jacobians, 37.1 and 42.5 s → 35.1 and 34.0 s (two
            // alternated rounds), the thick starshade 1,682 → 1,381 Jacobians, 121 → 92 s
            // (one run each, the first beside other work), the example 629–659 → 413–430
            // Jacobians for 10–15 % more right-hand sides, the same wall time (Intel Xeon
            // 2-core, load 1.0–1.6, 2026-11-30). The stop on the rate's estimate (above) gave
            // the iteration back, and 4 was measured again: the example's right-hand sides
            // 12 % fewer at the same wall time (2.21 against 2.23 s, medians of ten
            // tolerances), the 6 × 3 30.5 against 28.6 s (6,487 Jacobians against 4,650; one
            // run each, load ~1.1): 5 stays.
            fresh_jacobian = false;
            if max_iterations > 5 {
                fresh_jacobian = true;
                stats.jacobians += 1;
                if !newton.prepare(t, &y, h * GAMMA) {
                    return Err(OdeError::SingularNewton { t, h, block: newton.singular_block() });
                }
                prepared_h = h;
            }
        } else {
            stats.rejected += 1;
            after_rejection = true;
            (forced, non_finite) = (false, !e.is_finite());
            h *= factor.min(1.0);
        }
    }
}

/// The error a simplified Newton iteration leaves once its increment of norm `d` is
/// applied, estimated from its rate θ = `d` / `previous` (the increment before) as
/// θ/(1 − θ)·`d`, the sum of the geometric series of the increments to come (Hairer & Wanner,
/// *Solving Ordinary Differential Equations II*, §IV.8, (8.10)–(8.11)); `d` itself for the
/// first iteration (no rate yet: `previous` infinite) and for one not contracting (θ ≥ 1).
fn newton_error_left(d: f64, previous: f64) -> f64 {
    let theta = d / previous;
    if previous.is_finite() && theta < 1.0 { d * theta / (1.0 - theta) } else { d }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::DenseNewton;

    /// The error left after an increment, for increments shrinking geometrically at a rate θ,
    /// is the sum of the increments still to come (to round-off); the first increment and
    /// one not contracting are their own estimate.
    #[test]
    fn the_error_left_is_the_rest_of_the_series() {
        for theta in [0.05, 0.3, 0.7, 0.95] {
            let d = |k: i32| 2.0 * f64::powi(theta, k);
            for k in 1..6 {
                let rest: f64 = (k + 1..2000).map(d).sum();
                let left = newton_error_left(d(k), d(k - 1));
                assert!((left - rest).abs() <= 1e-12 * rest, "θ {theta}, k {k}: {left} vs {rest}");
            }
        }
        assert_eq!(newton_error_left(0.5, f64::INFINITY), 0.5);
        assert_eq!(newton_error_left(0.5, 0.4), 0.5);
    }

    /// The tableau's order conditions up to order 4 (stiffly accurate: b = last row).
    #[test]
    fn tableau_satisfies_order_conditions() {
        let b = A[4];
        let sum = |f: &dyn Fn(usize) -> f64| (0..5).map(f).sum::<f64>();
        for (i, row) in A.iter().enumerate() {
            assert!((row.iter().sum::<f64>() - C[i]).abs() < 1e-14, "row {i} sums to c");
        }
        assert!((sum(&|i| b[i]) - 1.0).abs() < 1e-14);
        assert!((sum(&|i| b[i] * C[i]) - 0.5).abs() < 1e-14);
        assert!((sum(&|i| b[i] * C[i] * C[i]) - 1.0 / 3.0).abs() < 1e-14);
        let ac = |i: usize| (0..5).map(|j| A[i][j] * C[j]).sum::<f64>();
        assert!((sum(&|i| b[i] * ac(i)) - 1.0 / 6.0).abs() < 1e-14);
        assert!((sum(&|i| b[i] * C[i].powi(3)) - 0.25).abs() < 1e-13);
        assert!((sum(&|i| b[i] * C[i] * ac(i)) - 0.125).abs() < 1e-13);
        let ac2 = |i: usize| (0..5).map(|j| A[i][j] * C[j] * C[j]).sum::<f64>();
        assert!((sum(&|i| b[i] * ac2(i)) - 1.0 / 12.0).abs() < 1e-13);
        let aac = |i: usize| (0..5).map(|j| A[i][j] * ac(j)).sum::<f64>();
        assert!((sum(&|i| b[i] * aac(i)) - 1.0 / 24.0).abs() < 1e-13);
        // Embedded order 3.
        let bh = B_HAT;
        assert!((bh.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        assert!(((0..5).map(|i| bh[i] * C[i]).sum::<f64>() - 0.5).abs() < 1e-14);
        assert!(((0..5).map(|i| bh[i] * C[i] * C[i]).sum::<f64>() - 1.0 / 3.0).abs() < 1e-13);
        assert!(((0..5).map(|i| bh[i] * ac(i)).sum::<f64>() - 1.0 / 6.0).abs() < 1e-13);
    }

    /// The dense output's weights `b_i(θ) = Σ_k θ^k β_k,i` with `β_k = A^T DENSE_k`: order 3 at
    /// every θ and the method's weights at θ = 1 (to 1e-12: the coefficients are given to 17
    /// digits).
    #[test]
    fn dense_output_meets_the_order_conditions() {
        let beta: Vec<[f64; 5]> =
            DENSE.iter().map(|d| std::array::from_fn(|i| (0..5).map(|j| A[j][i] * d[j]).sum::<f64>())).collect();
        let ac: [f64; 5] = std::array::from_fn(|i| (0..5).map(|j| A[i][j] * C[j]).sum());
        let sum = |k: usize, w: &dyn Fn(usize) -> f64| (0..5).map(|i| beta[k][i] * w(i)).sum::<f64>();
        // Per power θ^(k+1): Σ β = [1, 0, 0], Σ β c = [0, 1/2, 0], Σ β c² = [0, 0, 1/3],
        // Σ β Ac = [0, 0, 1/6].
        let targets = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.5, 0.0, 0.0], [0.0, 0.0, 1.0 / 3.0, 1.0 / 6.0]];
        for (k, target) in targets.iter().enumerate() {
            let got = [sum(k, &|_| 1.0), sum(k, &|i| C[i]), sum(k, &|i| C[i] * C[i]), sum(k, &|i| ac[i])];
            for (g, t) in got.iter().zip(target) {
                assert!((g - t).abs() < 1e-12, "power {}: {got:?} vs {target:?}", k + 1);
            }
        }
        for i in 0..5 {
            let at_one = beta[0][i] + beta[1][i] + beta[2][i];
            assert!((at_one - A[4][i]).abs() < 1e-12, "b_{i}(1) = {at_one} vs {}", A[4][i]);
        }
    }

    /// Between steps that stride over a damped stiff vibration, the dense output stays on the
    /// motion: the stiff pair at rtol 1e-4 takes steps hundreds of times the stiff period
    /// (up to 0.41 s), and at every step's quarter, half and three quarters the stiff rate x2'
    /// stays within 1e-6 of its slow-manifold value 1e-3 x1' (|x2'| ≤ 1e-3; measured 6.8e-8,
    /// against 1.4e-6 for the cubic Hermite through f at both ends that this replaced, whose
    /// term h f carries the stiff acceleration the step's end leaves), and the soft mode within
    /// 1e-3 of cos t (2.3e-4: the tolerance's).
    #[test]
    fn dense_output_between_long_steps_follows_the_stiff_manifold() {
        let (mut worst_rate, mut worst_soft, mut longest) = (0.0f64, 0.0f64, 0.0f64);
        let mut out = vec![0.0; 4];
        two_scales(1e-4, 1e-4, Limits::default(), |s: &Step<'_>| -> Result<Control, ()> {
            longest = longest.max(s.t - s.t_prev);
            for f in [0.25, 0.5, 0.75] {
                let t = s.t_prev + f * (s.t - s.t_prev);
                s.interpolate(t, &mut out);
                worst_rate = worst_rate.max((out[3] - 1e-3 * out[1]).abs());
                worst_soft = worst_soft.max((out[0] - t.cos()).abs());
            }
            Ok(Control::Continue)
        })
        .unwrap();
        assert!(longest > 100.0 * std::f64::consts::TAU / 1e4, "steps up to {longest:e} s");
        assert!(worst_rate < 1e-6, "stiff rate off its manifold by {worst_rate:e} between steps");
        assert!(worst_soft < 1e-3, "soft mode off by {worst_soft:e} between steps");
    }

    /// A small correction after every step (as the momenta's restoration) costs no
    /// right-hand side: the next step's first stage starts from the last stage's derivative,
    /// not from f evaluated afresh at the corrected state. With every step corrected by a
    /// relative 1e-12, the run takes as many right-hand sides as without (a restart would
    /// take one more per step) and ends within 1e-8 of it (the corrections add up to 1e-12
    /// per step, and the two paths' steps may differ within the tolerance, 1e-8).
    #[test]
    fn a_small_correction_does_not_restart_the_method() {
        let mut ends = Vec::new();
        let mut counts = Vec::new();
        for correct in [false, true] {
            let mut last = vec![0.0; 4];
            let stats = two_scales(1e-8, 1e-8, Limits::default(), |s: &Step<'_>| -> Result<Control, ()> {
                last.copy_from_slice(s.y);
                if !correct {
                    return Ok(Control::Continue);
                }
                let y: Vec<f64> = s.y.iter().map(|v| v * (1.0 + 1e-12)).collect();
                last.copy_from_slice(&y);
                Ok(Control::Correct { y })
            })
            .unwrap();
            counts.push((stats.rhs_evaluations, stats.accepted));
            ends.push(last);
        }
        let (plain, corrected) = (counts[0], counts[1]);
        let per_step = |(rhs, steps): (usize, usize)| rhs as f64 / steps as f64;
        assert!(
            per_step(corrected) < per_step(plain) + 0.5,
            "right-hand sides per step: {} corrected, {} plain",
            per_step(corrected),
            per_step(plain)
        );
        for (a, b) in ends[0].iter().zip(&ends[1]) {
            assert!((a - b).abs() < 1e-8, "{:?} vs {:?}", ends[0], ends[1]);
        }
    }

    /// A stiff spring–mass pair: a soft mode (ω = 1) and a stiff one (ω = 1e4), the stiff one
    /// started at rest. An explicit method needs steps below 1e-4; SDIRK4 follows the soft
    /// mode at the tolerance with steps set by accuracy only.
    struct TwoScales;
    impl OdeSystem for TwoScales {
        fn rhs(&self, _t: f64, y: &[f64], d: &mut [f64]) {
            // x1'' = −x1 (soft), x2'' = −1e8 (x2 − 0.001 x1) (stiff, slaved to x1)
            d[0] = y[1];
            d[1] = -y[0];
            d[2] = y[3];
            d[3] = -1e8 * (y[2] - 1e-3 * y[0]) - 2e3 * y[3];
        }
    }

    /// SDIRK4 (dense Newton) on [`TwoScales`] from x1 = 1, x2 = 1e-3 at rest over 10 s.
    fn two_scales(
        rtol: f64,
        atol: f64,
        limits: Limits,
        on_step: impl FnMut(&Step<'_>) -> Result<Control, ()>,
    ) -> Result<Stats, OdeError<()>> {
        let sys = TwoScales;
        let mut newton = DenseNewton::new(&sys, 4);
        integrate_sdirk4(
            &sys,
            &mut newton,
            rtol,
            atol,
            ErrorNorm::State,
            limits,
            0.0,
            10.0,
            &[1.0, 0.0, 1e-3, 0.0],
            on_step,
        )
    }

    #[test]
    fn stiff_problem_takes_accuracy_limited_steps() {
        let mut end = vec![];
        let stats = two_scales(1e-8, 1e-10, Limits::default(), |s: &Step<'_>| -> Result<Control, ()> {
            end = s.y.to_vec();
            Ok(Control::Continue)
        })
        .unwrap();
        let exact = 10f64.cos();
        assert!((end[0] - exact).abs() < 1e-6, "x1(10) = {} vs {exact}", end[0]);
        // The stiff component follows its slow manifold: x2 = 1e-3 x1 − (x2'' + 2e3 x2')/1e8
        // ≈ (1e-3 + 1e-11) x1 − 2e-8 x1', to ~1e-12.
        let manifold = (1e-3 + 1e-11) * end[0] - 2e-8 * end[1];
        assert!((end[2] - manifold).abs() < 1e-10, "x2 {} vs {manifold}", end[2]);
        eprintln!(
            "SDIRK4 on the stiff pair: {} accepted, {} rejected, {} rhs",
            stats.accepted, stats.rejected, stats.rhs_evaluations
        );
        // Explicit RK would need > 10 / 2.8e-4 ≈ 35,000 steps; accuracy-limited SDIRK4 far fewer.
        assert!(stats.accepted < 3000, "{} steps", stats.accepted);
    }

    /// With `hand_back_below`, the integration stops (Ok, `stopped_at` set) once that many
    /// accepted steps in a row were shorter than the given step, and goes on otherwise.
    #[test]
    fn hands_back_after_short_steps() {
        let sys = TwoScales;
        let mut newton = DenseNewton::new(&sys, 4);
        let limits = Limits { hand_back_below: Some((5, 1.0)), ..Limits::default() };
        let mut last = 0.0;
        let stats = integrate_sdirk4(
            &sys,
            &mut newton,
            1e-8,
            1e-10,
            ErrorNorm::State,
            limits,
            0.0,
            10.0,
            &[1.0, 0.0, 1e-3, 0.0],
            |s: &Step<'_>| -> Result<Control, ()> {
                last = s.t;
                Ok(Control::Continue)
            },
        )
        .unwrap();
        assert_eq!(stats.accepted, 5);
        assert_eq!(stats.stopped_at, Some(last));
        assert!(last < 10.0);
        let limits = Limits { hand_back_below: Some((5, 1e-9)), ..Limits::default() };
        let mut newton = DenseNewton::new(&sys, 4);
        let stats = integrate_sdirk4(
            &sys,
            &mut newton,
            1e-8,
            1e-10,
            ErrorNorm::State,
            limits,
            0.0,
            10.0,
            &[1.0, 0.0, 1e-3, 0.0],
            |_: &Step<'_>| -> Result<Control, ()> { Ok(Control::Continue) },
        )
        .unwrap();
        assert_eq!(stats.stopped_at, None);
    }
}

//! `integrator = "auto"`: DOP853 while it pays, an implicit method where stiffness limits
//! DOP853's steps (adaptive generalized-α, or SDIRK4 with contact: [`implicit_method`]),
//! and back when the implicit steps shrink to where DOP853 would be cheaper.
//!
//! The switch to the implicit method is Hairer's stiffness test in DOP853 (`dop853.f`: h·|λ|
//! beyond the stability boundary, 6.1, on 15 accepted steps in a row), the same test that
//! the report's stiffness note prints. The switch back is a cost comparison made from step
//! sizes alone, so that a run is the same on every machine: an implicit step costs about
//! [`implicit_method`]'s cost in DOP853 steps, so the implicit method hands back once
//! [`HAND_BACK_STEPS`] of its steps in a row were shorter than that many times the step
//! DOP853 was held to by stability. After each hand-back DOP853 runs at least twice as many
//! steps as before it may switch again, so two methods of equal cost cannot ping-pong, up to
//! 16 times its first watch ([`dop853_watch`]): DOP853 held by stability is the costlier
//! mistake.
//! Every switch is recorded for the report ([`MethodSpan`]).
//!
//! Why generalized-α without contact and not SDIRK4 (which it was until generalized-α had
//! error control): on the
//! starshade flasher (10 s, the Exudyn comparison's case) it reached 1e-5 m where SDIRK4
//! stopped at 2.1e-5 m at rtol 1e-7 in twice the time; its ρ∞ = 0.9 damps the stiff
//! vibrations it steps over over tens of steps, where SDIRK4 (L-stable) removes them at
//! once and took steps resolving their rates (docs/scenario.md has the table).

use super::report::{MethodSpan, SimError};
use super::settings::RunSettings;
use super::stopped::stopped;
use super::stream::{Restore, StreamOut, Tracked};
use crate::dynamics::newton::GraphNewton;
use crate::integrate::galpha::DEFAULT_RHO_INF;
use crate::integrate::{AlphaSteps, Limits, Method, Stats, integrate, integrate_generalized_alpha, integrate_sdirk4};

/// The implicit method of `auto` for a model, and what one of its steps costs in DOP853
/// steps (12 right-hand sides each).
///
/// Without contact, adaptive generalized-α: about 3.5 Newton iterations of one right-hand
/// side and one sparse solve each, one right-hand side and one solve for the error
/// estimate, and a Jacobian every 30–150 steps: 0.78 ms a step on the starshade flasher
/// against DOP853's 0.84 ms (rtol 1e-7 and 1e-10, same machine and load), so 1. (With
/// SDIRK4's 3 the stiff grid at rtol 1e-5 handed back to DOP853 18 times, whose steps at
/// the stability limit then let the energy grow 35-fold.)
///
/// With contact, SDIRK4 (18 right-hand sides, 14 sparse solves and a share of Jacobians a
/// step: 3): its L-stable steps through impacts cost less than generalized-α's on both
/// contact examples that switch (`bench/auto_examples.py`, medians of 3: the thick flasher
/// 4.99 s against 7.97 s, the contact z-fold 6.46 s against 8.31 s).
pub fn implicit_method(model: &crate::model::Model) -> (&'static str, f64) {
    if model.contact.is_some() { ("sdirk4", 3.0) } else { ("generalized-alpha", 1.0) }
}

/// Accepted SDIRK4 steps in a row shorter than the break-even step before it hands back.
pub const HAND_BACK_STEPS: usize = 20;

/// The fewest DOP853 steps before the first switch (and the base of the doubling after
/// each hand-back).
pub const FIRST_WATCH_STEPS: usize = 15;

/// How many times the DOP853 watch doubles at most ([`dop853_watch`]).
pub const MOST_DOUBLINGS: usize = 4;

/// The fewest DOP853 steps before it may switch to the implicit method after `hand_backs`
/// hand-backs: [`FIRST_WATCH_STEPS`] doubled at each, so that two methods of equal cost
/// cannot ping-pong, but at most [`MOST_DOUBLINGS`] times (240 steps). Without the cap a
/// run whose implicit steps shrink at every impact (the thick starshade with
/// `contact.slip_speed = 0.01`: 11 hand-backs after it reached flat) held DOP853 at its
/// stability limit for 2¹⁰ × 15 steps and more: 64,781 steps and 227 s, against 6,133 steps
/// and 101 s with the cap (one run each, AMD EPYC 2-core, load ~1, 2026-12-01); runs with four hand-backs
/// or fewer are as before.
pub fn dop853_watch(hand_backs: usize) -> usize {
    FIRST_WATCH_STEPS << hand_backs.min(MOST_DOUBLINGS)
}

/// Integrates from `(t0, y0)` to `t1` switching between DOP853 and SDIRK4 at `rtol`, `atol`;
/// the spans each method took are appended to `spans`.
#[allow(clippy::too_many_arguments)]
pub(super) fn integrate_auto(
    out: &mut StreamOut<'_, '_, '_, '_>,
    settings: &RunSettings,
    rtol: f64,
    atol: f64,
    t0: f64,
    t1: f64,
    y0: &[f64],
    first_step: Option<f64>,
    end: &mut Vec<f64>,
) -> Result<(Stats, usize), SimError> {
    let dynamics = out.dynamics;
    let model = dynamics.model();
    let base = settings.limits(model);
    let mut newton = GraphNewton::new_exact(dynamics, model, dynamics);
    let mut total = Stats::default();
    let (mut t, mut first) = (t0, first_step);
    let mut y = y0.to_vec();
    // Go on in the method of the span before (a stepped run's next piece).
    let spans = &out.s.spans;
    let (implicit_name, step_cost) = implicit_method(model);
    let mut implicit = spans.last().is_some_and(|s| s.method == implicit_name);
    let mut stable_step = spans.iter().rev().find_map(|s| s.stable_step).unwrap_or(f64::INFINITY);
    let mut hand_backs = spans.iter().filter(|s| s.method == "dop853").count().saturating_sub(1);
    if spans.is_empty() {
        out.s.spans.push(MethodSpan { from: t0, method: "dop853", why: "the start".into(), stable_step: None });
    }
    loop {
        let steps_so_far = total.accepted + total.rejected;
        let max_steps = base.max_steps.saturating_sub(steps_so_far).max(1);
        out.s.restore = if implicit { Restore::EveryStep } else { Restore::OnDrift };
        out.s.method = if implicit { implicit_name } else { "dop853" };
        let mut tracked = Tracked { out: &mut *out, end: &mut *end };
        let (limits, result) = if implicit {
            let limits = Limits {
                first_step: first,
                max_steps,
                hand_back_below: stable_step.is_finite().then_some((HAND_BACK_STEPS, step_cost * stable_step)),
                ..base
            };
            let on_step = |s: &crate::integrate::Step<'_>| tracked.on_step(s);
            let r = if implicit_name == "sdirk4" {
                integrate_sdirk4(dynamics, &mut newton, rtol, atol, settings.error_norm, limits, t, t1, &y, on_step)
            } else {
                let steps = AlphaSteps::Adaptive(settings.error_norm);
                integrate_generalized_alpha(
                    dynamics,
                    &mut newton,
                    steps,
                    DEFAULT_RHO_INF,
                    rtol,
                    atol,
                    limits,
                    t,
                    t1,
                    &y,
                    on_step,
                )
            };
            (limits, r)
        } else {
            let limits =
                Limits { first_step: first, max_steps, stop_when_stiff: Some(dop853_watch(hand_backs)), ..base };
            let r = integrate(
                dynamics,
                Method::Dop853 { rtol, atol },
                limits,
                t,
                t1,
                &y,
                |s: &crate::integrate::Step<'_>| tracked.on_step(s),
            );
            (limits, r)
        };
        let stats = result.map_err(|e| stopped(dynamics, settings, &limits, e))?;
        total.absorb(&stats);
        let Some(at) = stats.stopped_at else { break };
        t = at;
        y.clone_from(end);
        if implicit {
            out.s.spans.push(MethodSpan {
                from: t,
                method: "dop853",
                why: format!(
                    "{HAND_BACK_STEPS} implicit steps in a row below {:.3e} s, where DOP853 costs less",
                    step_cost * stable_step
                ),
                stable_step: None,
            });
            hand_backs += 1;
            first = Some(stable_step);
        } else {
            stable_step = stats.last_step;
            out.s.spans.push(MethodSpan {
                from: t,
                method: implicit_name,
                why: format!("stiff: DOP853's steps ({:.3e} s) held by stability, not accuracy", stats.last_step),
                stable_step: Some(stats.last_step),
            });
            first = Some(4.0 * stats.last_step);
        }
        implicit = !implicit;
    }
    total.stiff_from = total.stiff_from.or(out.s.spans.iter().find(|s| s.method == implicit_name).map(|s| s.from));
    Ok((total, newton.jacobian_counts().1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The DOP853 watch doubles at each hand-back from 15 steps and stops at 240: a run
    /// whose implicit method hands back at every impact is never held in DOP853 for
    /// thousands of steps at its stability limit.
    #[test]
    fn the_watch_doubles_up_to_its_cap() {
        assert_eq!(dop853_watch(0), FIRST_WATCH_STEPS);
        assert_eq!(dop853_watch(1), 2 * FIRST_WATCH_STEPS);
        assert_eq!(dop853_watch(MOST_DOUBLINGS), 240);
        for hand_backs in [MOST_DOUBLINGS + 1, 11, 40, usize::MAX] {
            assert_eq!(dop853_watch(hand_backs), 240, "after {hand_backs} hand-backs");
        }
    }
}

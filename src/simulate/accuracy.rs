//! `run.position_tolerance`: a run whose bodies' positions are estimated to be within a
//! stated distance of the exact motion, by running it again at a tighter tolerance
//! (docs/scenario.md, *A position tolerance*).
//!
//! `rtol` and `atol` bound each step's error, not the error in the bodies' positions over a
//! run, which is the steps' errors carried forward and added up; how the two relate depends
//! on the structure and the method (3–40 × rtol in metres with generalized-α on the starshade
//! and a stiff grid, 1e-2–0.2 × with DOP853, and up to 1e5 × where the motion amplifies
//! errors, as the small flasher's does from 1.5 s on). So a candidate run at `τ` is checked by
//! a run at `τ / r` (r = 4), and the candidate's error estimated from their largest
//! difference by tolerance proportionality (Hairer, Nørsett & Wanner, *Solving ODEs I*,
//! §II.4: with each step's error controlled, the global error goes as `C τ^q`, `q = p/(p+1)`
//! for a method of order p): `|x_A − x_B| ≈ e_A − e_B = e_A (1 − r^−q)`, so
//! `e_A ≈ |x_A − x_B| / (1 − r^−q)` (global error assessment by reintegration, Shampine,
//! *Numerical Solution of Ordinary Differential Equations*, 1994, §5.5.3). The estimate is of
//! the *coarser* run, and depends on q only through `1/(1 − r^−q)`, between 1 (large q) and
//! 1.66 (q = 2/3, the adaptive generalized-α's: second order with a third-order error
//! estimate), which is what is assumed: the estimate errs on the safe side, by at most 1.66.
//! A candidate whose estimate is at most the tolerance is the output (its rows are held in
//! memory until then; nothing is written before). Otherwise the next candidate's tolerance
//! is aimed at 2/3 of the tolerance by the power law, with the exponent the last two
//! candidates show (within [0.4, 2]; 2/3 at first), at most 1,000 times tighter at once; a
//! check looser than that aim becomes the next candidate itself. A candidate that passes
//! far within the tolerance is loosened (`loosen`). A run that fails (a loose
//! tolerance can make a hysteresis law's events chatter) is made again at a tenth of its
//! tolerance while runs are left. A tolerance not reached within [`MAX_RUNS`] runs or at
//! [`TIGHTEST`] stops with what was estimated, and says so when the estimates did not
//! fall as the candidates tightened ([`stagnates`]).

use super::pace::ProgressFn;
use super::report::{PositionAccuracy, RunReport, SimError};
use super::run::{Sink, simulate_once};
use super::settings::{Integrator, RunSettings};
use crate::kinematics::InitialConditions;
use crate::math::Vec3;
use crate::model::Model;
use crate::observe::Observation;

/// The order of the global error in the tolerance that the estimate assumes (see the module
/// documentation).
pub const TOLERANCE_ORDER: f64 = 2.0 / 3.0;

/// A candidate run is checked by one at its tolerance over this.
pub const RATIO: f64 = 4.0;

/// The first candidate's tolerance, as a fraction of the position tolerance in metres
/// (docs/scenario.md's rule of thumb, rtol = ε/10, from the starshade and the stiff grid).
pub const FIRST_GUESS: f64 = 0.1;

/// The first candidate's tolerance for DOP853 and Dormand–Prince 5(4) chosen by name, as a
/// fraction of the position tolerance: their error at a given tolerance is far smaller
/// (1e-2–0.2 of it in metres on the examples' structures at ε/10).
pub const FIRST_GUESS_EXPLICIT: f64 = 1.0;

/// The first candidate's rtol = atol for `integrator` and a position tolerance of
/// `tolerance` m (also what a scenario's trial runs at).
pub fn first_tolerance(integrator: Integrator, tolerance: f64) -> f64 {
    let guess = match integrator {
        Integrator::Dop853 { .. } | Integrator::Dopri5 { .. } => FIRST_GUESS_EXPLICIT,
        _ => FIRST_GUESS,
    };
    clamp(guess * tolerance)
}

/// A candidate's tolerance kept within [RATIO × TIGHTEST, LOOSEST], so that every check is
/// RATIO tighter and still a run's.
fn clamp(tolerance: f64) -> f64 {
    tolerance.clamp(RATIO * TIGHTEST, LOOSEST)
}

/// The most runs made before giving up.
pub const MAX_RUNS: usize = 8;

/// The loosest tolerance a run is given (the error estimate needs the error to follow its
/// power law, which a looser run leaves).
pub const LOOSEST: f64 = 1e-2;

/// The tightest tolerance a run is given: below it the runs' round-off, not their steps,
/// sets the error, and adaptive generalized-α takes millions of steps.
pub const TIGHTEST: f64 = 1e-12;

/// One run's result, held until it is accepted or superseded.
struct Trial {
    tolerance: f64,
    rows: Vec<Observation>,
    report: RunReport,
}

/// Runs a simulation from `ic`, streaming every output row to `sink`. `progress` is called
/// after each accepted step with the time reached, the step and what holds it back
/// ([`super::Progress`]); returning `ControlFlow::Break` stops the run with
/// [`SimError::Interrupted`] (how a Ctrl-C reaches it).
///
/// With [`RunSettings::position_tolerance`] the run is made more than once
/// (this module), and only the accepted one's rows reach `sink`.
pub fn simulate(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    sink: &mut dyn Sink,
    progress: Option<&mut ProgressFn<'_>>,
) -> Result<RunReport, SimError> {
    match settings.position_tolerance {
        Some(tolerance) => simulate_to_position(model, ic, settings, tolerance, sink, progress),
        None => simulate_once(model, ic, settings, sink, progress),
    }
}

/// The integrator with `rtol = atol = tolerance`.
pub fn with_tolerance(integrator: Integrator, tolerance: f64) -> Integrator {
    let (rtol, atol) = (tolerance, tolerance);
    match integrator {
        Integrator::Dop853 { .. } => Integrator::Dop853 { rtol, atol },
        Integrator::Dopri5 { .. } => Integrator::Dopri5 { rtol, atol },
        Integrator::Sdirk4 { .. } => Integrator::Sdirk4 { rtol, atol },
        Integrator::Auto { .. } => Integrator::Auto { rtol, atol },
        Integrator::GeneralizedAlpha { step, rho_inf, .. } => {
            Integrator::GeneralizedAlpha { step, rho_inf, rtol, atol }
        }
        fixed @ Integrator::Rk4 { .. } => fixed,
    }
}

/// The largest distance between two runs' bodies' centres of mass over their rows, m.
fn largest_difference(a: &[Observation], b: &[Observation]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| x.body_r_in_n.iter().zip(&y.body_r_in_n).map(|(p, q): (&Vec3, &Vec3)| (p - q).norm()))
        .fold(0.0, f64::max)
}

/// The coarser run's error from two runs' largest difference `difference` (m) and their
/// tolerances' ratio `ratio` (> 1), by tolerance proportionality: `e_A = d / (1 − r^−q)`.
pub fn coarser_error(difference: f64, ratio: f64) -> f64 {
    difference / (1.0 - ratio.powf(-TOLERANCE_ORDER))
}

/// Runs `model` from `ic` as [`super::simulate`] does, to `tolerance` (m) in every body's
/// position (see the module documentation), streaming the accepted run's rows to `sink`.
/// The report is the accepted run's, its wall time that of every run, with
/// [`RunReport::position_accuracy`] saying what was estimated.
pub fn simulate_to_position(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    tolerance: f64,
    sink: &mut dyn Sink,
    mut progress: Option<&mut ProgressFn<'_>>,
) -> Result<RunReport, SimError> {
    if matches!(settings.integrator, Integrator::Rk4 { .. } | Integrator::GeneralizedAlpha { step: Some(_), .. }) {
        return Err(SimError::Physics(format!(
            "run.position_tolerance needs an adaptive integrator; '{}' at a fixed run.step has no tolerance to set",
            settings.integrator.name()
        )));
    }
    let mut run = |tol: f64| -> Result<Trial, SimError> {
        let settings =
            RunSettings { integrator: with_tolerance(settings.integrator, tol), position_tolerance: None, ..*settings };
        let mut rows = Vec::new();
        let mut keep = |o: &Observation| -> Result<(), String> {
            rows.push(o.clone());
            Ok(())
        };
        let report = simulate_once(model, ic, &settings, &mut keep, progress.as_deref_mut())?;
        Ok(Trial { tolerance: tol, rows, report })
    };
    // Candidates and their checks: a candidate at τ is checked by a run at τ / RATIO, and its
    // error estimated from their difference; a candidate off the mark is replaced by one at
    // the tolerance the power law says (the check itself, when that is looser than it).
    // Every run made: (tolerance, wall s).
    let mut runs: Vec<(f64, f64)> = Vec::new();
    // A run at `tol`, or where it fails (a loose tolerance can: a hysteresis law's events
    // chattering, a step budget spent on them), at a tenth of it while runs are left; the
    // last failure is returned with the tolerances tried.
    let mut attempt = |tol: f64, runs: &mut Vec<(f64, f64)>| -> Result<Trial, SimError> {
        let mut tol = tol;
        loop {
            let start = std::time::Instant::now();
            match run(tol) {
                Ok(trial) => {
                    runs.push((tol, trial.report.wall_seconds));
                    return Ok(trial);
                }
                Err(e) => {
                    runs.push((tol, start.elapsed().as_secs_f64()));
                    let retry = matches!(e, SimError::Integrator { .. } | SimError::Physics(_));
                    if retry && runs.len() < MAX_RUNS && tol / 10.0 >= TIGHTEST {
                        tol /= 10.0;
                        continue;
                    }
                    let tried = runs.iter().map(|r| format!("{:.1e}", r.0)).collect::<Vec<_>>().join(", ");
                    let note = format!(" (run.position_tolerance: runs at rtol = atol {tried})");
                    return Err(match e {
                        SimError::Integrator { t, message } => SimError::Integrator { t, message: message + &note },
                        SimError::Physics(m) => SimError::Physics(m + &note),
                        other => other,
                    });
                }
            }
        }
    };
    let mut candidate = attempt(first_tolerance(settings.integrator, tolerance), &mut runs)?;
    // The last rejected candidate's tolerance and estimated error.
    let mut last: Option<(f64, f64)> = None;
    // The last two rejected candidates whose estimates did not fall with the tolerance.
    let mut stalled: Option<((f64, f64), (f64, f64))> = None;
    loop {
        // A check that cannot be made (a tolerance tighter than the motion can be followed
        // at: an impact whose step falls below the run's floor) leaves the candidate without
        // an estimate: the tolerance is not reached, and the refusal says so first.
        let check = attempt(candidate.tolerance / RATIO, &mut runs).map_err(|e| {
            not_reached(tolerance, &format!("the check of the run at rtol = atol = {:.1e}", candidate.tolerance), e)
        })?;
        let difference = largest_difference(&candidate.rows, &check.rows);
        let estimated = coarser_error(difference, candidate.tolerance / check.tolerance);
        if estimated <= tolerance {
            let passed = Passed { check_tolerance: check.tolerance, trial: candidate, estimated, difference };
            let out = loosen(passed, tolerance, &mut run, &mut runs)?;
            for row in &out.trial.rows {
                sink.record(row).map_err(SimError::Output)?;
            }
            let mut report = out.trial.report;
            report.wall_seconds = runs.iter().map(|r| r.1).sum();
            report.position_accuracy = Some(PositionAccuracy {
                asked: tolerance,
                estimated: out.estimated,
                difference: out.difference,
                rtol: out.trial.tolerance,
                check_rtol: out.check_tolerance,
                runs,
            });
            return Ok(report);
        }
        // Estimates that did not fall as the tolerance tightened, for the refusal.
        if let Some(prev) = last
            && stagnates(prev, (candidate.tolerance, estimated))
        {
            stalled = Some((prev, (candidate.tolerance, estimated)));
        }
        let floor = candidate.tolerance <= RATIO * TIGHTEST;
        if runs.len() + 1 > MAX_RUNS || floor {
            return Err(SimError::Physics(format!(
                "run.position_tolerance = {tolerance:e} m not reached: the bodies' positions are estimated {estimated:.2e} m off at rtol = atol = {:.1e} after {} runs (rtol = atol {}){}{}; give a looser tolerance (or set run.rtol and run.atol yourself)",
                candidate.tolerance,
                runs.len(),
                runs.iter().map(|r| format!("{:.1e}", r.0)).collect::<Vec<_>>().join(", "),
                if floor { format!(", {TIGHTEST:e} being the tightest a run is given") } else { String::new() },
                stalled.map_or(String::new(), |(a, b)| stall_note(a, b))
            )));
        }
        // The tolerance that would give 2/3 of the one asked, by the power law.
        // The power law's exponent as the last two candidates show it, where they show one
        // (a structure whose errors grow with its motion, or auto changing methods, departs
        // from 2/3), kept within [0.4, 2]; a tolerance at most 1,000 times tighter at once.
        let order = match last {
            Some((t, e)) if t > candidate.tolerance && e > estimated => {
                order_between((t, e), (candidate.tolerance, estimated))
            }
            Some(_) => LEAST_ORDER,
            None => TOLERANCE_ORDER,
        };
        last = Some((candidate.tolerance, estimated));
        let aim = clamp(candidate.tolerance * aim_factor(tolerance, estimated, order).max(1e-3));
        if aim >= check.tolerance && check.tolerance >= RATIO * TIGHTEST {
            candidate = check;
        } else {
            // A tighter candidate that cannot be made is, likewise, the tolerance not reached.
            candidate = attempt(aim, &mut runs)
                .map_err(|e| not_reached(tolerance, &format!("the run at rtol = atol = {aim:.1e}"), e))?;
        }
    }
}

/// The least exponent of the power law the aim assumes (the error as `τ^q`), whatever two
/// candidates show.
pub const LEAST_ORDER: f64 = 0.4;

/// [`stagnates`] judges two rejected candidates at least this many times apart in tolerance.
pub const STAGNATION_TIGHTENING: f64 = 100.0;

/// [`stagnates`]: an estimated error that fell by less than this factor over
/// [`STAGNATION_TIGHTENING`] does not follow the tolerance; the power law at
/// [`LEAST_ORDER`] has it fall 6.3 times over 100, at 2/3 21.5 times.
pub const STAGNATION_FALL: f64 = 2.0;

/// Whether two rejected candidates, each as (tolerance, estimated error m), the first the
/// looser, show errors that do not fall with the tolerance ([`STAGNATION_TIGHTENING`],
/// [`STAGNATION_FALL`]); a refusal then says so. It does not stop the tightening: the contact
/// z-fold under DOP853 asked 3e-5 m shows it once (6.2e-4 m at rtol 3e-5, 4.7e-4 m at
/// 1.7e-7) and is reached after (0.58 of it, 8 runs, 16.8 s on the Intel Xeon 2-core at load
/// ~0.5). Where it holds to the end: the thick
/// flasher example, whose impacts as its sheet reaches flat turn on the integration's last
/// digits (under SDIRK4 at rtol 1e-6, 1e-7 and 1e-8 it is 3.5e-5, 1.1e-3 and 3.4e-5 m off
/// DOP853 at 1e-11, all at t = 1.27–1.29 s), asked 6.7e-6 m: 1.85e-3 m at 6.7e-7, 1.78e-3 m
/// at 6.7e-10, 1.2e-3 m at 4e-12.
pub fn stagnates((loose, e_loose): (f64, f64), (tight, e_tight): (f64, f64)) -> bool {
    loose >= STAGNATION_TIGHTENING * tight && e_tight * STAGNATION_FALL > e_loose
}

/// What a refusal adds when two rejected candidates, each as (tolerance, estimated error m),
/// the first the looser, showed estimates that did not fall with the tolerance.
fn stall_note((loose, e_loose): (f64, f64), (tight, e_tight): (f64, f64)) -> String {
    format!(
        "; the estimates did not fall as the runs tightened ({e_loose:.2e} m at rtol = atol {loose:.1e}, {e_tight:.2e} m at {tight:.1e}, {:.0} times tighter, where a run's error falls with its tolerance by {:.0} times or more): this motion depends on the integration's smallest differences (an impact that grazes or misses, a motion that amplifies what it is given), and a tighter run may not reach the tolerance either",
        loose / tight,
        (loose / tight).powf(LEAST_ORDER),
    )
}

/// The factor to move a run's tolerance by so that its error, estimated `estimated` (m),
/// becomes 2/3 of `tolerance` (m), if the error goes as the tolerance to the power `order`.
fn aim_factor(tolerance: f64, estimated: f64, order: f64) -> f64 {
    (2.0 * tolerance / (3.0 * estimated.max(f64::MIN_POSITIVE))).powf(1.0 / order)
}

/// The power law's exponent two runs show, each as (tolerance, estimated error m), the
/// first the looser; kept within [[`LEAST_ORDER`], 2].
fn order_between((loose, e_loose): (f64, f64), (tight, e_tight): (f64, f64)) -> f64 {
    ((e_loose / e_tight.max(f64::MIN_POSITIVE)).ln() / (loose / tight).ln()).clamp(LEAST_ORDER, 2.0)
}

/// A run whose error is estimated within the position tolerance.
struct Passed {
    trial: Trial,
    /// Its estimated error, m.
    estimated: f64,
    /// Its largest difference from the run it was checked against, m.
    difference: f64,
    /// That run's rtol = atol.
    check_tolerance: f64,
}

/// A passing run estimated more than this many times within the tolerance is loosened
/// (`loosen`), so that where the error follows its power law the error delivered is
/// within this factor of the tolerance both ways.
pub const WITHIN: f64 = 3.0;

/// The most runs `loosen` adds.
pub const LOOSENING_RUNS: usize = 2;

/// The order the first loosening assumes (the error as `τ^q`): higher than
/// [`TOLERANCE_ORDER`], so that a method whose error does grow as slowly as that is loosened
/// too little rather than past the tolerance (DOP853's grows as τ^(8/9) and faster).
pub const LOOSENING_ORDER: f64 = 0.9;

/// The passing run `passed`, or a looser one that also passes: a run estimated far within
/// the tolerance `tolerance` (m; by more than [`WITHIN`]) is made again at the tolerance
/// the power law says gives 2/3 of it, and checked against the passing run itself (tighter
/// by the ratio of their tolerances, so the estimate `d / (1 − r^−q)` is nearly the
/// difference), up to [`LOOSENING_RUNS`] times (after a miss, the second aims with the
/// order the miss showed). Its output then has an error near what was asked, and its rtol
/// is the loosest found to give it (what a sweep would reuse), at the cost of one or two
/// looser runs. A looser run that fails or misses the tolerance leaves the passing one as
/// it is.
fn loosen(
    mut passed: Passed,
    tolerance: f64,
    run: &mut impl FnMut(f64) -> Result<Trial, SimError>,
    runs: &mut Vec<(f64, f64)>,
) -> Result<Passed, SimError> {
    let mut order = LOOSENING_ORDER;
    for _ in 0..LOOSENING_RUNS {
        let tight = passed.trial.tolerance;
        if passed.estimated * WITHIN >= tolerance || runs.len() >= MAX_RUNS || tight >= LOOSEST {
            break;
        }
        let aim = clamp(tight * aim_factor(tolerance, passed.estimated, order).min(1e6));
        if aim < 1.5 * tight {
            break;
        }
        let start = std::time::Instant::now();
        let loose = match run(aim) {
            Ok(loose) => loose,
            // A looser run can fail where the tighter did not (events chattering): the
            // passing run stands.
            Err(SimError::Integrator { .. } | SimError::Physics(_)) => {
                runs.push((aim, start.elapsed().as_secs_f64()));
                break;
            }
            Err(e) => return Err(e),
        };
        runs.push((aim, loose.report.wall_seconds));
        let difference = largest_difference(&loose.rows, &passed.trial.rows);
        let estimated = coarser_error(difference, aim / tight);
        if estimated <= tolerance {
            passed = Passed { trial: loose, estimated, difference, check_tolerance: tight };
        } else {
            // Too loose: the order the two runs show, for one more try between them.
            order = order_between((aim, estimated), (tight, passed.estimated));
        }
    }
    Ok(passed)
}

/// A run the position tolerance made tighter that failed (`what`: which, at what tolerance;
/// an integration or physics failure: a tolerance tighter than the motion can be followed
/// at, an impact whose step falls below the run's floor) as the refusal of the tolerance
/// `tolerance` (m), said first, with the failure's own message; a run stopped (Ctrl-C) or an
/// output error as it is.
fn not_reached(tolerance: f64, what: &str, e: SimError) -> SimError {
    match e {
        SimError::Integrator { .. } | SimError::Physics(_) => SimError::Physics(format!(
            "run.position_tolerance = {tolerance:e} m not reached: {what} failed ({e}); give a looser tolerance (or set run.rtol and run.atol yourself)"
        )),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The estimate inverts the power law it assumes: two runs whose errors follow
    /// `C τ^(2/3)` exactly (along one direction) give the coarser one's error back.
    #[test]
    fn finer_error_inverts_the_power_law() {
        let c = 3.0;
        for (ta, r) in [(1e-4, 4.0), (1e-6, 10.0), (3e-3, 1.7)] {
            let (ea, eb) = (c * f64::powf(ta, TOLERANCE_ORDER), c * f64::powf(ta / r, TOLERANCE_ORDER));
            assert!((coarser_error(ea - eb, r) / ea - 1.0).abs() < 1e-12);
        }
    }

    /// Errors that fall with the tolerance do not stagnate, down to the aim's least
    /// exponent (0.4) over the least tightening that is looked at; errors that fall by less
    /// than half over 100 times do, as the thick flasher's did; and the refusal's note names
    /// both candidates and what the power law would have them do.
    #[test]
    fn errors_that_do_not_fall_with_the_tolerance_are_named() {
        for q in [LEAST_ORDER, TOLERANCE_ORDER, 1.0, 2.0] {
            for tightening in [STAGNATION_TIGHTENING, 1e3] {
                let (t, e) = (6.7e-7, 1e-3);
                assert!(!stagnates((t, e), (t / tightening, e * tightening.powf(-q))), "q {q}, {tightening}");
            }
        }
        // Tightened less than 100 times: not judged.
        assert!(!stagnates((1e-6, 1e-3), (2e-8, 1e-3)));
        // 6.7e-7 → 6.7e-10 with the estimate 1.1e-3 → 0.9e-3 m.
        assert!(stagnates((6.7e-7, 1.1e-3), (6.7e-10, 0.9e-3)));
        assert!(stagnates((6.7e-7, 1.1e-3), (6.7e-9, 2e-3)));
        let m = stall_note((6.7e-7, 1.85e-3), (6.7e-10, 1.78e-3));
        for part in [
            "did not fall as the runs tightened (1.85e-3 m at rtol = atol 6.7e-7, 1.78e-3 m at 6.7e-10, 1000 times tighter",
            "by 16 times or more",
            "a tighter run may not reach the tolerance either",
        ] {
            assert!(m.contains(part), "{part}: {m}");
        }
    }
}

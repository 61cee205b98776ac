//! Why an integration stopped, in the user's terms.

use super::report::SimError;
use super::settings::{MIN_STEP_BUDGET, RunSettings};
use crate::dynamics::Dynamics;
use crate::integrate::{Limits, OdeError};

/// Why the integrator stopped, in the user's terms: what it could not do, the hinge or body
/// responsible (the fastest hinge direction, or the body whose state or acceleration is not
/// finite), and what to change.
pub(super) fn stopped(
    dynamics: &Dynamics<'_>,
    settings: &RunSettings,
    limits: &Limits,
    e: OdeError<SimError>,
) -> SimError {
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

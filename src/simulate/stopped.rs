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
        OdeError::SingularNewton { t, h, block } => SimError::Integrator {
            t,
            message: format!(
                "the implicit integrator's Newton matrix I − hγJ could not be factored at a step of {h:.3e} s (a singular pivot block{}): {}otherwise it is a fault in foldsim, please report it with the scenario. integrator = \"dop853\" does not need the matrix",
                singular_where(model, block),
                match farthest_hinge(model) {
                    Some((what, ratio)) if ratio > FAR_LEVER => format!(
                        "{what}, {ratio:.1e} times its body's size: f64 keeps too few digits for the rest of the structure beside such a length (a length in mm where m was meant?); give it in the body's scale. A structure whose locked directions are redundant (locks closing a loop of locked hinges) does this too; "
                    ),
                    _ => "a structure whose locked directions are redundant (locks closing a loop of locked hinges) does this; ".to_string(),
                }
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

/// Where the Newton matrix's singular pivot block is, in words: `block` numbers the bodies
/// in model order, then the locked hinges carried as constraint rows
/// (`crate::dynamics::newton::GraphNewton`).
fn singular_where(model: &crate::model::Model, block: Option<usize>) -> String {
    let Some(b) = block else { return String::new() };
    let Some(body) = model.bodies.get(b) else { return ", in a locked hinge's constraint rows".to_string() };
    let hinges: Vec<&str> =
        model.hinges.iter().filter(|h| h.parent == b || h.child == b).map(|h| h.name.as_str()).take(6).collect();
    format!(", body '{}''s, joined by hinges {}", body.name, hinges.join(", "))
}

/// A hinge lever this many times its body's size leaves the Newton matrix's other entries
/// below f64's resolution (1e-16 relative) once squared into its inertia terms.
const FAR_LEVER: f64 = 1e6;

/// The hinge placed farthest from a body's centre of mass against the body's size (its
/// radius of gyration, √(tr I / m), at least 1 mm): the key and hinge in words, and the ratio.
fn farthest_hinge(model: &crate::model::Model) -> Option<(String, f64)> {
    let size = |b: usize| {
        let body = &model.bodies[b];
        (body.inertia_in_body.trace() / body.mass).sqrt().max(1e-3)
    };
    model
        .hinges
        .iter()
        .flat_map(|h| {
            [
                (
                    format!(
                        "hinge '{}''s a0.position is {:.3e} m from body '{}''s centre of mass",
                        h.name,
                        h.r_a0_in_parent.norm(),
                        model.bodies[h.parent].name
                    ),
                    h.r_a0_in_parent.norm() / size(h.parent),
                ),
                (
                    format!(
                        "hinge '{}''s a.child_com puts body '{}''s centre of mass {:.3e} m from the hinge",
                        h.name,
                        model.bodies[h.child].name,
                        h.r_child_in_a.norm()
                    ),
                    h.r_child_in_a.norm() / size(h.child),
                ),
            ]
        })
        .filter(|(_, r)| r.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

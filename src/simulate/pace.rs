//! What a run's progress callback is told after each accepted step, and what holds its steps
//! back, for a person deciding whether to wait (the command line's early note on a long run).

use crate::dynamics::Dynamics;

/// A run's progress callback: told after every accepted step, it may stop the run.
pub type ProgressFn<'y> = dyn FnMut(&Progress<'_, '_>) -> std::ops::ControlFlow<()> + 'y;

/// A run's progress after an accepted step.
pub struct Progress<'p, 'm> {
    /// Simulated time reached, s.
    pub t: f64,
    /// The last accepted step, s (0 at a restart).
    pub step: f64,
    /// The method that took it: `"dop853"`, `"sdirk4"`, … (under `auto`, the one in use).
    pub method: &'static str,
    pub(super) dynamics: &'p Dynamics<'m>,
    pub(super) y: &'p [f64],
    /// Law events, lock engagements and restarts so far.
    pub(super) events: usize,
    /// Accepted steps so far.
    pub steps: usize,
}

impl Progress<'_, '_> {
    /// What holds the steps back at this state, and what the user can change: stiffness
    /// (an explicit method's steps near the fastest hinge's period), contact, events, a
    /// fast body, or the tolerances. For a person; costs one right-hand side.
    pub fn pace(&self) -> String {
        let model = self.dynamics.model();
        let fastest = model.fastest_hinge();
        let explicit = matches!(self.method, "dop853" | "dopri5" | "rk4");
        // An explicit method's stability boundary is a few units of h·|λ| (DOP853's test
        // takes 6.1); steps within a factor of ~10 of it are held by the fastest vibration.
        if explicit && let Some(r) = fastest.filter(|r| held_by_stiffness(self.step, r.rate)) {
            return format!(
                "stiffness: {} holds the explicit steps ({:.2e} s) near its period; integrator = \"auto\" or \"sdirk4\" steps over it, or make that hinge softer or its bodies heavier",
                r.describe(model),
                self.step
            );
        }
        // Each control sample ends a step: steps of about the period are held by it.
        if let Some(period) = model.control.as_ref().and_then(|c| c.period)
            && self.step >= 0.5 * period
            && self.step <= period * (1.0 + 1e-9)
        {
            return format!(
                "control samples: the law samples every {period:.3e} s (control.period) and each sample ends a step ({:.2e} s); a longer period shortens it",
                self.step
            );
        }
        if let Some((summary, bodies)) = self.touching() {
            return format!(
                "contact: {bodies} bodies touching (deepest {:.2e} m); each impact is followed through the contact law's stiffness; a softer contact.stiffness (deeper penetration) or a looser run.rtol shortens it",
                summary.deepest.0
            );
        }
        if self.steps > 0 && self.events * 10 > self.steps {
            return format!(
                "events: {} law events, lock engagements or restarts in {} steps, each restarting the integration; a hinge law with fewer corners (stops, tables) shortens it",
                self.events, self.steps
            );
        }
        let body = self.dynamics.fastest_body(self.y).unwrap_or_default();
        format!(
            "accuracy: the tolerances set the steps ({:.2e} s; {body}: a body that fast may have too small a mass or inertia); a looser run.rtol and run.atol shortens it",
            self.step
        )
    }

    /// How many pairs of bodies no hinge joins touch now (0 without contact); costs one
    /// contact evaluation.
    pub fn unhinged_pairs_touching(&self) -> usize {
        self.dynamics.unhinged_pairs_touching(self.y)
    }

    /// With contact, what it adds up to now and how many bodies touch (now, or at an accepted
    /// step since the last output row); `None` without contact or with none touching. The
    /// output rows' record of who touched is left as it is.
    pub fn touching(&self) -> Option<(crate::contact::ContactSummary, usize)> {
        let (summary, touched) = self.dynamics.contact_at(self.y)?;
        let bodies = touched.iter().filter(|&&t| t).count();
        (bodies > 0).then_some((summary, bodies))
    }
}

/// Whether an explicit method's step `step` (s) is held near its stability bound by a
/// vibration of rate `rate` (1/s): within a factor of ~10 of DOP853's h·|λ| = 6.1.
pub fn held_by_stiffness(step: f64, rate: f64) -> bool {
    step * rate > 0.3
}

/// Seconds as a person reads them: `0.4 s`, `9 s`, `4.2 min`, `3.1 h` (a tenth of a second
/// below 10 s, so that a short run's progress does not read "0 s so far, about 0 s left").
pub fn human_seconds(s: f64) -> String {
    if s < 9.95 {
        format!("{s:.1} s")
    } else if s < 100.0 {
        format!("{s:.0} s")
    } else if s < 6000.0 {
        format!("{:.1} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

#[cfg(test)]
mod tests {
    use super::human_seconds;

    /// Each range in its unit, and a sub-second time not rounded to nothing.
    #[test]
    fn seconds_read_in_the_unit_of_their_size() {
        assert_eq!(human_seconds(0.04), "0.0 s");
        assert_eq!(human_seconds(0.4), "0.4 s");
        assert_eq!(human_seconds(9.4), "9.4 s");
        assert_eq!(human_seconds(9.96), "10 s");
        assert_eq!(human_seconds(42.0), "42 s");
        assert_eq!(human_seconds(252.0), "4.2 min");
        assert_eq!(human_seconds(11_160.0), "3.1 h");
    }
}

//! How long a run will take, measured rather than guessed: the run itself for a short budget
//! of wall time, its simulated time extrapolated to the whole duration. A deployment's step
//! size changes as it opens, so the projection is a guide (within a factor of about two on
//! the generated examples), and says how much of the run it saw.

use super::run::simulate;
use super::settings::RunSettings;
use crate::kinematics::InitialConditions;
use crate::model::Model;
use crate::observe::Observation;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

/// A run's projected wall time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Simulated time the trial reached, s.
    pub simulated: f64,
    /// Wall time the trial took, s.
    pub wall: f64,
    /// The whole run's duration, s.
    pub duration: f64,
    /// Whether the trial ran the whole duration (then `wall` is the run's time).
    pub complete: bool,
    /// Whether the trial stopped with an error (the run would too).
    pub failed: bool,
}

impl Estimate {
    /// The projected wall time of the whole run, s: the trial's own time when it finished,
    /// else its wall time scaled by duration over simulated time (infinite if it did not get
    /// past the start).
    pub fn projected(&self) -> f64 {
        if self.complete {
            self.wall
        } else if self.simulated > 0.0 {
            self.wall * self.duration / self.simulated
        } else {
            f64::INFINITY
        }
    }

    /// One line for a person: `about 9 s (a 0.5-s trial reached t = 0.31 s of 5 s)`.
    pub fn describe(&self) -> String {
        if self.failed {
            return format!("the run stops with an error at t = {:.3} s (run it to see why)", self.simulated);
        }
        if self.complete {
            return format!("{:.2} s (the whole run, measured)", self.wall);
        }
        let p = self.projected();
        let shown = if p.is_finite() { format!("about {}", human_seconds(p)) } else { "very long".to_string() };
        format!(
            "{shown} on this machine (a {:.1}-s trial reached t = {:.3} s of {} s; steps change as it deploys)",
            self.wall, self.simulated, self.duration
        )
    }
}

pub use super::pace::human_seconds;

/// Runs the scenario for at most `budget` of wall time and projects the whole run's time.
pub fn estimate(model: &Model, initial: &InitialConditions, settings: &RunSettings, budget: Duration) -> Estimate {
    let started = Instant::now();
    let mut reached = 0.0;
    let mut sink = |o: &Observation| -> Result<(), String> {
        reached = o.t;
        Ok(())
    };
    let mut last_t = 0.0;
    let mut progress = |p: &super::Progress<'_, '_>| {
        last_t = p.t;
        if started.elapsed() > budget { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    };
    let result = simulate(model, initial, settings, &mut sink, Some(&mut progress));
    let wall = started.elapsed().as_secs_f64();
    let simulated = last_t.max(reached);
    match result {
        Ok(_) => {
            Estimate { simulated: settings.duration, wall, duration: settings.duration, complete: true, failed: false }
        }
        Err(super::SimError::Interrupted { t }) => {
            Estimate { simulated: t.max(simulated), wall, duration: settings.duration, complete: false, failed: false }
        }
        Err(_) => Estimate { simulated, wall, duration: settings.duration, complete: false, failed: true },
    }
}

//! How long a run will take, measured rather than guessed: the run itself for a short budget
//! of wall time, its simulated time extrapolated to the whole duration along its trend
//! ([`Trend`]). A deployment's step size changes as it opens, so the projection is a guide,
//! and says how much of the run it saw.

use super::run::simulate;
use super::settings::RunSettings;
use crate::kinematics::InitialConditions;
use crate::model::Model;
use crate::observe::Observation;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

/// The largest pace-up exponent a projection assumes (see [`Trend`]).
pub const MOST_ACCELERATION: f64 = 1.4;

/// Simulated time against wall time as a run goes, for projecting when it ends.
///
/// A deployment from a packed start speeds up as it opens: a stowed thick flasher's first
/// hundredths of a second, every layer pressing on the next, cost 50–500 times the wall time
/// per simulated second of its later motion, so a projection from the average pace so far
/// was 10–150 times too long. Where its steps have grown (the mean step over the last half
/// of the wall time so far more than 1.2 times the mean before), the projection takes the
/// trend: the simulated time reached, as a power of the wall time over that last half,
/// `t ∝ w^p`, `p = ln(t(w)/t(w/2)) / ln 2` held between 1 and [`MOST_ACCELERATION`], is
/// extrapolated to the duration: `w_end = w (T / t(w))^(1/p)`. Where the steps have not
/// grown the pace is taken as steady (`p = 1`): a run's first second also holds its setup
/// (the first Jacobian, the contact lists), which looks like a quickening pace and is not
/// (the thick starshade, steps held by a stiff hinge, was projected at 2.8 h from it and
/// took ~60). The cap is measured, not derived: on three thick flashers (5 × 2 with stiff and
/// with soft hinges, 6 × 3 soft; 1 cm) the projection after 2 s and 3 s of the run was
/// 0.57–1.44 times the actual wall time with the cap at 1.4, against 0.53–1.09 at 1.5 and
/// 0.71–2.89 at 1.2, and 7–150 times before the trend was taken (docs/outputs.md).
#[derive(Clone, Debug, Default)]
pub struct Trend {
    /// (wall time s, simulated time s, accepted steps), one per 1 % of the wall time so far
    /// at most.
    samples: Vec<(f64, f64, usize)>,
}

impl Trend {
    /// Adds a point: `simulated` s reached after `wall` s in `steps` accepted steps (`None`
    /// for work not made of steps, as a sweep's runs: its pace is then taken as steady).
    pub fn add(&mut self, wall: f64, simulated: f64, steps: Option<usize>) {
        let point = (wall, simulated, steps.unwrap_or(0));
        // Points closer together than 1 % of the wall time replace the last one (the history
        // stays short: a few hundred per decade of wall time).
        let n = self.samples.len();
        if n > 1 && wall - self.samples[n - 2].0 < 0.01 * wall {
            self.samples[n - 1] = point;
        } else {
            self.samples.push(point);
        }
    }

    /// The wall time the whole `duration` (s) will take, projected along the trend, s; infinite
    /// before the run has got anywhere.
    pub fn projected(&self, duration: f64) -> f64 {
        let Some(&(w, t, n)) = self.samples.last() else { return f64::INFINITY };
        if t <= 0.0 || w <= 0.0 {
            return f64::INFINITY;
        }
        if t >= duration {
            return w;
        }
        // The sample nearest to half the wall time so far, and whether the steps since have
        // grown.
        let half = self.samples.iter().rev().find(|s| s.0 <= 0.5 * w).copied();
        let p = match half {
            Some((wh, th, nh)) if nh > 0 && n > nh && (t - th) / (n - nh) as f64 > 1.2 * th / nh as f64 => {
                if th > 0.0 && wh > 0.0 { (t / th).ln() / (w / wh).ln() } else { MOST_ACCELERATION }
            }
            _ => 1.0,
        };
        w * (duration / t).powf(1.0 / p.clamp(1.0, MOST_ACCELERATION))
    }
}

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
    /// The whole run's wall time projected along the trial's trend ([`Trend`]), s.
    pub trend: f64,
}

impl Estimate {
    /// The projected wall time of the whole run, s: the trial's own time when it finished,
    /// else projected along its trend ([`Trend`]; infinite if it did not get past the
    /// start).
    pub fn projected(&self) -> f64 {
        if self.complete { self.wall } else { self.trend }
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
        let linear = self.wall * self.duration / self.simulated;
        let trend = if p < 0.9 * linear {
            format!(", projected along its quickening pace; at its average pace {}", human_seconds(linear))
        } else {
            String::new()
        };
        format!(
            "{shown} on this machine (a {:.1}-s trial reached t = {:.4} s of {} s{trend}; steps change as it deploys)",
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
    let mut trend = Trend::default();
    let mut progress = |p: &super::Progress<'_, '_>| {
        last_t = p.t;
        trend.add(started.elapsed().as_secs_f64(), p.t, Some(p.steps));
        if started.elapsed() > budget { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    };
    let result = simulate(model, initial, settings, &mut sink, Some(&mut progress));
    let wall = started.elapsed().as_secs_f64();
    let simulated = last_t.max(reached);
    let duration = settings.duration;
    let trend = trend.projected(duration);
    match result {
        Ok(_) => Estimate { simulated: duration, wall, duration, complete: true, failed: false, trend: wall },
        Err(super::SimError::Interrupted { t }) => {
            Estimate { simulated: t.max(simulated), wall, duration, complete: false, failed: false, trend }
        }
        Err(_) => Estimate { simulated, wall, duration, complete: false, failed: true, trend },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A steady pace projects linearly; a pace that quickens as a power of the wall time
    /// (t ∝ w^1.3, inside the cap) projects its own end exactly (to round-off, 1e-12); a
    /// faster quickening is taken at the cap (a projection longer than its own end, never
    /// shorter); before anything was simulated the projection is infinite.
    #[test]
    fn the_projection_follows_the_trend() {
        // Steps of a size growing as the pace does (t ∝ w^p in steps ∝ w): accepted steps
        // 100 per second of wall time.
        let run = |p: f64, until: f64, growing: bool| {
            let mut trend = Trend::default();
            for i in 1..=1000 {
                let w = until * i as f64 / 1000.0;
                let steps = if growing { (100.0 * w) as usize } else { (1e4 * 0.01 * w.powf(p)) as usize };
                trend.add(w, 0.01 * w.powf(p), Some(steps.max(1)));
            }
            trend
        };
        // 0.01 w^p reaches T = 1 s at w = 100^(1/p).
        let steady = run(1.0, 2.0, true).projected(1.0);
        assert!((steady - 100.0).abs() < 1e-9, "{steady}");
        let quick = run(1.3, 2.0, true).projected(1.0);
        let end = 100f64.powf(1.0 / 1.3);
        assert!((quick - end).abs() < 1e-12 * end, "{quick} vs {end}");
        let faster = run(2.0, 2.0, true).projected(1.0);
        assert!(faster > 10.0 && faster < 100f64.powf(1.0 / MOST_ACCELERATION) * 1.3, "{faster}");
        // The same quickening made of more steps of one size (a setup's cost, not longer
        // steps): taken as steady, projected linearly.
        let same_steps = run(1.3, 2.0, false).projected(1.0);
        let linear = 2.0 / (0.01 * 2f64.powf(1.3));
        assert!((same_steps - linear).abs() < 1e-9 * linear, "{same_steps} vs {linear}");
        // Work without steps (a sweep's runs): steady.
        let mut runs = Trend::default();
        for i in 1..=10 {
            runs.add(i as f64, (i * i) as f64, None);
        }
        assert!((runs.projected(1000.0) - 10.0 * 1000.0 / 100.0).abs() < 1e-9);
        assert!(Trend::default().projected(1.0).is_infinite());
        let mut nothing = Trend::default();
        nothing.add(1.0, 0.0, Some(0));
        assert!(nothing.projected(1.0).is_infinite());
    }
}

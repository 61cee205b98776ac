//! How long a run will take, measured rather than guessed: the run itself for a short budget
//! of wall time, its simulated time extrapolated to the whole duration along its trend
//! ([`Trend`]). A deployment's step size changes as it opens, so the projection is a guide,
//! and says how much of the run it saw.

use super::run::simulate_once as simulate;
use super::settings::RunSettings;
use crate::kinematics::InitialConditions;
use crate::model::Model;
use crate::observe::Observation;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

/// What a projection of a run with a packed start says of itself (the generator's trial and
/// the run's note): measured, such projections have been 1.3–19 times the run's wall time
/// (docs/outputs.md, *How projections are made*; the 8 × 4 1.3× on 2026-11-29, the 6 × 3
/// 5–9× and the thick starshade 5–9× since; on 2026-12-01 the thick starshade 18×, the
/// 12 × 7 17× and the 12 × 9 with 0.6 N·m/rad folds 19×).
pub const PACKED_START: &str = "with contact a packed start is the slowest part of a run and its first seconds cannot show when it opens: thick flashers have taken 1.3 to 19 times less than projected from them (docs/outputs.md)";

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
///
/// Under `integrator = "auto"` a run's first phase can be DOP853 held by a stiff hinge,
/// steps 10–100 times shorter than the SDIRK4 it switches to (the thick starshade's first
/// 1.6 ms took its first seconds: projected from them, 6.7 h for a run of 94 s). A change
/// of method restarts the trend ([`Trend::restart`]): the projection is the time so far
/// plus the rest at the pace since the change.
#[derive(Clone, Debug, Default)]
pub struct Trend {
    /// (wall time s, simulated time s, accepted steps), one per 1 % of the wall time so far
    /// at most, since `origin`.
    samples: Vec<(f64, f64, usize)>,
    /// Where the trend starts: the last change of method (wall s, simulated s, steps), or
    /// zero.
    origin: (f64, f64, usize),
}

impl Trend {
    /// Starts the trend again from its last point (the method changed there): what came
    /// before counts as time spent, not as pace.
    pub fn restart(&mut self) {
        if let Some(&last) = self.samples.last() {
            self.origin = last;
            self.samples.clear();
        }
    }

    /// Starts the trend afresh at `wall` (s) for a new run from its start (a position
    /// tolerance's next run: simulated time and steps count from zero again). What came
    /// before counts as time spent.
    pub fn begin_again(&mut self, wall: f64) {
        self.samples.clear();
        self.origin = (wall, 0.0, 0);
    }

    /// Whether a point at `simulated` s is behind the trend's last (a new run began).
    pub fn went_back(&self, simulated: f64) -> bool {
        self.samples.last().is_some_and(|s| simulated < s.1)
    }

    /// The simulated time where the trend starts, s (0, or the last change of method).
    pub fn since(&self) -> f64 {
        self.origin.1
    }

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
        if t >= duration {
            return w;
        }
        // Measured from the origin.
        let (w0, t0, n0) = self.origin;
        let (w, t, n, duration) = (w - w0, t - t0, n.saturating_sub(n0), duration - t0);
        if t <= 0.0 || w <= 0.0 {
            return f64::INFINITY;
        }
        // The sample nearest to half the wall time so far, and whether the steps since have
        // grown.
        let half =
            self.samples.iter().rev().map(|s| (s.0 - w0, s.1 - t0, s.2.saturating_sub(n0))).find(|s| s.0 <= 0.5 * w);
        let p = match half {
            Some((wh, th, nh)) if nh > 0 && n > nh && (t - th) / (n - nh) as f64 > 1.2 * th / nh as f64 => {
                if th > 0.0 && wh > 0.0 { (t / th).ln() / (w / wh).ln() } else { MOST_ACCELERATION }
            }
            _ => 1.0,
        };
        w0 + w * (duration / t).powf(1.0 / p.clamp(1.0, MOST_ACCELERATION))
    }
}

/// How many times its usual wait a projection waits for `auto` to leave a DOP853 held by the
/// stiffest hinge ([`Phase`]). `auto` leaves it once its stiffness test has seen enough
/// steps, and on a large packed structure each of those DOP853 steps is slow: the thick
/// starshade (the example's options with 1-cm panels, 229 bodies) switched at t = 0.0009 s
/// after 7.5–9 s of wall time, so with 4 (8 s with contact) `generate`'s trial ended just
/// before it and projected 177–182 h from the held steps, where with 16 it saw the switch and
/// projected 29 min, for a run of about 5 min (Intel Xeon 2-core, load ~1.6, 2026-11-29).
/// The wait is spent only while DOP853 is held.
pub const HELD_WAIT: f64 = 16.0;

/// When a run's pace has been seen, for a projection: `after` of wall time in the method in
/// use (s); but under `auto`, while it still runs the DOP853 it starts with and its steps are
/// held by the stiffest hinge (`auto` then switches to its implicit method soon: see [`Trend`]), until it
/// changes or [`HELD_WAIT`] times `after` have passed.
#[derive(Clone, Debug)]
pub struct Phase {
    /// Under `auto`: the fastest hinge's rate, 1/s (see `pace::held_by_stiffness`).
    auto_rate: Option<f64>,
    after: f64,
    method: Option<&'static str>,
    held: bool,
    changes: usize,
    started: f64,
}

impl Phase {
    /// For a run of `model` (under `auto` or not), its pace seen after `after`.
    pub fn new(model: &Model, auto: bool, after: Duration) -> Self {
        let auto_rate = auto.then(|| model.fastest_hinge().map_or(0.0, |r| r.rate));
        Self { auto_rate, after: after.as_secs_f64(), method: None, held: false, changes: 0, started: 0.0 }
    }

    /// Notes the method in use at `wall` (s) and its last step (s); true if it changed (the
    /// trend restarts).
    pub fn changed(&mut self, method: &'static str, step: f64, wall: f64) -> bool {
        let changed = self.method.is_some_and(|m| m != method);
        if changed {
            self.changes += 1;
            self.started = wall;
        }
        self.method = Some(method);
        if let Some(rate) = self.auto_rate
            && step > 0.0
        {
            self.held = method == "dop853" && super::pace::held_by_stiffness(step, rate);
        }
        changed
    }

    /// Whether the pace has been seen at `wall` (s).
    pub fn seen(&self, wall: f64) -> bool {
        if self.auto_rate.is_some() && self.changes == 0 && self.held {
            wall >= HELD_WAIT * self.after
        } else {
            wall - self.started >= self.after
        }
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
    /// Where the trend starts: the simulated time of the last change of method (s; 0 for
    /// none) and the method since.
    pub since: (f64, &'static str),
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
        let mut trend = String::new();
        if self.since.0 > 0.0 {
            trend =
                format!(", projected from its pace since it changed to {} at t = {:.4} s", self.since.1, self.since.0);
        }
        if p < 0.9 * linear {
            let along = if trend.is_empty() { ", projected along" } else { " and along" };
            trend += &format!("{along} its quickening pace; at its average pace {}", human_seconds(linear));
        }
        format!(
            "{shown} on this machine (a {:.1}-s trial reached t = {:.4} s of {} s{trend}; steps change as it deploys)",
            self.wall, self.simulated, self.duration
        )
    }
}

pub use super::pace::human_seconds;

/// A run made again from its start at another tolerance (a position tolerance's next run),
/// projected against the run before it: the same motion, whose wall time to each simulated
/// time differs from the run before's by a factor that changes slowly, where its own trend
/// knows nothing of what is to come (a thick flasher's packed start: "about 18.5 h left" at
/// 0.0001 s of a run that took minutes). The projection is the run before's whole wall time
/// times that factor at the simulated time reached.
#[derive(Clone, Debug, Default)]
pub struct Rerun {
    /// The run before: (simulated s, wall s since its start), simulated ascending, and its
    /// whole wall time, s.
    before: Vec<(f64, f64)>,
    before_wall: f64,
    /// This run: its start (wall s) and its points as `before`'s.
    start: f64,
    now: Vec<(f64, f64)>,
}

impl Rerun {
    /// Adds a point of this run: `simulated` s reached at `wall` s (since the watch began).
    pub fn add(&mut self, wall: f64, simulated: f64) {
        let point = (simulated, wall - self.start);
        // Points closer than 1 % of the run's wall time replace the last (as `Trend::add`).
        let n = self.now.len();
        if n > 1 && point.1 - self.now[n - 2].1 < 0.01 * point.1 {
            self.now[n - 1] = point;
        } else {
            self.now.push(point);
        }
    }

    /// The run before ended and a new one begins at `wall` s: the run just made becomes the
    /// one to project against, its wall time counted to `wall`.
    pub fn begin_again(&mut self, wall: f64) {
        self.before = std::mem::take(&mut self.now);
        self.before_wall = wall - self.start;
        self.start = wall;
    }

    /// The wall time left in this run at `wall` s, having reached `simulated` s, projected
    /// against the run before; `None` before anything was simulated or without a run before.
    pub fn left(&self, wall: f64, simulated: f64) -> Option<f64> {
        let &(last_t, _) = self.before.last()?;
        if simulated <= 0.0 || self.before_wall <= 0.0 {
            return None;
        }
        // The run before's wall time at `simulated`, interpolated linearly.
        let at = if simulated >= last_t {
            self.before_wall
        } else {
            let k = self.before.partition_point(|p| p.0 <= simulated);
            let (t0, w0) = if k == 0 { (0.0, 0.0) } else { self.before[k - 1] };
            let (t1, w1) = self.before[k];
            w0 + (w1 - w0) * (simulated - t0) / (t1 - t0).max(f64::MIN_POSITIVE)
        };
        (at > 0.0).then(|| ((wall - self.start) * (self.before_wall / at - 1.0)).max(0.0))
    }
}

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
    let mut phase = Phase::new(model, matches!(settings.integrator, super::settings::Integrator::Auto { .. }), budget);
    let mut progress = |p: &super::Progress<'_, '_>| {
        last_t = p.t;
        let wall = started.elapsed().as_secs_f64();
        if phase.changed(p.method, p.step, wall) {
            trend.restart();
        }
        trend.add(wall, p.t, Some(p.steps));
        if phase.seen(wall) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    };
    let result = simulate(model, initial, settings, &mut sink, Some(&mut progress));
    let since = (trend.since(), phase.method.unwrap_or(""));
    let wall = started.elapsed().as_secs_f64();
    let simulated = last_t.max(reached);
    let duration = settings.duration;
    let trend = trend.projected(duration);
    match result {
        Ok(_) => Estimate { simulated: duration, wall, duration, complete: true, failed: false, trend: wall, since },
        Err(super::SimError::Interrupted { t }) => {
            Estimate { simulated: t.max(simulated), wall, duration, complete: false, failed: false, trend, since }
        }
        Err(_) => Estimate { simulated, wall, duration, complete: false, failed: true, trend, since },
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

    /// A run whose method changes (`auto` leaving a stiffness-held DOP853 after 3 s of wall
    /// time at t = 0.001 s, then steady at 1 simulated s per 10 s of wall in as many steps)
    /// is projected from its pace since the change: the 3 s spent plus 10 s per simulated
    /// second left, exactly; from the start the projection was 3,000 times too long. The
    /// phase waits for the change (to [`HELD_WAIT`] times its wait) only while DOP853 is held.
    #[test]
    fn a_change_of_method_restarts_the_trend() {
        let mut trend = Trend::default();
        let auto = Phase { auto_rate: Some(1e4), after: 2.0, method: None, held: false, changes: 0, started: 0.0 };
        let mut phase = auto.clone();
        for i in 1..=300 {
            let w = 0.01 * i as f64;
            assert!(!phase.changed("dop853", 1e-4, w), "no change yet");
            trend.add(w, 1e-3 * w / 3.0, Some(i));
            assert!(!phase.seen(w), "held DOP853 is not seen until it changes or 32 s have passed");
        }
        // Held to the end of the wait and past it: seen at HELD_WAIT times the wait, not before.
        let mut held = auto.clone();
        held.changed("dop853", 1e-4, 0.1);
        assert!(!held.seen(8.0) && !held.seen(HELD_WAIT * 2.0 - 1e-9) && held.seen(HELD_WAIT * 2.0));
        assert!(trend.projected(10.0) > 1e4);
        for i in 1..=300 {
            let w = 3.0 + 0.01 * i as f64;
            if phase.changed("sdirk4", 1e-3, w) {
                trend.restart();
            }
            trend.add(w, 1e-3 + 0.1 * (w - 3.0), Some(300 + i));
            assert_eq!(phase.seen(w), w >= 5.01 - 1e-9, "seen 2 s after the change (at 3.01 s), at {w}");
        }
        let expected = 3.0 + 10.0 * (10.0 - 1e-3);
        assert!((trend.projected(10.0) - expected).abs() < 1e-9 * expected, "{} vs {expected}", trend.projected(10.0));
        assert_eq!(trend.since(), 1e-3);
        // DOP853 not held (its steps well inside its stability): seen after the wait alone.
        let mut free = auto;
        free.changed("dop853", 1e-6, 1.0);
        assert!(!free.seen(1.9) && free.seen(2.0));
    }

    /// A run made again at a tolerance that costs 2.5 times the wall time throughout (a packed
    /// start at 50 times the later pace in both) is projected exactly against the run before
    /// from its first points, where its own trend projects it many times too long.
    #[test]
    fn a_run_made_again_is_projected_against_the_one_before() {
        // Wall time to simulated time t in the first run: 10 s for the first 0.01 s, then
        // 2 s per simulated second, to 1 s: 11.98 s.
        let wall_at = |t: f64| if t <= 0.01 { 1000.0 * t } else { 10.0 + 2.0 * (t - 0.01) };
        let mut rerun = Rerun::default();
        let mut trend = Trend::default();
        for i in 0..=1000 {
            let t = i as f64 * 1e-3;
            rerun.add(wall_at(t), t);
        }
        let first = wall_at(1.0);
        rerun.begin_again(first);
        trend.begin_again(first);
        assert_eq!(rerun.left(first, 0.0), None);
        for i in 1..=5 {
            let t = i as f64 * 1e-3;
            let wall = first + 2.5 * wall_at(t);
            rerun.add(wall, t);
            trend.add(wall, t, Some(i));
            let left = rerun.left(wall, t).unwrap();
            let exact = 2.5 * first - (wall - first);
            assert!((left - exact).abs() < 1e-9 * exact, "{left} vs {exact}");
        }
        let own = trend.projected(1.0) - (first + 2.5 * wall_at(5e-3));
        assert!(own > 20.0 * 2.5 * first, "the trend alone: {own} s left");
        assert_eq!(Rerun::default().left(1.0, 0.5), None, "no run before");
    }

    /// A second run from the start (a position tolerance's next run, 60 s into the first,
    /// at 1 simulated s per 10 s of wall) is projected from its own start: 60 s spent plus
    /// 10 s per simulated second, exactly. Without `begin_again` its first points, behind the
    /// first run's, are projected as if that run had taken all the time so far: here more than
    /// ten times too long.
    #[test]
    fn a_new_run_starts_its_own_trend() {
        let mut trend = Trend::default();
        for i in 1..=600 {
            let w = 0.1 * i as f64;
            trend.add(w, 0.02 * w, Some(i));
        }
        assert!(trend.went_back(0.05) && !trend.went_back(1.3));
        let mut carried_on = trend.clone();
        trend.begin_again(60.0);
        for i in 1..=50 {
            let w = 60.0 + 0.01 * i as f64;
            trend.add(w, 0.1 * (w - 60.0), Some(i));
            carried_on.add(w, 0.1 * (w - 60.0), Some(i));
        }
        assert!(!trend.went_back(0.05 + 1e-9));
        let expected = 60.0 + 10.0 * 1.3;
        assert!((trend.projected(1.3) - expected).abs() < 1e-9 * expected, "{}", trend.projected(1.3));
        assert!(carried_on.projected(1.3) - 60.0 > 10.0 * (expected - 60.0), "{}", carried_on.projected(1.3));
    }
}

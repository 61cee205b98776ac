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

/// What a projection of a run with a packed start says of itself when its trial or its note
/// did not see the package open ([`PACKED_WAIT`]): measured, projections from a packed
/// start alone have been 1.3–19 times the run's wall time (docs/outputs.md, *How
/// projections are made*; the 8 × 4 1.3× on 2026-11-29, the 6 × 3 5–9× and the thick
/// starshade 5–9× since; on 2026-12-01 the thick starshade 18×, the 12 × 7 17× and the
/// 12 × 9 with 0.6 N·m/rad folds 19×).
pub const PACKED_START: &str = "with contact a packed start is the slowest part of a run, and this projection did not see it open: projected from packed starts alone, thick flashers have taken 1.3 to 19 times less (docs/outputs.md)";

/// A run starts packed when at least this many pairs of bodies that no hinge joins touch at
/// its start (a stowed package's layers pressing on each other; a panel resting on the hub
/// is one).
pub const PACKED_PAIRS: usize = 3;

/// A packed start has opened when the pairs of bodies no hinge joins that touch have fallen
/// to this fraction of the most seen: the layers have parted (an opened sheet's touching
/// pairs are mostly hinged neighbours at their creases). Measured on the thick 6 × 3 (66
/// pairs at most, 30 when its steps grew tenfold at t = 0.10 s) and starshade (252, 108 at
/// t = 0.15 s, its steps tenfold too), 2026-12-02.
pub const OPENED_FRACTION: f64 = 0.5;

/// A packed start has opened only when its pace has also quickened: the simulated time per
/// wall time over the last tenth of the run so far (at least half a second of wall time) at
/// least this many times its average since the trend's origin. The touching pairs alone
/// fell to half their most on the 6 × 3 at t = 0.03 s, still packed, as its layers settled;
/// with this, at t = 0.15 s (and the starshade at t = 0.13 s), where the pace rose 4–5 times
/// (2026-12-02).
pub const OPENED_QUICKENING: f64 = 4.0;

/// How many times its usual wait a projection waits for a packed start to open before it
/// projects from the packed start alone (and says so, [`PACKED_START`]): the thick
/// starshade's opened after 36 s of wall time on a 2-core AMD EPYC at load ~1.5.
pub const PACKED_WAIT: f64 = 40.0;

/// How often a projection counts the touching pairs of a run that may be packed, s of wall
/// time (each count costs about one right-hand side's contact).
pub const PACKED_CHECK_EVERY: f64 = 0.1;

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
/// From a packed start ([`PACKED_PAIRS`]) no such trend can see when the package opens (the
/// 6 × 3's first 4 s of a 20-s run reached 0.05 of its 5 s, the starshade's first 36 s of a
/// 122-s run 0.13 of its 60 s; 2-core AMD EPYC, load ~1.5), so its projection waits for the
/// opening ([`Phase`]) and restarts the trend there ([`Trend::restart_opened`]): what came before counts as time
/// spent, and what follows is taken at the cap's quickening, `p` = [`MOST_ACCELERATION`],
/// since a deployment keeps speeding up while its parting layers still touch and after
/// (the starshade's pace rose tenfold over the 13 s it took to unwrap). Measured on those
/// two: 0.8–1.4 times the run's wall time from 2 to 8 s after the opening, where the trend
/// measured in that window gave 2.2–3.7 on the starshade (docs/outputs.md).
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
    /// Whether a packed start opened at the origin or before it: the pace is then taken to
    /// quicken at [`MOST_ACCELERATION`].
    opened: bool,
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

    /// Starts the trend again from its last point because a packed start opened there
    /// ([`Phase::pairs`]): from then on the pace is taken to quicken at the cap.
    pub fn restart_opened(&mut self) {
        self.restart();
        self.opened = true;
    }

    /// Starts the trend afresh at `wall` (s) for a new run from its start (a position
    /// tolerance's next run: simulated time and steps count from zero again). What came
    /// before counts as time spent.
    pub fn begin_again(&mut self, wall: f64) {
        self.samples.clear();
        self.origin = (wall, 0.0, 0);
        self.opened = false;
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

    /// Whether the pace has quickened: the simulated time per wall time over the last tenth
    /// of the wall time since the origin (at least 0.5 s of it) is at least
    /// [`OPENED_QUICKENING`] times the average since the origin.
    pub fn quickened(&self) -> bool {
        let Some(&(w, t, _)) = self.samples.last() else { return false };
        let (w0, t0, _) = self.origin;
        let window = (0.1 * (w - w0)).max(0.5);
        let Some(&(wb, tb, _)) = self.samples.iter().rev().find(|s| s.0 <= w - window) else { return false };
        let average = (t - t0) / (w - w0);
        average > 0.0 && (t - tb) / (w - wb) >= OPENED_QUICKENING * average
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
            _ if self.opened => MOST_ACCELERATION,
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
///
/// A run that starts packed ([`PACKED_PAIRS`]) is seen only once the package has opened
/// ([`OPENED_FRACTION`]) and `after` has passed since, or at [`PACKED_WAIT`] times `after`
/// if it has not; its caller counts the touching pairs when [`Phase::wants_pairs`] says so.
#[derive(Clone, Debug)]
pub struct Phase {
    /// Under `auto`: the fastest hinge's rate, 1/s (see `pace::held_by_stiffness`).
    auto_rate: Option<f64>,
    after: f64,
    method: Option<&'static str>,
    held: bool,
    changes: usize,
    started: f64,
    packed: Packed,
}

/// Whether a run started packed, and whether its package has opened.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Packed {
    /// Not counted yet (a run with contact).
    Unknown,
    /// Not packed (or no contact).
    No,
    /// Packed: the most pairs of bodies no hinge joins touching so far, and when they were
    /// last counted (wall s).
    Yes { most: usize, counted: f64 },
    /// Opened at simulated time `t` (s), `wall` s into the run.
    Opened { t: f64, wall: f64 },
}

impl Phase {
    /// For a run of `model` (under `auto` or not), its pace seen after `after`.
    pub fn new(model: &Model, auto: bool, after: Duration) -> Self {
        let auto_rate = auto.then(|| model.fastest_hinge().map_or(0.0, |r| r.rate));
        let packed = if model.contact.is_some() { Packed::Unknown } else { Packed::No };
        Self { auto_rate, after: after.as_secs_f64(), method: None, held: false, changes: 0, started: 0.0, packed }
    }

    /// Whether the caller should count the pairs of bodies no hinge joins that touch now
    /// ([`Phase::pairs`]): at the start of a run with contact, and every
    /// [`PACKED_CHECK_EVERY`] while it is packed.
    pub fn wants_pairs(&self, wall: f64) -> bool {
        match self.packed {
            Packed::Unknown => true,
            Packed::Yes { counted, .. } => wall - counted >= PACKED_CHECK_EVERY,
            _ => false,
        }
    }

    /// Notes `count` pairs of bodies no hinge joins touching at simulated time `simulated`
    /// (s), `wall` s into the run, whose pace has `quickened` or not ([`Trend::quickened`]);
    /// true when this opens a packed start (the caller restarts its trend there:
    /// [`Trend::restart_opened`]).
    pub fn pairs(&mut self, count: usize, simulated: f64, wall: f64, quickened: bool) -> bool {
        match self.packed {
            Packed::Unknown => {
                self.packed =
                    if count >= PACKED_PAIRS { Packed::Yes { most: count, counted: wall } } else { Packed::No };
                false
            }
            Packed::Yes { most, .. } => {
                let most = most.max(count);
                if quickened && (count as f64) <= OPENED_FRACTION * most as f64 {
                    self.packed = Packed::Opened { t: simulated, wall };
                    self.started = wall;
                    true
                } else {
                    self.packed = Packed::Yes { most, counted: wall };
                    false
                }
            }
            _ => false,
        }
    }

    /// Whether the run started packed and has not opened yet.
    pub fn still_packed(&self) -> bool {
        matches!(self.packed, Packed::Yes { .. })
    }

    /// Where a packed start opened: simulated time (s) and wall time into the run (s).
    pub fn opened(&self) -> Option<(f64, f64)> {
        match self.packed {
            Packed::Opened { t, wall } => Some((t, wall)),
            _ => None,
        }
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
        if self.still_packed() {
            return wall >= PACKED_WAIT * self.after;
        }
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
    /// Where a packed start opened: simulated time (s) and wall time into the trial (s).
    pub opened: Option<(f64, f64)>,
    /// Whether the trial started packed and ended before the package opened.
    pub still_packed: bool,
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
        if let Some((t, wall)) = self.opened {
            trend = format!(
                ", its packed start opening at t = {t:.4} s after {wall:.1} s; projected from its pace since, as a deployment that keeps quickening"
            );
        } else if self.since.0 > 0.0 {
            trend =
                format!(", projected from its pace since it changed to {} at t = {:.4} s", self.since.1, self.since.0);
        }
        if p < 0.9 * linear && self.opened.is_none() {
            let along = if trend.is_empty() { ", projected along" } else { " and along" };
            trend += &format!("{along} its quickening pace; at its average pace {}", human_seconds(linear));
        }
        let packed = if self.still_packed { format!("; {PACKED_START}") } else { String::new() };
        format!(
            "{shown} on this machine (a {:.1}-s trial reached t = {:.4} s of {} s{trend}; steps change as it deploys){packed}",
            self.wall, self.simulated, self.duration
        )
    }
}

pub use super::pace::human_seconds;
pub use super::rerun::Rerun;

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
        if phase.wants_pairs(wall) && phase.pairs(p.unhinged_pairs_touching(), p.t, wall, trend.quickened()) {
            trend.restart_opened();
        }
        if phase.seen(wall) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    };
    let result = simulate(model, initial, settings, &mut sink, Some(&mut progress));
    let since = (trend.since(), phase.method.unwrap_or(""));
    let (opened, still_packed) = (phase.opened(), phase.still_packed());
    let wall = started.elapsed().as_secs_f64();
    let simulated = last_t.max(reached);
    let duration = settings.duration;
    let trend = trend.projected(duration);
    match result {
        Ok(_) => Estimate {
            simulated: duration,
            wall,
            duration,
            complete: true,
            failed: false,
            trend: wall,
            since,
            opened,
            still_packed: false,
        },
        Err(super::SimError::Interrupted { t }) => Estimate {
            simulated: t.max(simulated),
            wall,
            duration,
            complete: false,
            failed: false,
            trend,
            since,
            opened,
            still_packed,
        },
        Err(_) => {
            Estimate { simulated, wall, duration, complete: false, failed: true, trend, since, opened, still_packed }
        }
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
        let auto = Phase {
            auto_rate: Some(1e4),
            after: 2.0,
            method: None,
            held: false,
            changes: 0,
            started: 0.0,
            packed: Packed::No,
        };
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

    /// A packed start (40 pairs of bodies no hinge joins touching, 0.01 simulated s per s of
    /// wall) is not seen while it stays packed, even past its wait, nor when its pairs fall
    /// by half without its pace quickening (the layers settling); it opens where both happen
    /// (at 5 s of wall, the pairs 10, then t − 0.05 = 0.2 (w − 5)^1.4), is seen `after` later,
    /// and is projected from there at the cap's quickening: within 10 % of its end (the
    /// opening is found once the pace over the last half second has quickened fourfold, a
    /// few tenths after 5 s, so the power law does not start at the trend's origin), where its
    /// trend from the start projected it more than twice too long. A run that never opens is seen at
    /// [`PACKED_WAIT`] times its wait; one with two pairs touching is not packed.
    #[test]
    fn a_packed_start_is_projected_from_its_opening() {
        let new = || Phase {
            auto_rate: None,
            after: 2.0,
            method: None,
            held: false,
            changes: 0,
            started: 0.0,
            packed: Packed::Unknown,
        };
        let t_at = |w: f64| if w <= 5.0 { 0.01 * w } else { 0.05 + 0.2 * (w - 5.0).powf(1.4) };
        let duration: f64 = 10.0;
        let end = 5.0 + ((duration - 0.05) / 0.2).powf(1.0 / 1.4);
        let (mut phase, mut trend, mut from_start) = (new(), Trend::default(), Trend::default());
        let mut seen_at = None;
        for i in 1..=2000 {
            let w = 0.01 * i as f64;
            let t = t_at(w);
            // Settling: the pairs fall to 18 at 3 s with the pace unchanged.
            let pairs = if w > 5.0 {
                10
            } else if w > 3.0 {
                18
            } else {
                40
            };
            assert!(!phase.changed("sdirk4", 1e-4, w));
            trend.add(w, t, Some(i));
            from_start.add(w, t, Some(i));
            if phase.wants_pairs(w) && phase.pairs(pairs, t, w, trend.quickened()) {
                trend.restart_opened();
            }
            if w <= 5.0 {
                assert!(phase.still_packed() && !phase.seen(w), "packed at {w}");
            }
            if seen_at.is_none() && phase.seen(w) {
                seen_at = Some(w);
                let projected = trend.projected(duration);
                assert!((projected - end).abs() < 0.1 * end, "{projected} vs {end}");
                assert!(from_start.projected(duration) > 2.0 * end, "{}", from_start.projected(duration));
            }
        }
        let (t_open, w_open) = phase.opened().expect("opened");
        assert!(w_open > 5.0 && w_open < 5.5, "opened at {w_open}");
        assert!((t_open - t_at(w_open)).abs() < 1e-12);
        let seen = seen_at.unwrap();
        assert!(seen >= w_open + 2.0 && seen < w_open + 2.0 + 0.02, "seen at {seen}");
        // Never opening: seen at the wait's end. Two pairs: not packed.
        let mut stuck = new();
        stuck.pairs(40, 0.0, 0.0, false);
        assert!(!stuck.seen(PACKED_WAIT * 2.0 - 1e-9) && stuck.seen(PACKED_WAIT * 2.0));
        let mut loose = new();
        assert!(loose.wants_pairs(0.0));
        loose.pairs(2, 0.0, 0.0, false);
        assert!(!loose.still_packed() && !loose.wants_pairs(1.0) && loose.seen(2.0));
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

//! What a long command says while it works, beyond the progress bar on a terminal: a
//! one-line report to standard error at least every [`REPORT_EVERY`] when standard error is
//! not a terminal (scripts, notebooks, CI), and, once, after [`NOTE_AFTER`] of wall time, a
//! note when the whole run is projected to take more than [`LONG`] (even under `--quiet`: a
//! run of hours should never start in silence). Projections follow the run's trend
//! (`foldsim::simulate::estimate::Trend`): a deployment from a packed start speeds up, and
//! under `auto` a stiff model's first DOP853 steps are no guide to the implicit method that follows
//! (the note waits for the switch, and a packed start's for the package to open:
//! `estimate::Phase`).

use foldsim::simulate::estimate::{Phase, Rerun, Trend, human_seconds};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// How often a run off a terminal reports its progress (the environment variable
/// `FOLDSIM_PROGRESS_EVERY`, in seconds, changes it: for logs that want more, and for tests).
pub(crate) const REPORT_EVERY: Duration = Duration::from_secs(30);

fn report_every() -> Duration {
    std::env::var("FOLDSIM_PROGRESS_EVERY")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s > 0.0)
        .map_or(REPORT_EVERY, Duration::from_secs_f64)
}
/// A run projected longer than this says so early.
pub(crate) const LONG: f64 = 60.0;

/// When the note comes, s of wall time: a packed start's trend shows after about two seconds
/// (docs/outputs.md has the measurements).
pub(crate) const NOTE_AFTER: f64 = 2.0;

/// The progress bar a long command draws on a terminal (`None` under `--quiet` or when
/// standard error is not a terminal, where [`Watch`] reports in lines instead): `len` steps,
/// `counted` the text before the bar (an `indicatif` template, e.g. `"run {pos}/{len} {msg}"`).
pub(crate) fn progress_bar(quiet: bool, len: u64, counted: &str) -> Option<indicatif::ProgressBar> {
    (!quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(len);
        bar.set_style(
            indicatif::ProgressStyle::with_template(&format!("{{spinner}} {counted} [{{bar:40}}] eta {{eta}}"))
                .expect("static progress template")
                .progress_chars("=> "),
        );
        bar
    })
}

/// Watches one command's progress.
pub(crate) struct Watch {
    what: &'static str,
    started: Instant,
    last_report: Instant,
    lines: bool,
    every: Duration,
    warned: bool,
    trend: Trend,
    /// A run's method and when it changed (`None` for a sweep).
    phase: Option<Phase>,
    /// Runs begun (a position tolerance makes several, each from the start).
    runs: usize,
    /// A later run projected against the one before it.
    rerun: Rerun,
}

impl Watch {
    /// A watch of `what` (`foldsim run`); lines off a terminal unless `quiet`; `phase` for a
    /// run (its note comes once its pace in the method in use has been seen).
    pub(crate) fn new(what: &'static str, quiet: bool, phase: Option<Phase>) -> Self {
        let now = Instant::now();
        let lines = !quiet && !std::io::stderr().is_terminal();
        Self {
            what,
            started: now,
            last_report: now,
            lines,
            every: report_every(),
            warned: false,
            trend: Trend::default(),
            phase,
            runs: 1,
            rerun: Rerun::default(),
        }
    }

    /// Whether the run may still be in a packed start and wants its touching pairs counted
    /// now ([`Watch::pairs`]; `estimate::Phase`).
    pub(crate) fn wants_pairs(&self) -> bool {
        let wall = self.started.elapsed().as_secs_f64();
        self.runs == 1 && self.phase.as_ref().is_some_and(|p| p.wants_pairs(wall))
    }

    /// `count` pairs of bodies no hinge joins touch at simulated time `done` (s), the last
    /// point given to [`Watch::tick`]: where a packed start opens, the projection's trend
    /// starts again.
    pub(crate) fn pairs(&mut self, count: usize, done: f64) {
        let wall = self.started.elapsed().as_secs_f64();
        let quickened = self.trend.quickened();
        if let Some(phase) = self.phase.as_mut()
            && phase.pairs(count, done, wall, quickened)
        {
            self.trend.restart_opened();
        }
    }

    /// Whether the run started packed and has not opened yet.
    pub(crate) fn still_packed(&self) -> bool {
        self.phase.as_ref().is_some_and(|p| p.still_packed())
    }

    /// Progress `done` of `total` (simulated seconds, or runs), with `unit` (`s`, `runs`), in
    /// `steps` accepted steps with the last `step` (s) taken by `method` (a run's; `None` for
    /// runs of a sweep); `hint` says, when asked (once, for a long run), what holds it back
    /// and what would shorten it.
    pub(crate) fn tick(
        &mut self,
        done: f64,
        total: f64,
        unit: &str,
        steps: Option<(usize, f64, &'static str)>,
        hint: impl FnOnce() -> String,
    ) {
        let wall = self.started.elapsed().as_secs_f64();
        // A run made again from its start (a position tolerance's next): its own trend.
        if steps.is_some() && self.trend.went_back(done) {
            self.trend.begin_again(wall);
            self.rerun.begin_again(wall);
            self.runs += 1;
        }
        self.rerun.add(wall, done);
        if let (Some(phase), Some((_, step, method))) = (self.phase.as_mut(), steps)
            && phase.changed(method, step, wall)
        {
            self.trend.restart();
        }
        self.trend.add(wall, done, steps.map(|s| s.0));
        let left = match self.rerun.left(wall, done) {
            Some(left) if self.runs > 1 => left,
            _ => self.trend.projected(total) - wall,
        };
        let seen = self.phase.as_ref().map_or(wall >= NOTE_AFTER, |p| wall >= NOTE_AFTER && p.seen(wall));
        if !self.warned && seen {
            self.warned = true;
            if wall + left > LONG {
                let projected =
                    if left.is_finite() { format!("about {}", human_seconds(wall + left)) } else { "very long".into() };
                let opened = match self.phase.as_ref().and_then(|p| p.opened()) {
                    Some((t, w)) => format!(
                        "; its packed start opened at t = {t:.4} s after {w:.1} s, and the rest is projected from its pace since as a deployment that keeps quickening (docs/outputs.md)"
                    ),
                    None => String::new(),
                };
                eprintln!(
                    "note: {} will take {projected} ({done:.4} of {total} {unit} after {wall:.1} s{opened}); {}",
                    self.what,
                    hint()
                );
            }
        }
        if self.lines && self.last_report.elapsed() >= self.every {
            self.last_report = Instant::now();
            let this = if self.runs > 1 { " in this run" } else { "" };
            // A packed start's own pace says nothing of the rest (docs/outputs.md): no
            // figure until it opens or the note gives up waiting.
            let waiting = self.phase.as_ref().is_some_and(|p| p.still_packed() && !p.seen(wall));
            let left = if waiting {
                "time left projected once its packed start opens".into()
            } else if left.is_finite() {
                format!("about {} left{this}", human_seconds(left))
            } else {
                "time left unknown".into()
            };
            let run = if self.runs > 1 { format!(" (run {})", self.runs) } else { String::new() };
            eprintln!(
                "{}{run}: {done:.4} of {total} {unit} ({:.0} %), {} so far, {left}",
                self.what,
                100.0 * done / total,
                human_seconds(wall)
            );
        }
    }
}

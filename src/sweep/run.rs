//! Running a sweep: each run's values drawn from its own random stream, the scenario changed
//! and built, run with its metrics taken as it streams, over a pool of worker threads, with
//! the rows handed on in run order.

use super::metrics::{BUILT_IN, Resolved, Tracker, resolve};
use super::spec::{Distribution, Metric, SweepSpec, read};
use crate::observe::Observation;
use crate::scenario::{ScenarioError, ScenarioText, SetValue};
use crate::simulate::{RunSettings, SimError, simulate};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution as _, Normal};
use rayon::iter::{ParallelBridge, ParallelIterator};
use std::collections::BTreeMap;
use std::ops::{ControlFlow, Range};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

/// A sweep ready to run: the nominal scenario's text and its `[sweep]` table.
#[derive(Clone, Debug)]
pub struct Sweep {
    text: ScenarioText,
    spec: SweepSpec,
    metrics: Vec<Resolved>,
    header: Vec<String>,
    inputs: Vec<std::path::PathBuf>,
    /// Whether a metric reads a hinge-load column (`RunSettings::hinge_loads`).
    hinge_loads: bool,
}

/// One run's row of the summary table.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// Run index, 0-based.
    pub run: usize,
    /// The swept values, in the order of `[sweep.parameters]`.
    pub values: Vec<f64>,
    /// The requested metrics then the built-in ones ([`BUILT_IN`]); `None` where a run has
    /// none (no crossing, no latch, or the run failed).
    pub metrics: Vec<Option<f64>>,
    /// Why the run failed, if it did.
    pub error: Option<String>,
}

impl Sweep {
    /// Reads a sweep file: a scenario with a `[sweep]` table.
    pub fn from_file(path: &Path) -> Result<Self, ScenarioError> {
        Self::new(ScenarioText::from_file(path)?)
    }

    /// A sweep of scenario text whose `[sweep]` table says what to vary. Checks the table,
    /// that the nominal scenario builds, that every key path can be set, and that every
    /// metric's column or hinge exists.
    pub fn new(text: ScenarioText) -> Result<Self, ScenarioError> {
        let source = text.text();
        let spec = read(&source, &text.file)?.ok_or_else(|| ScenarioError {
            file: text.file.clone(),
            location: None,
            message:
                "no [sweep] table: a sweep file is a scenario with a [sweep] table saying what to vary (docs/sweep.md)"
                    .into(),
        })?;
        Self::with_spec(text, spec)
    }

    /// A sweep of a scenario with the given specification (its own `[sweep]` table, if any,
    /// is not used).
    pub fn with_spec(text: ScenarioText, spec: SweepSpec) -> Result<Self, ScenarioError> {
        let fail = |message: String| ScenarioError { file: text.file.clone(), location: None, message };
        let nominal = text.build()?;
        let mut probe = text.clone();
        for p in &spec.parameters {
            let x = sample_first(&p.distribution);
            probe.set(&p.path, &SetValue::Number(x)).map_err(|e| fail(format!("[sweep.parameters]: {e}")))?;
        }
        check_paths(&text, &spec).map_err(|e| fail(format!("[sweep.parameters]: {e}")))?;
        let metrics = resolve(&spec.metrics, &nominal.model).map_err(|e| fail(format!("[sweep.metrics]: {e}")))?;
        let mut header = vec!["run".to_string(), "status".to_string()];
        header.extend(spec.parameters.iter().map(|p| p.path.clone()));
        header.extend(spec.metrics.iter().map(|(name, _)| name.clone()));
        header.extend(BUILT_IN.iter().map(|(name, _)| name.to_string()));
        header.push("error".into());
        let mut seen = std::collections::HashSet::new();
        if let Some(dup) = header.iter().find(|h| !seen.insert(h.as_str())) {
            return Err(fail(format!("[sweep.metrics]: '{dup}' names two columns of the summary; rename the metric")));
        }
        let text = text.without_trailing_table("sweep");
        let hinge_loads = spec
            .metrics
            .iter()
            .any(|(_, m)| matches!(m, Metric::Column { column, .. } if crate::observe::is_hinge_load(column)));
        Ok(Self { text, spec, metrics, header, inputs: nominal.inputs, hinge_loads })
    }

    /// The files the nominal scenario reads (the scenario file, if it was read from one, and
    /// its table files): what no output of the sweep may replace.
    pub fn inputs(&self) -> &[std::path::PathBuf] {
        &self.inputs
    }

    /// The specification.
    pub fn spec(&self) -> &SweepSpec {
        &self.spec
    }

    /// The number of runs.
    pub fn runs(&self) -> usize {
        self.spec.runs
    }

    /// Changes the run count (not for a sweep of explicit lists, whose length it is).
    pub fn set_runs(&mut self, runs: usize) -> Result<(), String> {
        if self.spec.parameters.iter().any(|p| matches!(p.distribution, Distribution::List(_)))
            && runs != self.spec.runs
        {
            return Err(format!("this sweep's lists give {} runs; the run count cannot differ", self.spec.runs));
        }
        if runs == 0 || runs > super::spec::MAX_RUNS {
            return Err(format!("a sweep takes 1 to {} runs; got {runs}", super::spec::MAX_RUNS));
        }
        self.spec.runs = runs;
        Ok(())
    }

    /// Changes the seed.
    pub fn set_seed(&mut self, seed: u64) {
        self.spec.seed = seed;
    }

    /// The summary table's column names: `run`, `status`, the swept key paths, the requested
    /// metrics, the built-in ones, `error`.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// The values run `run` takes, in the order of `[sweep.parameters]`: drawn from stream
    /// `run` of a ChaCha8 generator seeded with the sweep's seed, so they depend on the seed
    /// and the run index only (not on which worker runs it, or when).
    pub fn values(&self, run: usize) -> Vec<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(self.spec.seed);
        rng.set_stream(run as u64);
        self.spec
            .parameters
            .iter()
            .map(|p| match &p.distribution {
                Distribution::Normal { mean, sd } => Normal::new(*mean, *sd).expect("sd > 0, checked").sample(&mut rng),
                Distribution::Uniform { low, high } => low + (high - low) * rng.random::<f64>(),
                Distribution::LogUniform { low, high } => {
                    (low.ln() + (high.ln() - low.ln()) * rng.random::<f64>()).exp()
                }
                Distribution::Choice(v) => v[rng.random_range(0..v.len())],
                Distribution::List(v) => v[run],
            })
            .collect()
    }

    /// Runs run `run` (on this thread). A failure (a drawn value the scenario refuses, an
    /// integration that stops, even a panic) is recorded in the row, not returned. `stop`
    /// set ends the run early, recorded as interrupted.
    pub fn run_one(&self, run: usize, stop: &AtomicBool) -> SweepRow {
        let values = self.values(run);
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.simulate(&values, stop)));
        let outcome = outcome.unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Err(format!("internal error (please report it): {what}"))
        });
        match outcome {
            Ok(metrics) => SweepRow { run, values, metrics, error: None },
            Err(e) => SweepRow { run, values, metrics: vec![None; self.metric_count()], error: Some(e) },
        }
    }

    fn metric_count(&self) -> usize {
        self.metrics.len() + BUILT_IN.len()
    }

    fn simulate(&self, values: &[f64], stop: &AtomicBool) -> Result<Vec<Option<f64>>, String> {
        let mut text = self.text.clone();
        for (p, x) in self.spec.parameters.iter().zip(values) {
            text.set(&p.path, &SetValue::Number(*x))?;
        }
        let s = text.build().map_err(|e| e.to_string())?;
        let mut tracker = Tracker::new(&self.metrics);
        let mut sink = |o: &Observation| -> Result<(), String> {
            tracker.record(o);
            Ok(())
        };
        let mut progress = |_: &crate::simulate::Progress<'_, '_>| {
            if stop.load(Ordering::Relaxed) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
        };
        // A metric of a hinge-load column needs the locks' reactions in it, as the CSV has.
        let settings = RunSettings { hinge_loads: self.hinge_loads, ..s.settings };
        match simulate(&s.model, &s.initial, &settings, &mut sink, Some(&mut progress)) {
            Ok(report) => Ok(tracker.finish(&report)),
            Err(SimError::Interrupted { t }) => Err(format!("interrupted at t = {t} s")),
            Err(e) => Err(e.to_string()),
        }
    }

    /// Runs `runs` on `workers` threads, handing each row to `on_row` in run order as soon
    /// as it and every run before it are done. Stops (with `Err`) when `on_row` fails or
    /// `stop` is set; the rows handed on until then are complete.
    pub fn run(
        &self,
        runs: Range<usize>,
        workers: usize,
        stop: &AtomicBool,
        on_row: &mut dyn FnMut(SweepRow) -> Result<(), String>,
    ) -> Result<(), String> {
        if runs.end > self.runs() {
            return Err(format!("runs {}..{} asked of a sweep of {}", runs.start, runs.end, self.runs()));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(workers.max(1))
            .build()
            .map_err(|e| format!("cannot start {workers} worker threads: {e}"))?;
        let (tx, rx) = mpsc::channel::<SweepRow>();
        let first = runs.start;
        std::thread::scope(|scope| {
            let indices = runs.clone();
            scope.spawn(move || {
                // `par_bridge` hands the runs out in order as workers free up, so rows come
                // back nearly in order and few wait to be written.
                pool.install(|| {
                    indices.par_bridge().for_each_with(tx, |tx, i| {
                        if !stop.load(Ordering::Relaxed) {
                            let row = self.run_one(i, stop);
                            // A run cut short by `stop` is not a result: it is not handed on.
                            if !stop.load(Ordering::Relaxed) {
                                let _ = tx.send(row);
                            }
                        }
                    })
                })
            });
            let mut waiting = BTreeMap::new();
            let mut next = first;
            let mut result = Ok(());
            for row in rx {
                if result.is_err() {
                    continue;
                }
                waiting.insert(row.run, row);
                while let Some(row) = waiting.remove(&next) {
                    next += 1;
                    if let Err(e) = on_row(row) {
                        stop.store(true, Ordering::Relaxed);
                        result = Err(e);
                        break;
                    }
                }
            }
            result?;
            if next < runs.end {
                return Err(format!("stopped after {} of {} runs", next - first, runs.len()));
            }
            Ok(())
        })
    }
}

/// A value in the distribution's support, to check that its key path can be set.
/// Refuses, before any run, swept paths that could only give failed or silently wrong runs:
/// a path into `[sweep]` itself, two paths naming one value, a path whose value is not a
/// number, and a key the scenario does not hold that a trial edit shows it cannot take (a
/// misspelt key: every run would fail).
fn check_paths(text: &ScenarioText, spec: &SweepSpec) -> Result<(), String> {
    let paths: Vec<&str> = spec.parameters.iter().map(|p| p.path.as_str()).collect();
    if let Some(p) = paths.iter().find(|p| p.split('.').next() == Some("sweep")) {
        return Err(format!("'{p}' is inside [sweep] itself: a sweep varies the scenario, not its own table"));
    }
    text.check_distinct(&paths)?;
    for p in &spec.parameters {
        let mut absent = false;
        for at in text.locations(&p.path)? {
            match text.get(&at)? {
                Some(v) if v.parse::<toml_edit::Value>().is_ok_and(|v| v.is_integer() || v.is_float()) => {}
                Some(v) => {
                    return Err(format!("'{}' names {at}, which holds {v}: a sweep draws numbers", p.path));
                }
                None => absent = true,
            }
        }
        if absent {
            let x = typical(&p.distribution);
            let mut trial = text.clone();
            trial.set(&p.path, &SetValue::Number(x))?;
            if let Err(e) = trial.build() {
                return Err(format!(
                    "'{}' is not in the scenario, and a trial run's scenario with it set to {x} is refused: {}",
                    p.path, e.message
                ));
            }
        }
    }
    Ok(())
}

/// A value a distribution typically draws: its mean or middle, or its first value.
fn typical(d: &Distribution) -> f64 {
    match d {
        Distribution::Normal { mean, .. } => *mean,
        Distribution::Uniform { low, high } => 0.5 * (low + high),
        Distribution::LogUniform { low, high } => (low * high).sqrt(),
        Distribution::Choice(v) | Distribution::List(v) => v[0],
    }
}

fn sample_first(d: &Distribution) -> f64 {
    match d {
        Distribution::Normal { mean, .. } => *mean,
        Distribution::Uniform { low, .. } | Distribution::LogUniform { low, .. } => *low,
        Distribution::Choice(v) | Distribution::List(v) => v[0],
    }
}

//! `foldsim run`: a scenario run to CSV, with its animation and report.

use foldsim::observe::Selection;
use foldsim::output::CsvSink;
#[cfg(feature = "animation")]
use foldsim::output::animation::Frames;
use foldsim::output::paths::check_outputs;
use foldsim::scenario::Scenario;
use foldsim::simulate::{Sink, simulate};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Output estimated above this many bytes is refused unless `--large-output` is given.
pub(crate) const LARGE_OUTPUT: f64 = 1024.0 * 1024.0 * 1024.0;

/// Bytes a CSV field takes on average (shortest round-trip digits, sign, exponent, comma).
pub(crate) const BYTES_PER_FIELD: f64 = 22.0;

pub(crate) fn run(
    path: &Path,
    (csv, contacts, events): (Option<PathBuf>, Option<PathBuf>, Option<PathBuf>),
    columns: Option<Vec<String>>,
    large_output: bool,
    quiet: bool,
    animation: Option<(PathBuf, Option<f64>)>,
    page: Option<(&Path, Option<f64>)>,
) -> Result<(PathBuf, Option<Frames>), String> {
    let scenario = Scenario::from_file(path).map_err(|e| e.to_string())?;
    if let Some((_, fps)) = &animation {
        check_fps(*fps)?;
    }
    for w in &scenario.warnings {
        eprintln!("warning: {w}");
    }
    let csv_label = if csv.is_some() {
        "--csv"
    } else if scenario.csv.is_some() {
        "run.csv"
    } else {
        "the output CSV"
    };
    let target = csv.or_else(|| scenario.csv.clone()).unwrap_or_else(|| {
        let stem = path.file_stem().map_or_else(|| "foldsim".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.csv"))
    });
    let columns = match columns {
        Some(patterns) => Selection::matching(&scenario.model, &patterns).map_err(|m| format!("--columns: {m}"))?,
        None => scenario.columns.clone(),
    };
    let mut outputs: Vec<(&str, &Path)> = vec![(csv_label, &target)];
    if let Some((glb, _)) = &animation {
        outputs.push(("--animation", glb));
    }
    if let Some((page, fps)) = page {
        check_fps(fps)?;
        outputs.push(("--view", page));
    }
    if let Some(c) = &contacts {
        if scenario.model.contact.is_none() {
            return Err(format!(
                "--contacts {}: the scenario has no [contact] table, so no contact to log",
                c.display()
            ));
        }
        outputs.push(("--contacts", c));
    }
    if let Some(e) = &events {
        outputs.push(("--events", e));
    }
    check_outputs(&scenario.inputs, &outputs)?;
    if let Some(c) = &contacts {
        check_extension("--contacts", c, "csv", "a CSV table")?;
    }
    if let Some(e) = &events {
        check_extension("--events", e, "csv", "a CSV table")?;
    }
    // Then each named as what it holds (after the checks against overwriting an input).
    use foldsim::output::paths::{GLB, HTML, check_extension};
    if let Some((glb, _)) = &animation {
        check_extension("--animation", glb, GLB.0, GLB.1)?;
    }
    if let Some((page, _)) = page {
        check_extension("--view", page, HTML.0, HTML.1)?;
    }
    let settings = &foldsim::simulate::RunSettings { hinge_loads: columns.has_hinge_loads(), ..scenario.settings };
    let rows = (settings.duration / settings.output_step).floor() + 2.0;
    let bytes = rows * columns.names.len() as f64 * BYTES_PER_FIELD;
    if bytes > LARGE_OUTPUT && !large_output {
        return Err(format!(
            "{}: this run would write about {:.1} GiB ({rows:.3e} rows of {} columns): raise run.output_step, choose fewer columns (run.columns or --columns), or pass --large-output to write it anyway",
            path.display(),
            bytes / LARGE_OUTPUT,
            columns.names.len()
        ));
    }
    let stale = target.is_file().then(|| target.clone());
    let mut sink = CsvSink::create(&target, &columns)?;
    let duration = settings.duration;

    // Ctrl-C (and SIGTERM, SIGHUP: the crate's "termination" feature) stops the run at its
    // next step, which then says where it stopped.
    let interrupted = Arc::new(AtomicBool::new(false));
    let flag = interrupted.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));

    let bar = crate::watch::progress_bar(quiet, 1000, "t = {msg} {percent}%");
    let auto = matches!(settings.integrator, foldsim::simulate::settings::Integrator::Auto { .. });
    let phase = foldsim::simulate::estimate::Phase::new(
        &scenario.model,
        auto,
        std::time::Duration::from_secs_f64(crate::watch::NOTE_AFTER),
    );
    let mut watch = crate::watch::Watch::new("foldsim run", quiet, Some(phase));
    let mut tick = |p: &foldsim::simulate::Progress<'_, '_>| {
        let t = p.t;
        // A packed start not yet open when the note comes: its projection cannot see past it.
        let packed = watch.still_packed();
        watch.tick(t, duration, "s", Some((p.steps, p.step, p.method)), || {
            // Before its first step a run has no step size to show (a large model with
            // contact can take seconds over it).
            let steps = if p.step > 0.0 {
                format!("steps of {:.2e} s ({})", p.step, p.method)
            } else {
                format!("no step finished yet ({})", p.method)
            };
            let caveat =
                if packed { format!("{}; ", foldsim::simulate::estimate::PACKED_START) } else { String::new() };
            format!("{caveat}{steps}; what holds them back: {}; or shorten run.duration. Ctrl-C stops it", p.pace())
        });
        if watch.wants_pairs() {
            watch.pairs(p.unhinged_pairs_touching(), t);
        }
        if let Some(b) = &bar {
            b.set_position((1000.0 * t / duration) as u64);
            b.set_message(format!("{t:.3} s"));
        }
        if interrupted.load(Ordering::SeqCst) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    };
    // Frames for the animation and the page: the page's from the run itself, since the rows
    // alone miss contacts shorter than a row.
    let fps = animation.as_ref().and_then(|(_, fps)| *fps).or(page.and_then(|(_, fps)| fps));
    let mut frames = (animation.is_some() || page.is_some()).then(|| Frames::new(scenario.model.bodies.len(), fps));
    let result = {
        let mut both = |o: &foldsim::observe::Observation| -> Result<(), String> {
            sink.record(o)?;
            if let Some(f) = frames.as_mut() {
                f.push(o);
            }
            Ok(())
        };
        simulate(&scenario.model, &scenario.initial, settings, &mut both, Some(&mut tick))
    };
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    match result {
        Ok(report) => {
            let written = sink.finish()?;
            if !quiet {
                crate::report::print_report(&scenario, &report, &written, events.as_deref());
            }
            if let Some(f) = frames.as_mut() {
                f.finish();
            }
            if let (Some((glb, _)), Some(frames)) = (animation, &frames) {
                write_animation(&scenario.model, frames, &glb, quiet)?;
            }
            if let Some(c) = &contacts {
                let names: Vec<&str> = scenario.model.bodies.iter().map(|b| b.name.as_str()).collect();
                let table = foldsim::contact::episodes::episodes_csv(&report.contact_episodes, &names);
                write_table(c, &table, ("contact episodes", report.contact_episodes.len()), quiet)?;
            }
            if let Some(e) = &events {
                let names: Vec<&str> = scenario.model.hinges.iter().map(|h| h.name.as_str()).collect();
                let table = foldsim::output::events::events_csv(&report.events, &names);
                write_table(e, &table, ("hinge events", report.events.len()), quiet)?;
            }
            Ok((written, frames))
        }
        Err(e) => {
            let partial = sink.partial_path().to_path_buf();
            drop(sink);
            let mut message = if scenario.settings.position_tolerance.is_some() {
                // Nothing was written: only an accepted run's rows are.
                let _ = std::fs::remove_file(&partial);
                format!(
                    "{}: {e}\nno rows written: a run held to run.position_tolerance writes only the run it accepts",
                    path.display()
                )
            } else {
                format!("{}: {e}\nthe rows written before it stopped are in {}", path.display(), partial.display())
            };
            if let Some(old) = stale.filter(|old| *old != partial) {
                message.push_str(&format!("\n{} is an earlier run's complete output, left as it was", old.display()));
            }
            Err(message)
        }
    }
}

#[cfg(not(feature = "animation"))]
pub(crate) struct Frames;

#[cfg(not(feature = "animation"))]
impl Frames {
    pub(crate) fn new(_: usize, _: Option<f64>) -> Self {
        Frames
    }
    pub(crate) fn push(&mut self, _: &foldsim::observe::Observation) {}
    pub(crate) fn finish(&mut self) {}
}

#[cfg(not(feature = "animation"))]
pub(crate) fn write_animation(_: &foldsim::model::Model, _: &Frames, _: &Path, _: bool) -> Result<(), String> {
    Ok(())
}

/// Writes a finished run's side table (`--contacts`, `--events`) whole, and says so: `what`
/// it holds and how many rows.
fn write_table(path: &Path, table: &str, (what, rows): (&str, usize), quiet: bool) -> Result<(), String> {
    foldsim::output::paths::write_atomically(path, table.as_bytes())?;
    if !quiet {
        outln!("  {what:<16} {rows} -> {}", path.display());
    }
    Ok(())
}

/// Refuses an animation frame rate that is not positive.
pub(crate) fn check_fps(fps: Option<f64>) -> Result<(), String> {
    match fps {
        Some(f) if !(f.is_finite() && f > 0.0) => {
            Err(format!("the animation's frame rate must be a positive number of frames per second; got {f}"))
        }
        _ => Ok(()),
    }
}

#[cfg(feature = "animation")]
pub(crate) fn write_animation(
    model: &foldsim::model::Model,
    frames: &Frames,
    glb: &Path,
    quiet: bool,
) -> Result<(), String> {
    let written = foldsim::output::animation::write_glb(model, frames, glb)?;
    if !quiet {
        outln!(
            "  animation        {} frames, {:.1} MB -> {}",
            written.frames,
            written.bytes as f64 / 1e6,
            glb.display()
        );
    }
    Ok(())
}

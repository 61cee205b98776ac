//! `foldsim sweep`: a sweep's runs on every core, its table streamed to CSV.

use foldsim::output::paths::{check_outputs, partial_path};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// `foldsim sweep`: runs the sweep, streaming its rows to `<output>.partial`, renamed to
/// `output` once every run is done.
pub(crate) fn sweep(
    path: &Path,
    output: Option<PathBuf>,
    workers: Option<usize>,
    runs: Option<usize>,
    seed: Option<u64>,
    quiet: bool,
) -> Result<(), String> {
    let mut sweep = foldsim::sweep::Sweep::from_file(path).map_err(|e| e.to_string())?;
    if let Some(n) = runs {
        sweep.set_runs(n).map_err(|e| format!("--runs: {e}"))?;
    }
    if let Some(s) = seed {
        sweep.set_seed(s);
    }
    let mut workers = match workers {
        Some(0) => return Err("--workers must be at least 1".into()),
        Some(w) => w,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    if workers > sweep.runs() {
        eprintln!("note: {workers} workers for {} runs: using {}", sweep.runs(), sweep.runs());
        workers = sweep.runs();
    }
    let target = output.unwrap_or_else(|| {
        let stem = path.file_stem().map_or_else(|| "foldsim".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}-sweep.csv"))
    });
    if target.extension().is_some_and(|e| e.eq_ignore_ascii_case("parquet")) {
        return Err(format!(
            "{}: the command line writes the summary as CSV; for Parquet, run the sweep from Python (foldsim.sweep(...).to_parquet(...), docs/sweep.md)",
            target.display()
        ));
    }
    check_outputs(sweep.inputs(), &[("-o", &target)])?;
    let partial = partial_path(&target);
    let file = std::fs::File::create(&partial).map_err(|e| format!("cannot write {}: {e}", partial.display()))?;
    let mut table = foldsim::sweep::CsvTable::new(std::io::BufWriter::new(file), sweep.header())?;

    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    let total = sweep.runs();
    let bar = crate::watch::progress_bar(quiet, total as u64, "run {pos}/{len} {msg}");
    let started = std::time::Instant::now();
    let mut failed = 0usize;
    let mut first_error: Option<String> = None;
    let mut watch = crate::watch::Watch::new("foldsim sweep", quiet, None);
    let mut done = 0usize;
    let result = sweep.run(0..total, workers, &stop, &mut |row| {
        done += 1;
        watch.tick(done as f64, total as f64, "runs", None, || {
            "fewer runs, shorter runs, or more workers shorten it".into()
        });
        failed += usize::from(row.error.is_some());
        if first_error.is_none() {
            first_error = row.error.as_ref().map(|e| format!("run {}: {e}", row.run));
        }
        if let Some(b) = &bar {
            b.inc(1);
            b.set_message(format!("({failed} failed)"));
        }
        table.write(&row)
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    table.finish()?;
    if let Err(e) = result {
        return Err(format!("{}: {e}\nthe rows of the runs done are in {}", path.display(), partial.display()));
    }
    std::fs::rename(&partial, &target)
        .map_err(|e| format!("cannot rename {} to {}: {e}", partial.display(), target.display()))?;
    if failed == total {
        return Err(format!(
            "{}: every run failed ({total} runs; the table of failures is {}); {}",
            path.display(),
            target.display(),
            first_error.unwrap_or_default()
        ));
    }
    if !quiet {
        outln!(
            "foldsim sweep: {total} runs ({failed} failed) on {workers} workers in {:.2} s -> {}",
            started.elapsed().as_secs_f64(),
            target.display()
        );
    }
    Ok(())
}

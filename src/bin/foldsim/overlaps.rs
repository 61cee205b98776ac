//! `foldsim overlaps`: how deep any two bodies overlap over a finished run, from its CSV's
//! poses alone (`foldsim::verify::overlap`).

use foldsim::output::table::{Table, poses_from_table};
use foldsim::scenario::Scenario;
use foldsim::verify::overlap::{Solids, deepest_overlaps};
use std::path::Path;
use std::sync::Mutex;

/// Measures the run of `scenario_path` written to `csv` and prints its `pairs` deepest
/// overlaps; an error if one is deeper than `fail_above` of the thinner body's thickness.
pub(crate) fn overlaps(
    scenario_path: &Path,
    csv: &Path,
    sharp: bool,
    pairs: usize,
    fail_above: Option<f64>,
    quiet: bool,
) -> Result<(), String> {
    if let Some(f) = fail_above
        && !(f.is_finite() && f >= 0.0)
    {
        return Err(format!("--fail-above {f}: give a fraction of the thickness, 0 or more (0.1 for ten per cent)"));
    }
    let scenario = Scenario::from_file(scenario_path).map_err(|e| e.to_string())?;
    let model = &scenario.model;
    if model.bodies.iter().filter(|b| b.shape.is_some()).count() < 2 {
        return Err(format!(
            "{}: fewer than two bodies have a shape, so nothing can overlap (give the bodies a `shape`)",
            scenario_path.display()
        ));
    }
    let table = Table::read(csv)?;
    let (poses, warnings) = poses_from_table(model, &table).map_err(|m| format!("{}: {m}", csv.display()))?;
    for w in warnings {
        eprintln!("warning: {}: {w}", csv.display());
    }
    let rows = poses.times.len();
    if rows == 0 {
        return Err(format!("{}: no rows: the CSV holds only its header", csv.display()));
    }
    let bar = crate::watch::progress_bar(quiet, rows as u64, "row {pos}/{len}");
    let watch = Mutex::new(crate::watch::Watch::new("foldsim overlaps", quiet, None));
    let progress = |done: usize| {
        if let Some(b) = &bar {
            b.set_position(done as u64);
        }
        if let Ok(mut w) = watch.lock() {
            w.tick(done as f64, rows as f64, "rows", None, || "fewer rows (a longer output_step) shorten it".into());
        }
    };
    let kind = if sharp { Solids::Sharp } else { Solids::Sampled };
    let found = deepest_overlaps(model, &poses, kind, Some(&progress));
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let found = found.map_err(|m| format!("{}: {m}", scenario_path.display()))?;
    let name = |i: usize| model.bodies[i].name.as_str();
    let solids = if sharp {
        "thin plates as sharp prisms"
    } else {
        "thin plates with their rims rounded as the contact code samples them"
    };
    outln!("overlaps in {} ({rows} rows, {} bodies; {solids}):", csv.display(), model.bodies.len());
    let Some(worst) = found.first() else {
        outln!("  none: no two bodies overlap at any row");
        return Ok(());
    };
    outln!("  pairs that overlap at some row: {}", found.len());
    for o in found.iter().take(pairs) {
        outln!(
            "  {} / {}: {:.3e} m ({:.2} % of the thinner's thickness) at t = {} s",
            name(o.bodies.0),
            name(o.bodies.1),
            o.depth,
            100.0 * o.of_thickness,
            time(o.t)
        );
    }
    if let Some(f) = fail_above
        && worst.of_thickness > f
    {
        return Err(format!(
            "{} and {} overlap by {:.3e} m at t = {} s, {:.2} % of the thinner's thickness: above --fail-above {f}",
            name(worst.bodies.0),
            name(worst.bodies.1),
            worst.depth,
            time(worst.t),
            100.0 * worst.of_thickness
        ));
    }
    Ok(())
}

/// A row's time as the CSV gives it, to a microsecond (s).
fn time(t: f64) -> String {
    let s = format!("{t:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

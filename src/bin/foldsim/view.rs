//! `foldsim animate` and `foldsim view`: a finished run's animation and viewer page.

use crate::run::{check_fps, write_animation};
use foldsim::output::animation::Frames;
use foldsim::output::paths::check_outputs;
use foldsim::scenario::Scenario;
use std::path::Path;

/// A finished run read back for `animate` and `view`: its scenario, CSV, animation frames
/// and the rows they came from; `output` checked not to be one of its inputs.
#[cfg(feature = "animation")]
pub(crate) fn finished_run(
    scenario_path: &Path,
    csv: &Path,
    output: &Path,
    fps: Option<f64>,
    format: (&str, &str),
) -> Result<(Scenario, foldsim::output::animation::Table, Frames, Vec<usize>), String> {
    use foldsim::output::animation::{Table, frames_from_table};
    let scenario = Scenario::from_file(scenario_path).map_err(|e| e.to_string())?;
    check_fps(fps)?;
    let mut inputs = scenario.inputs.clone();
    inputs.push(csv.to_path_buf());
    check_outputs(&inputs, &[("-o", output)])?;
    foldsim::output::paths::check_extension("-o", output, format.0, format.1)?;
    let table = Table::read(csv)?;
    let (frames, kept, warnings) =
        frames_from_table(&scenario.model, &table, fps).map_err(|m| format!("{}: {m}", csv.display()))?;
    for w in warnings {
        eprintln!("warning: {}: {w}", csv.display());
    }
    Ok((scenario, table, frames, kept))
}

/// `foldsim animate`: the animation of a finished run from its CSV's body columns.
#[cfg(feature = "animation")]
pub(crate) fn animate(scenario_path: &Path, csv: &Path, output: &Path, fps: Option<f64>) -> Result<(), String> {
    let (scenario, _, frames, _) = finished_run(scenario_path, csv, output, fps, foldsim::output::paths::GLB)?;
    write_animation(&scenario.model, &frames, output, false)
}

/// `foldsim view`: a self-contained page playing a finished run, beside a plot of `columns`.
#[cfg(feature = "animation")]
pub(crate) fn view(
    scenario_path: &Path,
    csv: &Path,
    output: &Path,
    fps: Option<f64>,
    columns: &[String],
) -> Result<(), String> {
    let (scenario, table, frames, kept) = finished_run(scenario_path, csv, output, fps, foldsim::output::paths::HTML)?;
    write_page(scenario_path, &scenario, &table, &frames, &kept, columns, output, false)
}

/// `foldsim run --view`: the page of the run just made, its frames (with every contact the
/// run saw between them) from the run itself, its plot from the CSV written.
#[cfg(feature = "animation")]
pub(crate) fn view_run(
    scenario_path: &Path,
    csv: &Path,
    output: &Path,
    frames: Frames,
    quiet: bool,
) -> Result<(), String> {
    let scenario = Scenario::from_file(scenario_path).map_err(|e| e.to_string())?;
    let table = foldsim::output::animation::Table::read(csv)?;
    let kept = frames.kept.clone();
    write_page(scenario_path, &scenario, &table, &frames, &kept, &[], output, quiet)
}

#[cfg(feature = "animation")]
#[allow(clippy::too_many_arguments)]
fn write_page(
    scenario_path: &Path,
    scenario: &Scenario,
    table: &foldsim::output::animation::Table,
    frames: &Frames,
    kept: &[usize],
    columns: &[String],
    output: &Path,
    quiet: bool,
) -> Result<(), String> {
    let title = scenario.title.clone().unwrap_or_else(|| scenario_path.display().to_string());
    let html = foldsim::output::viewer::page(&title, &scenario.model, table, frames, kept, columns)?;
    foldsim::output::paths::write_atomically(output, html.as_bytes())?;
    if !quiet {
        outln!(
            "  viewer           {} frames, {:.1} MB -> {}",
            frames.times.len(),
            html.len() as f64 / 1e6,
            output.display()
        );
    }
    Ok(())
}

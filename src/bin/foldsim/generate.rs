//! `foldsim generate`: scenario files of z-folds, grids and flashers.

use crate::args::{FlasherArgs, Shape};
use std::path::PathBuf;

/// An option's key as the command line spells it: `k_fold` → `--k-fold`.
pub(crate) fn flag(key: &str) -> String {
    format!("--{}", key.replace('_', "-"))
}

pub(crate) fn generate(shape: Shape, p: &foldsim::generate::Params, output: Option<PathBuf>) -> Result<(), String> {
    use foldsim::generate::options::{grid_checked, zfold_checked};
    check_output(&output)?;
    let text = match shape {
        Shape::Zfold { panels } => zfold_checked(panels, p, &flag)?,
        Shape::Grid { rows, cols } => grid_checked(rows, cols, p, &flag)?,
        Shape::Flasher(_) => unreachable!("flashers are written by generate_flasher"),
    };
    let report = output.is_some();
    write_scenario(&text, output)?;
    if report {
        crate::out::print(&format!("expected run time: {}\n", expected_run_time(&text)?))?;
    }
    Ok(())
}

/// How long `foldsim run` of generated scenario text will take, from a trial of half a
/// second, or two with contact, and from a packed start two after it opens
/// (`estimate::Phase`, `estimate::Trend`).
fn expected_run_time(text: &str) -> Result<String, String> {
    let s = foldsim::scenario::Scenario::from_toml(text, "the generated scenario").map_err(|e| e.to_string())?;
    let contact = s.model.contact.is_some();
    let budget = std::time::Duration::from_millis(if contact { 2000 } else { 500 });
    // A packed start's trial waits for the package to open (`estimate::Phase`).
    Ok(foldsim::simulate::estimate::estimate(&s.model, &s.initial, &s.settings, budget).describe())
}

/// Writes a scenario to `output` through `<output>.partial` (renamed when complete), or to
/// standard output.
pub(crate) fn write_scenario(text: &str, output: Option<PathBuf>) -> Result<(), String> {
    match output {
        None => crate::out::print(text),
        Some(output) => foldsim::output::paths::write_atomically(&output, text.as_bytes()),
    }
}

/// Checks the output before anything is generated (an existing directory, a writable file).
pub(crate) fn check_output(output: &Option<PathBuf>) -> Result<(), String> {
    match output {
        Some(o) => foldsim::output::paths::check_outputs(&[], &[("-o", o)]),
        None => Ok(()),
    }
}

/// Writes a flasher's scenario (to `output`, or standard output) and prints its report (to
/// standard output, or standard error when the scenario goes there); the report also heads
/// the scenario as comments.
pub(crate) fn generate_flasher(
    a: &FlasherArgs,
    k_translation: f64,
    k_rotation: f64,
    k_fold: f64,
    (duration, tolerance): (f64, Option<f64>),
    output: Option<PathBuf>,
) -> Result<(), String> {
    use foldsim::generate::flasher::FlasherLaws;
    use foldsim::generate::options::{FlasherOptions, hinge_axes, panel_model};
    check_output(&output)?;
    let hub_inertia = match a.hub_inertia.as_deref() {
        None => None,
        Some(&[x, y, z]) => Some([x, y, z]),
        Some(v) => {
            return Err(format!(
                "--hub-inertia takes 3 comma-separated principal values (x, y, z) in kg·m², e.g. 25,25,50; got {}",
                v.len()
            ));
        }
    };
    let options = FlasherOptions {
        gores: a.gores,
        rings: a.rings,
        hub_radius: a.hub_radius,
        thickness: a.thickness,
        hinge_axes: hinge_axes(&a.hinge_axes)?,
        areal_density: a.areal_density,
        hub_mass: a.hub_mass,
        hub_inertia,
        panels: panel_model(&a.panels)?,
        laws: FlasherLaws {
            k_fold,
            c_fold: a.c_fold,
            k_bending: a.k_panel_bending,
            c_bending: a.c_panel_bending,
            k_translation,
            c_translation: a.c_translation,
            k_rotation,
            c_rotation: a.c_rotation,
            k_stop: a.k_stop,
            membrane_bending: a.membrane_bending,
            membrane_width: a.membrane_width,
            membrane_damping_ratio: a.membrane_damping_ratio,
        },
        spin_rpm: a.spin_rpm,
        duration,
        output_step: a.output_step,
        tolerance,
        integrator: a.integrator.clone(),
        release_at: a.release_at,
    };
    let (text, report) = options.scenario(&flag)?;
    let summary = report.text(a.all_folds);
    // The command that wrote it (without the output file), then the report, as comments.
    let mut command: Vec<String> = vec!["foldsim".into()];
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "-o" || arg == "--output" {
            args.next();
        } else if !arg.starts_with("--output=") {
            command.push(arg);
        }
    }
    let commented: String = std::iter::once(format!("Written by: {}", command.join(" ")))
        .chain(report.text(false).lines().map(str::to_string))
        .map(|l| format!("# {l}\n"))
        .collect();
    let text = format!("{commented}{text}");
    let summary =
        if a.no_trial { summary } else { format!("{summary}expected run time: {}\n", expected_run_time(&text)?) };
    if output.is_some() {
        write_scenario(&text, output)?;
        crate::out::print(&summary)
    } else {
        eprint!("{summary}");
        write_scenario(&text, output)
    }
}

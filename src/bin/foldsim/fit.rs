//! `foldsim fit`: scenario values fitted to measurements (docs/fit.md).

use foldsim::fit::{Fit, Fitted, data::Data, lm, params, problem::Problem};
use foldsim::output::paths::{check_outputs, write_atomically};
use foldsim::scenario::ScenarioText;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Fits the `--free` values of `scenario` to `data`, with `--sigma` noise levels; prints the
/// report, writes the fitted scenario to `output` and the plot to `plot` when given.
pub(crate) fn fit(
    scenario: &Path,
    data: &Path,
    (free, sigma): (&[String], &[String]),
    (output, plot): (Option<PathBuf>, Option<PathBuf>),
    max_iterations: usize,
    quiet: bool,
) -> Result<(), String> {
    if max_iterations == 0 {
        return Err("--max-iterations must be at least 1".into());
    }
    let text = ScenarioText::from_file(scenario).map_err(|e| e.to_string())?;
    let nominal = text.build().map_err(|e| e.to_string())?;
    let mut inputs = nominal.inputs.clone();
    inputs.push(data.to_path_buf());
    let mut outputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(o) = &output {
        outputs.push(("-o", o));
    }
    if let Some(p) = &plot {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            return Err(format!("--plot {}: the plot is written as PNG; name a .png file", p.display()));
        }
        outputs.push(("--plot", p));
    }
    check_outputs(&inputs, &outputs)?;
    let free = params::parse(free, &text)?;
    let mut measured = Data::read(data, &nominal.model, nominal.settings.duration)?;
    for s in sigma {
        let (name, value) =
            s.split_once('=').ok_or_else(|| format!("--sigma {s}: give COLUMN=SIGMA (h1_yaw=0.001)"))?;
        let v: f64 = value.trim().parse().map_err(|_| format!("--sigma {s}: '{value}' is not a number"))?;
        measured.set_sigma(name.trim(), v)?;
    }
    if nominal.settings.position_tolerance.is_some() {
        return Err(format!(
            "{}: run.position_tolerance is set; a fit's runs are made at the integrator's own rtol and atol (set those, tight: the fit's differences need them), so leave it out",
            scenario.display()
        ));
    }
    let problem = Problem::new(text, free, measured)?;
    let terminal = !quiet && std::io::stderr().is_terminal();
    let mut on_iteration = |k: usize, norm: f64| {
        if terminal {
            eprint!("\rfit: iteration {k}, weighted residual norm {norm:.6e}   ");
        }
    };
    let options = lm::Options { max_iterations, ..lm::Options::default() };
    let result = foldsim::fit::fit(&problem, &options, &mut on_iteration);
    if terminal {
        eprintln!();
    }
    let result = result?;
    crate::out::print(&result.text(&problem))?;
    let x = &result.solution.x;
    if let Some(o) = &output {
        let fitted = problem.scenario_at(x)?;
        let values: Vec<String> = problem.free.iter().zip(x).map(|(f, v)| format!("{} = {v}", f.path)).collect();
        let header = format!(
            "# Fitted by: foldsim fit {} --data {} ({}): {}\n",
            scenario.display(),
            data.display(),
            result.solution.stop.says(),
            values.join(", ")
        );
        write_atomically(o, (header + &fitted.text()).as_bytes())?;
        crate::out::print(&format!("fitted scenario: {}\n", o.display()))?;
    }
    #[cfg(feature = "plot")]
    if let Some(p) = &plot {
        let title = format!("{} fitted to {}", scenario.display(), data.display());
        draw(&result, &problem.abscissa(), &title, p)?;
    }
    #[cfg(not(feature = "plot"))]
    let _ = plot;
    Ok(())
}

/// Writes the fit's PNG: each column's data against the fitted model.
#[cfg(feature = "plot")]
fn draw(result: &Fit, x_label: &str, title: &str, out: &Path) -> Result<(), String> {
    use foldsim::output::fit_plot::{Compared, plot_fit};
    let columns: Vec<Compared> = result
        .columns
        .iter()
        .map(|c| Compared {
            name: &c.name,
            unit: c.unit,
            abscissa: &c.abscissa,
            measured: &c.measured,
            fitted: &c.fitted,
        })
        .collect();
    plot_fit(&columns, x_label, title, out)?;
    crate::out::print(&format!("plot: {}\n", out.display()))
}

//! `foldsim fit`: scenario values fitted to measurements, or a hinge law's values to a bench
//! test (docs/fit.md).

use foldsim::fit::law::{Bench, LawProblem};
use foldsim::fit::{Fit, Fitted, data::Data, lm, params, problem::Problem};
use foldsim::output::paths::{check_outputs, write_atomically};
use foldsim::scenario::ScenarioText;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// What is fitted: a scenario to `--data`, or a law file to `--moment` in `--direction`.
pub(crate) struct What {
    pub(crate) scenario: Option<PathBuf>,
    pub(crate) data: Option<PathBuf>,
    pub(crate) law: Option<PathBuf>,
    pub(crate) moment: Option<PathBuf>,
    pub(crate) direction: String,
}

/// `--sigma COLUMN=SIGMA` as a pair.
fn sigma_arg(s: &str) -> Result<(&str, f64), String> {
    let (name, value) = s.split_once('=').ok_or_else(|| format!("--sigma {s}: give COLUMN=SIGMA (h1_yaw=0.001)"))?;
    let v: f64 = value.trim().parse().map_err(|_| format!("--sigma {s}: '{value}' is not a number"))?;
    Ok((name.trim(), v))
}

/// Fits the `--free` values, with `--sigma` noise levels; prints the report, writes the
/// fitted scenario or law file to `output` and the plot to `plot` when given.
pub(crate) fn fit(
    what: What,
    (free, sigma): (&[String], &[String]),
    (output, plot): (Option<PathBuf>, Option<PathBuf>),
    max_iterations: usize,
    quiet: bool,
) -> Result<(), String> {
    if max_iterations == 0 {
        return Err("--max-iterations must be at least 1".into());
    }
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
    let (problem, source, data): (Box<dyn Fitted>, PathBuf, PathBuf) = match what {
        What { scenario: Some(scenario), data: Some(data), .. } => {
            let text = ScenarioText::from_file(&scenario).map_err(|e| e.to_string())?;
            let nominal = text.build().map_err(|e| e.to_string())?;
            let mut inputs = nominal.inputs.clone();
            inputs.push(data.clone());
            check_outputs(&inputs, &outputs)?;
            if nominal.settings.position_tolerance.is_some() {
                return Err(format!(
                    "{}: run.position_tolerance is set; a fit's runs are made at the integrator's own rtol and atol (set those, tight: the fit's differences need them), so leave it out",
                    scenario.display()
                ));
            }
            let free = params::parse(free, &text)?;
            let mut measured = Data::read(&data, &nominal.model, nominal.settings.duration)?;
            for s in sigma {
                let (name, v) = sigma_arg(s)?;
                measured.set_sigma(name, v)?;
            }
            (Box::new(Problem::new(text, free, measured)?), scenario, data)
        }
        What { law: Some(law), moment: Some(moment), direction, .. } => {
            let text = ScenarioText::from_file(&law).map_err(|e| e.to_string())?;
            let (_, mut inputs) =
                foldsim::scenario::law_from_toml(&text.text(), &text.file, &text.base).map_err(|e| e.to_string())?;
            inputs.extend([law.clone(), moment.clone()]);
            check_outputs(&inputs, &outputs)?;
            let free = params::parse(free, &text)?;
            let bench_text =
                std::fs::read_to_string(&moment).map_err(|e| format!("cannot read {}: {e}", moment.display()))?;
            let mut bench = Bench::parse(&bench_text, &moment.display().to_string())?;
            for s in sigma {
                let (name, v) = sigma_arg(s)?;
                let own = if bench.rotational { "moment" } else { "force" };
                if name != own {
                    return Err(format!("--sigma {s}: a bench test has one column to weigh, '{own}'"));
                }
                if !(v.is_finite() && v > 0.0) {
                    return Err(format!("--sigma {s}: a standard deviation is a finite number > 0"));
                }
                bench.sigma = Some(v);
            }
            (Box::new(LawProblem::new(text, free, bench, &direction)?), law, moment)
        }
        What { scenario: Some(s), .. } => {
            return Err(format!(
                "foldsim fit {}: give the measurements with --data DATA.csv (docs/fit.md)",
                s.display()
            ));
        }
        _ => return Err("give a scenario with --data, or --law with --moment (docs/fit.md)".into()),
    };
    let terminal = !quiet && std::io::stderr().is_terminal();
    let mut on_iteration = |k: usize, norm: f64| {
        if terminal {
            eprint!("\rfit: iteration {k}, weighted residual norm {norm:.6e}   ");
        }
    };
    let options = lm::Options { max_iterations, ..lm::Options::default() };
    let result = foldsim::fit::fit(problem.as_ref(), &options, &mut on_iteration);
    if terminal {
        eprintln!();
    }
    let result = result?;
    crate::out::print(&result.text(problem.as_ref()))?;
    let x = &result.solution.x;
    if let Some(o) = &output {
        let mut fitted = ScenarioText::from_file(&source).map_err(|e| e.to_string())?;
        for (f, v) in problem.free().iter().zip(x) {
            fitted.set(&f.path, &foldsim::scenario::SetValue::Number(*v))?;
        }
        let values: Vec<String> = problem.free().iter().zip(x).map(|(f, v)| format!("{} = {v}", f.path)).collect();
        let header = format!(
            "# Fitted by: foldsim fit {} to {} ({}): {}\n",
            source.display(),
            data.display(),
            result.solution.stop.says(),
            values.join(", ")
        );
        write_atomically(o, (header + &fitted.text()).as_bytes())?;
        crate::out::print(&format!("fitted: {}\n", o.display()))?;
    }
    #[cfg(feature = "plot")]
    if let Some(p) = &plot {
        let title = format!("{} fitted to {}", source.display(), data.display());
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

//! Fitting scenario values to measurements (docs/fit.md): `foldsim fit`. The free values are
//! named by key path as sweeps name them ([`params`]), the measurements are output columns at
//! times ([`data`]); each evaluation is a run with rows at the measurement times
//! ([`problem`]), minimised by a bounded Levenberg–Marquardt ([`lm`]), and what the data say
//! about the result comes from the Jacobian at the optimum ([`stats`]). A layer of its own
//! beside `sweep`: it edits scenario text and runs it, and nothing below knows of it.

pub mod data;
pub mod differences;
pub mod law;
pub mod lm;
pub mod params;
pub mod problem;
pub mod report;
pub mod stats;

use params::Free;
use stats::Statistics;

/// One measured column beside the fitted model's values at the same points: for the
/// residuals per column, the report and the plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// The column's name (an output column's, or `moment` / `force` for a law alone).
    pub name: String,
    /// Its unit.
    pub unit: &'static str,
    /// Where each value is: the time (s), or the coordinate a law is driven through.
    pub abscissa: Vec<f64>,
    /// The measurements (`None`: not measured there).
    pub measured: Vec<Option<f64>>,
    /// The model's values there.
    pub fitted: Vec<f64>,
    /// The noise level given for it, if any.
    pub sigma: Option<f64>,
}

/// A least-squares problem over free values: a scenario's runs against measured columns
/// ([`problem::Problem`]), or a hinge law's response against a bench test
/// ([`law::LawProblem`]).
pub trait Fitted: Sync {
    /// The free values.
    fn free(&self) -> &[Free];
    /// The weighted residuals (model − measured) / σ at `x`.
    fn residuals(&self, x: &[f64]) -> Result<Vec<f64>, String>;
    /// The measured columns beside the model's values at `x`.
    fn columns(&self, x: &[f64]) -> Result<Vec<Column>, String>;
    /// What is fitted to, for the report's first line.
    fn data_summary(&self) -> String;
    /// The columns' abscissa, with its unit, for the plot (`t (s)`).
    fn abscissa(&self) -> String;
    /// The residuals' Jacobian at `x`, where they are `r`: by differences, the evaluations
    /// in parallel ([`differences::jacobian`]).
    fn jacobian(&self, x: &[f64], r: &[f64]) -> Result<nalgebra::DMatrix<f64>, String> {
        differences::jacobian(self.free(), x, r, &|y: &[f64]| self.residuals(y))
    }
}

/// A finished fit.
#[derive(Clone, Debug)]
pub struct Fit {
    /// The optimiser's result (values, residuals, Jacobian, counts, why it stopped).
    pub solution: lm::Solution,
    /// Standard errors, correlations, warnings.
    pub statistics: Statistics,
    /// Per measured column: its residuals' root mean square in the column's unit (unweighted)
    /// and how many values it has.
    pub rms: Vec<(f64, usize)>,
    /// The start's weighted residual norm `|r|`, and the optimum's.
    pub norm: (f64, f64),
    /// The measured columns beside the fitted model's values.
    pub columns: Vec<Column>,
    /// Runs made (each residual evaluation one, each Jacobian two per parameter).
    pub runs: usize,
    /// Wall time, s.
    pub wall_seconds: f64,
}

/// Fits `problem` from its free values' starts. `on_iteration` is told each iteration's
/// number and weighted residual norm (for a terminal's progress line).
pub fn fit(
    problem: &dyn Fitted,
    options: &lm::Options,
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<Fit, String> {
    let started = std::time::Instant::now();
    let free = problem.free();
    let x0: Vec<f64> = free.iter().map(|f| f.start).collect();
    let low: Vec<f64> = free.iter().map(|f| f.low).collect();
    let high: Vec<f64> = free.iter().map(|f| f.high).collect();
    let mut start_norm = f64::NAN;
    let mut iteration = 0;
    let mut residuals = |x: &[f64]| problem.residuals(x);
    let mut jacobian = |x: &[f64], r: &[f64]| {
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        if iteration == 0 {
            start_norm = norm;
        }
        iteration += 1;
        on_iteration(iteration, norm);
        problem.jacobian(x, r)
    };
    let solution = lm::minimize(&x0, &low, &high, &mut residuals, &mut jacobian, options)?;
    let statistics = stats::statistics(&solution.x, &low, &high, &solution.residuals, &solution.jacobian);
    let columns = problem.columns(&solution.x)?;
    let rms = columns
        .iter()
        .map(|c| {
            let d: Vec<f64> = c.measured.iter().zip(&c.fitted).filter_map(|(v, q)| v.map(|v| q - v)).collect();
            ((d.iter().map(|x| x * x).sum::<f64>() / d.len().max(1) as f64).sqrt(), d.len())
        })
        .collect();
    let end_norm = solution.residuals.iter().map(|v| v * v).sum::<f64>().sqrt();
    let runs = solution.evaluations + 2 * free.len() * iteration + 1;
    Ok(Fit {
        solution,
        statistics,
        rms,
        norm: (start_norm, end_norm),
        columns,
        runs,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

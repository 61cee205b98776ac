//! Fitting scenario values to measurements (docs/fit.md): `foldsim fit`. The free values are
//! named by key path as sweeps name them ([`params`]), the measurements are output columns at
//! times ([`data`]); each evaluation is a run with rows at the measurement times
//! ([`problem`]), minimised by a bounded Levenberg–Marquardt ([`lm`]), and what the data say
//! about the result comes from the Jacobian at the optimum ([`stats`]). A layer of its own
//! beside `sweep`: it edits scenario text and runs it, and nothing below knows of it.

pub mod data;
pub mod lm;
pub mod params;
pub mod problem;
pub mod report;
pub mod stats;

use problem::Problem;
use stats::Statistics;

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
    /// The fitted run's values of the measured columns at the data's times.
    pub predicted: Vec<Vec<f64>>,
    /// Runs made (each residual evaluation one, each Jacobian two per parameter).
    pub runs: usize,
    /// Wall time, s.
    pub wall_seconds: f64,
}

/// Fits `problem` from its free values' starts. `on_iteration` is told each iteration's
/// number and weighted residual norm (for a terminal's progress line).
pub fn fit(problem: &Problem, options: &lm::Options, on_iteration: &mut dyn FnMut(usize, f64)) -> Result<Fit, String> {
    let started = std::time::Instant::now();
    let x0: Vec<f64> = problem.free.iter().map(|f| f.start).collect();
    let low: Vec<f64> = problem.free.iter().map(|f| f.low).collect();
    let high: Vec<f64> = problem.free.iter().map(|f| f.high).collect();
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
    let predicted = problem.predict(&solution.x)?;
    let rms = problem
        .data
        .columns
        .iter()
        .zip(&predicted)
        .map(|(c, p)| {
            let d: Vec<f64> = c.values.iter().zip(p).filter_map(|(v, q)| v.map(|v| q - v)).collect();
            ((d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt(), d.len())
        })
        .collect();
    let end_norm = solution.residuals.iter().map(|v| v * v).sum::<f64>().sqrt();
    let runs = solution.evaluations + 2 * problem.free.len() * iteration + 1;
    Ok(Fit {
        solution,
        statistics,
        rms,
        norm: (start_norm, end_norm),
        predicted,
        runs,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

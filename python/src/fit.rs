//! `foldsim._foldsim.fit`: scenario values fitted to measurements (docs/fit.md), with the
//! GIL released; the result as a dict of Python values and NumPy arrays.

use crate::scenario::Scenario;
use foldsim::fit::data::Data;
use foldsim::fit::problem::Problem;
use foldsim::fit::{lm, params};
use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Fits `free` (`KEY` or `KEY=LOW:HIGH`) of `scenario` to the CSV text `data` (labelled
/// `data_name` in errors), with per-column noise `sigma`; at most `max_iterations`.
#[pyfunction]
#[pyo3(signature = (scenario, data, data_name, free, sigma, max_iterations))]
pub fn fit<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    data: &str,
    data_name: &str,
    free: Vec<String>,
    sigma: Vec<(String, f64)>,
    max_iterations: usize,
) -> PyResult<Bound<'py, PyDict>> {
    if max_iterations == 0 {
        return Err(PyValueError::new_err("max_iterations must be at least 1"));
    }
    let s = &scenario.inner;
    let text = scenario.text.clone();
    if s.settings.position_tolerance.is_some() {
        return Err(PyValueError::new_err(
            "run.position_tolerance is set; a fit's runs are made at the integrator's own rtol and atol (set those, tight), so leave it out",
        ));
    }
    let mut measured = Data::parse(data, data_name, &s.model, s.settings.duration).map_err(PyValueError::new_err)?;
    for (c, v) in &sigma {
        measured.set_sigma(c, *v).map_err(PyValueError::new_err)?;
    }
    let free = params::parse(&free, &text).map_err(PyValueError::new_err)?;
    let problem = Problem::new(text, free, measured).map_err(PyValueError::new_err)?;
    let options = lm::Options { max_iterations, ..lm::Options::default() };
    let result =
        py.detach(|| foldsim::fit::fit(&problem, &options, &mut |_, _| {})).map_err(PyRuntimeError::new_err)?;
    let fitted = problem.scenario_at(&result.solution.x).map_err(PyRuntimeError::new_err)?;
    let d = PyDict::new(py);
    let st = &result.statistics;
    d.set_item("paths", problem.free.iter().map(|f| f.path.clone()).collect::<Vec<_>>())?;
    d.set_item("values", result.solution.x.clone())?;
    d.set_item("starts", problem.free.iter().map(|f| f.start).collect::<Vec<_>>())?;
    d.set_item("bounds", problem.free.iter().map(|f| (f.low, f.high)).collect::<Vec<_>>())?;
    d.set_item("standard_errors", st.estimates.iter().map(|e| e.standard_error).collect::<Vec<_>>())?;
    d.set_item("warnings", st.estimates.iter().map(|e| e.warning.clone()).collect::<Vec<_>>())?;
    let n = problem.free.len();
    let corr = PyArray2::<f64>::zeros(py, [n, n], false);
    let jac = PyArray2::<f64>::zeros(py, [result.solution.jacobian.nrows(), n], false);
    {
        let mut c = corr.readwrite();
        let mut c = c.as_array_mut();
        for a in 0..n {
            for b in 0..n {
                c[[a, b]] = st.correlation[(a, b)];
            }
        }
        let mut j = jac.readwrite();
        let mut j = j.as_array_mut();
        for i in 0..result.solution.jacobian.nrows() {
            for k in 0..n {
                j[[i, k]] = result.solution.jacobian[(i, k)];
            }
        }
    }
    d.set_item("correlation", corr)?;
    d.set_item("jacobian", jac)?;
    d.set_item("residuals", result.solution.residuals.clone().into_pyarray(py))?;
    d.set_item("variance", st.variance)?;
    d.set_item("dof", st.dof)?;
    d.set_item("condition", st.condition)?;
    d.set_item("converged", result.solution.stop != lm::Stop::Iterations)?;
    d.set_item("stop", result.solution.stop.says())?;
    d.set_item("iterations", result.solution.iterations)?;
    d.set_item("runs", result.runs)?;
    d.set_item("wall_seconds", result.wall_seconds)?;
    d.set_item("residual_norm", result.norm)?;
    let columns = PyDict::new(py);
    for (c, (rms, count)) in result.columns.iter().zip(&result.rms) {
        let cd = PyDict::new(py);
        cd.set_item("fitted", c.fitted.clone().into_pyarray(py))?;
        cd.set_item("measured", c.measured.iter().map(|v| v.unwrap_or(f64::NAN)).collect::<Vec<_>>().into_pyarray(py))?;
        cd.set_item("rms", rms)?;
        cd.set_item("count", count)?;
        cd.set_item("sigma", c.sigma)?;
        cd.set_item("unit", c.unit)?;
        columns.set_item(&c.name, cd)?;
    }
    d.set_item("columns", columns)?;
    d.set_item("t", problem.data.times.clone().into_pyarray(py))?;
    d.set_item("report", result.text(&problem))?;
    d.set_item("text", fitted.text())?;
    Ok(d)
}

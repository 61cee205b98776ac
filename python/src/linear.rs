//! `Scenario.linearize` and `Scenario.modes` for Python: the state-space model and the modes
//! as NumPy arrays (docs/linear.md, docs/python.md).

use foldsim::linear::modes::{Mode, Modes};
use foldsim::linear::statespace::{default_outputs, outputs_matching, state_space};
use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A matrix as a 2-D NumPy array.
fn matrix<'py>(py: Python<'py>, m: &nalgebra::DMatrix<f64>) -> PyResult<Bound<'py, PyAny>> {
    let a = Array2::from_shape_fn((m.nrows(), m.ncols()), |(r, c)| m[(r, c)]);
    Ok(a.into_pyarray(py).into_any())
}

/// Where to linearise: the design state if asked, else time `at` of the run.
fn prepare(mut s: foldsim::scenario::Scenario, at: f64, deployed: bool) -> PyResult<foldsim::scenario::Scenario> {
    s.initial = foldsim::linear::start_for(&s.model, &s.initial, &mut s.settings, at, deployed)
        .map_err(|e| PyValueError::new_err(format!("at = {e}")))?;
    Ok(s)
}

/// The state-space model as a dict (see `foldsim.Scenario.linearize`).
pub(crate) fn linearize<'py>(
    py: Python<'py>,
    scenario: foldsim::scenario::Scenario,
    at: f64,
    deployed: bool,
    inputs: Option<Vec<String>>,
    outputs: Option<Vec<String>>,
    reduced: (Option<usize>, bool),
) -> PyResult<Bound<'py, PyDict>> {
    let mut s = prepare(scenario, at, deployed)?;
    s.model.commandable = true;
    let bodies =
        match inputs {
            None => vec![0],
            Some(names) => names
                .iter()
                .map(|b| {
                    s.model.bodies.iter().position(|x| &x.name == b).ok_or_else(|| {
                        PyValueError::new_err(format!("inputs: no body '{b}' (Scenario.bodies lists them)"))
                    })
                })
                .collect::<PyResult<_>>()?,
        };
    let outputs = match outputs {
        None => default_outputs(),
        Some(p) => outputs_matching(&s.model, &p).map_err(|e| PyValueError::new_err(format!("outputs: {e}")))?,
    };
    let ss = match reduced {
        (None, true) => return Err(PyValueError::new_err("hub_held=True reduces the model: give modes=N too")),
        (None, false) => py.detach(|| state_space(&s.model, &s.initial, &s.settings, at, &bodies, &outputs)),
        (Some(count), hub_held) => {
            use foldsim::linear::reduced::{Reduction, reduced_state_space};
            let kind = if hub_held { Reduction::HubHeld } else { Reduction::FreeFree };
            py.detach(|| reduced_state_space(&s.model, &s.initial, &s.settings, at, &bodies, &outputs, count, kind))
                .map_err(|e| format!("modes: {e}"))
        }
    }
    .map_err(PyValueError::new_err)?;
    let d = PyDict::new(py);
    d.set_item("A", matrix(py, &ss.a)?)?;
    d.set_item("B", matrix(py, &ss.b)?)?;
    d.set_item("C", matrix(py, &ss.c)?)?;
    d.set_item("D", matrix(py, &ss.d)?)?;
    d.set_item("y0", ss.y0.as_slice().to_vec().into_pyarray(py))?;
    d.set_item("t", ss.t)?;
    d.set_item("residual", ss.residual)?;
    d.set_item("states", ss.states)?;
    d.set_item("inputs", ss.inputs)?;
    d.set_item("outputs", ss.outputs)?;
    Ok(d)
}

/// One set of modes as a dict of arrays.
fn mode_set<'py>(py: Python<'py>, modes: &[Mode]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let column = |f: &dyn Fn(&Mode) -> f64| modes.iter().map(f).collect::<Vec<f64>>();
    d.set_item("frequency_hz", column(&|m| m.frequency_hz()).into_pyarray(py))?;
    d.set_item("omega", column(&|m| m.omega).into_pyarray(py))?;
    d.set_item("omega_squared", column(&|m| m.eigenvalue).into_pyarray(py))?;
    d.set_item("damping_ratio", column(&|m| m.damping_ratio).into_pyarray(py))?;
    d.set_item("rigid", modes.iter().map(|m| m.rigid).collect::<Vec<bool>>())?;
    let rows = modes.first().map_or(0, |m| m.shape.len());
    let shapes = Array2::from_shape_fn((rows, modes.len()), |(r, c)| modes[c].shape[r]);
    d.set_item("shapes", shapes.into_pyarray(py))?;
    let effective = Array2::from_shape_fn((modes.len(), 6), |(r, c)| modes[r].effective[c]);
    d.set_item("effective", effective.into_pyarray(py))?;
    Ok(d)
}

/// The modes as a dict (see `foldsim.Scenario.modes`).
pub(crate) fn modes<'py>(
    py: Python<'py>,
    scenario: foldsim::scenario::Scenario,
    at: f64,
    deployed: bool,
    count: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let s = prepare(scenario, at, deployed)?;
    if count == Some(0) {
        return Err(PyValueError::new_err("count = 0: ask for at least one mode"));
    }
    let found = py.detach(|| -> Result<Modes, String> {
        let (lin, here) = foldsim::linear::linearize_at(&s.model, &s.initial, &s.settings, at)?;
        match count {
            Some(c) => Modes::lowest(&lin, &here.positions, &here.dcm_n_b, c),
            None => Modes::of(&lin, &here.positions, &here.dcm_n_b),
        }
    });
    let found = found.map_err(PyValueError::new_err)?;
    let d = PyDict::new(py);
    d.set_item("free", mode_set(py, &found.free)?)?;
    d.set_item("hub_fixed", mode_set(py, &found.hub_fixed)?)?;
    d.set_item("appendage_total", found.appendage_total.to_vec())?;
    Ok(d)
}

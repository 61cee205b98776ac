//! Python bindings of foldsim (`foldsim._foldsim`; the package `foldsim` wraps it): load a
//! scenario, run it with the GIL released, and get every output column as a NumPy array and
//! the run report as a dict. Work in progress (the Python issue): no sweeps yet.

use foldsim::observe::{Observation, Selection, row};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ops::ControlFlow;
use std::path::PathBuf;

/// What `run` returns to Python: column names, one array per column, the report.
type RunOutput<'py> = (Vec<String>, Vec<Bound<'py, PyArray1<f64>>>, Bound<'py, PyDict>);

/// A scenario: a structure, its initial state and run settings (docs/scenario.md).
#[pyclass(module = "foldsim._foldsim")]
struct Scenario {
    inner: foldsim::scenario::Scenario,
}

#[pymethods]
impl Scenario {
    /// Reads a scenario file; a bad file raises ValueError naming the file, line and key.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        foldsim::scenario::Scenario::from_file(&path)
            .map(|inner| Self { inner })
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Reads a scenario from TOML text; `name` stands for the file in messages, `base` is the
    /// directory table files are read from.
    #[staticmethod]
    #[pyo3(signature = (text, name = "scenario", base = None))]
    fn from_toml(text: &str, name: &str, base: Option<PathBuf>) -> PyResult<Self> {
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        foldsim::scenario::Scenario::from_toml_in(text, name, &base)
            .map(|inner| Self { inner })
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The scenario's title.
    #[getter]
    fn title(&self) -> Option<String> {
        self.inner.title.clone()
    }

    /// Names of the bodies, hub first.
    #[getter]
    fn bodies(&self) -> Vec<String> {
        self.inner.model.bodies.iter().map(|b| b.name.clone()).collect()
    }

    /// Names of the hinges.
    #[getter]
    fn hinges(&self) -> Vec<String> {
        self.inner.model.hinges.iter().map(|h| h.name.clone()).collect()
    }

    /// Runs the scenario with the GIL released. `columns`: names or patterns as `run.columns`
    /// takes them (default: the scenario's). Returns (names, arrays, report). Ctrl-C stops
    /// the run with KeyboardInterrupt.
    #[pyo3(signature = (columns = None))]
    fn run<'py>(&self, py: Python<'py>, columns: Option<Vec<String>>) -> PyResult<RunOutput<'py>> {
        let s = &self.inner;
        let selection = match columns {
            Some(patterns) => Selection::matching(&s.model, &patterns).map_err(PyValueError::new_err)?,
            None => s.columns.clone(),
        };
        let width = selection.indices.len();
        let result = py.detach(|| {
            let mut values: Vec<Vec<f64>> = vec![Vec::new(); width];
            let mut sink = |o: &Observation| -> Result<(), String> {
                let r = row(o);
                for (k, &i) in selection.indices.iter().enumerate() {
                    values[k].push(r[i]);
                }
                Ok(())
            };
            // Ctrl-C: look at Python's signals now and then, with the GIL held briefly.
            let mut last = std::time::Instant::now();
            let mut progress = |_t: f64| {
                if last.elapsed().as_millis() < 100 {
                    return ControlFlow::Continue(());
                }
                last = std::time::Instant::now();
                let interrupted = Python::attach(|py| py.check_signals().is_err());
                if interrupted { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
            };
            foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, Some(&mut progress))
                .map(|report| (values, report))
        });
        let (values, report) = match result {
            Ok(v) => v,
            Err(foldsim::simulate::SimError::Interrupted { t }) => {
                return Err(PyKeyboardInterrupt::new_err(format!("interrupted at t = {t} s")));
            }
            Err(e) => return Err(PyRuntimeError::new_err(e.to_string())),
        };
        let arrays = values.into_iter().map(|v| v.into_pyarray(py)).collect();
        let d = PyDict::new(py);
        let drift = &report.drift;
        d.set_item("simulated", report.simulated)?;
        d.set_item("wall_seconds", report.wall_seconds)?;
        d.set_item("steps_accepted", report.steps_accepted)?;
        d.set_item("steps_rejected", report.steps_rejected)?;
        d.set_item("rhs_evaluations", report.rhs_evaluations)?;
        d.set_item("newton_iterations", report.newton_iterations)?;
        d.set_item("jacobians", report.jacobians)?;
        d.set_item("rows", report.rows)?;
        d.set_item("momentum_drift", drift.momentum)?;
        d.set_item("angular_momentum_drift", drift.angular_momentum)?;
        d.set_item("barycenter_drift", drift.barycenter)?;
        d.set_item("energy_drift", drift.energy)?;
        d.set_item("energy_initial", drift.energy_initial)?;
        d.set_item("dissipated", drift.dissipated)?;
        d.set_item("energy_balance", drift.energy_balance)?;
        d.set_item("energy_conserving", report.energy_conserving)?;
        d.set_item("released_at", report.released_at)?;
        d.set_item("deployed_90", report.deployed_90)?;
        let events: Vec<(f64, String, String, String)> = report
            .events
            .iter()
            .map(|e| (e.t, s.model.hinges[e.hinge].name.clone(), format!("{:?}", e.kind), e.description.clone()))
            .collect();
        d.set_item("events", events)?;
        Ok((selection.names.clone(), arrays, d))
    }
}

/// The native part of the `foldsim` package.
#[pymodule]
fn _foldsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scenario>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

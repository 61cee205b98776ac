//! Python bindings of foldsim (`foldsim._foldsim`; the package `foldsim` wraps it): scenarios
//! from files, text or dicts, changed by key path and run with the GIL released (every
//! output column a NumPy array, the report a dict); the generators; sweeps.
//!
//! - `convert`: Python values ↔ TOML values (a dict is a scenario file's structure);
//! - `scenario`: the `Scenario` class;
//! - `simulation`: the `Simulation` class (a run advanced piece by piece);
//! - `generate`: `zfold`, `grid`, `flasher`;
//! - `sweep`: the `Sweep` class.

mod convert;
mod fit;
mod generate;
mod linear;
mod scenario;
mod simulation;
mod sweep;

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use std::ops::ControlFlow;

/// A run's progress callback that looks at Python's signals every 100 ms (taking the GIL
/// briefly) and stops the run on Ctrl-C; it also hands the simulated time (s) to `report`
/// (a progress bar's update), if given. An exception raised by `report` is ignored (a progress
/// display must not end a run), except Ctrl-C's KeyboardInterrupt, which stops it.
pub(crate) fn interrupt_check(
    report: Option<Py<PyAny>>,
) -> impl FnMut(&foldsim::simulate::Progress<'_, '_>) -> ControlFlow<()> {
    let mut last = std::time::Instant::now();
    move |p: &foldsim::simulate::Progress<'_, '_>| {
        let t = p.t;
        if last.elapsed().as_millis() < 100 {
            return ControlFlow::Continue(());
        }
        last = std::time::Instant::now();
        let interrupted = Python::attach(|py| {
            // Signals first: Python code run by the report would take a pending Ctrl-C
            // (raised inside it), which must stop the run, not vanish with the report.
            if py.check_signals().is_err() {
                return true;
            }
            match &report {
                Some(f) => f.call1(py, (t,)).err().is_some_and(|e| e.is_instance_of::<PyKeyboardInterrupt>(py)),
                None => false,
            }
        });
        if interrupted { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}

/// Checks outputs before a command runs, as the command line does
/// (`foldsim::output::paths::check_outputs`): `outputs` are (what, path) pairs; none may be
/// one of `inputs` or another output, and each must be a writable file in an existing
/// directory. ValueError says which and why.
#[pyfunction]
fn check_outputs(inputs: Vec<std::path::PathBuf>, outputs: Vec<(String, std::path::PathBuf)>) -> PyResult<()> {
    let named: Vec<(&str, &std::path::Path)> = outputs.iter().map(|(w, p)| (w.as_str(), p.as_path())).collect();
    foldsim::output::paths::check_outputs(&inputs, &named).map_err(pyo3::exceptions::PyValueError::new_err)
}

/// The native part of the `foldsim` package.
#[pymodule]
fn _foldsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scenario::Scenario>()?;
    m.add_class::<sweep::Sweep>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_function(wrap_pyfunction!(check_outputs, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(generate::zfold, m)?)?;
    m.add_function(wrap_pyfunction!(generate::grid, m)?)?;
    m.add_function(wrap_pyfunction!(generate::flasher, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

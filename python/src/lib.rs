//! Python bindings of foldsim (`foldsim._foldsim`; the package `foldsim` wraps it): scenarios
//! from files, text or dicts, changed by key path and run with the GIL released (every
//! output column a NumPy array, the report a dict); the generators; sweeps.
//!
//! - `convert`: Python values ↔ TOML values (a dict is a scenario file's structure);
//! - `scenario`: the `Scenario` class;
//! - `generate`: `zfold`, `grid`, `flasher`;
//! - `sweep`: the `Sweep` class.

mod convert;
mod generate;
mod scenario;
mod sweep;

use pyo3::prelude::*;
use std::ops::ControlFlow;

/// A run's progress callback that looks at Python's signals every 100 ms (taking the GIL
/// briefly) and stops the run on Ctrl-C.
pub(crate) fn interrupt_check() -> impl FnMut(f64) -> ControlFlow<()> {
    let mut last = std::time::Instant::now();
    move |_t: f64| {
        if last.elapsed().as_millis() < 100 {
            return ControlFlow::Continue(());
        }
        last = std::time::Instant::now();
        let interrupted = Python::attach(|py| py.check_signals().is_err());
        if interrupted { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}

/// The native part of the `foldsim` package.
#[pymodule]
fn _foldsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scenario::Scenario>()?;
    m.add_class::<sweep::Sweep>()?;
    m.add_function(wrap_pyfunction!(generate::zfold, m)?)?;
    m.add_function(wrap_pyfunction!(generate::grid, m)?)?;
    m.add_function(wrap_pyfunction!(generate::flasher, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

//! `foldsim._foldsim.Sweep`: a sweep of a scenario (docs/sweep.md), run over a range of its
//! runs with the GIL released; the rows come back as columns.

use crate::convert;
use crate::scenario::Scenario;
use foldsim::sweep::SweepRow;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicBool, Ordering};

/// A sweep: a scenario and what varies from run to run.
#[pyclass(module = "foldsim._foldsim")]
pub struct Sweep {
    inner: foldsim::sweep::Sweep,
    text: String,
    name: String,
    base: std::path::PathBuf,
}

#[pymethods]
impl Sweep {
    /// A sweep of `scenario`: its own [sweep] table, or `spec` (a dict with the table's
    /// keys: runs, seed, parameters, metrics) in its place; `runs` and `seed` override.
    #[new]
    #[pyo3(signature = (scenario, spec = None, runs = None, seed = None))]
    fn new(
        scenario: &Scenario,
        spec: Option<&Bound<'_, PyDict>>,
        runs: Option<usize>,
        seed: Option<u64>,
    ) -> PyResult<Self> {
        let mut text = scenario.text.clone();
        if let Some(spec) = spec {
            text.set_table("sweep", convert::table(spec, "sweep")?);
        }
        let mut inner = foldsim::sweep::Sweep::new(text.clone()).map_err(|e| PyValueError::new_err(e.to_string()))?;
        if let Some(n) = runs {
            inner.set_runs(n).map_err(PyValueError::new_err)?;
        }
        if let Some(s) = seed {
            inner.set_seed(s);
        }
        Ok(Self { inner, text: text.text(), name: text.file.clone(), base: text.base.clone() })
    }

    /// The summary table's column names.
    #[getter]
    fn header(&self) -> Vec<String> {
        self.inner.header().to_vec()
    }

    /// Number of runs.
    #[getter]
    fn runs(&self) -> usize {
        self.inner.runs()
    }

    /// The seed of the draws.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.spec().seed
    }

    /// The scenario text with its [sweep] table (what a worker elsewhere rebuilds it from).
    #[getter]
    fn text(&self) -> String {
        self.text.clone()
    }

    /// The label messages use.
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    /// The directory table files are read from.
    #[getter]
    fn base(&self) -> std::path::PathBuf {
        self.base.clone()
    }

    /// The files the nominal scenario reads: what no output of the sweep may replace.
    #[getter]
    fn inputs(&self) -> Vec<std::path::PathBuf> {
        self.inner.inputs().to_vec()
    }

    /// The values run `run` takes, in the order of the parameters.
    fn values(&self, run: usize) -> Vec<f64> {
        self.inner.values(run)
    }

    /// Runs `start` to `stop` (exclusive) on `workers` threads with the GIL released; returns
    /// {column: values} in run order (NumPy arrays for numbers, NaN where a run has none;
    /// lists of str for status and error). Ctrl-C stops it with KeyboardInterrupt.
    #[pyo3(signature = (start, stop, workers = 1))]
    fn run<'py>(&self, py: Python<'py>, start: usize, stop: usize, workers: usize) -> PyResult<Bound<'py, PyDict>> {
        if start > stop || stop > self.inner.runs() {
            return Err(PyValueError::new_err(format!("runs {start}..{stop} of a sweep of {}", self.inner.runs())));
        }
        let halt = AtomicBool::new(false);
        let (result, rows, interrupted) = py.detach(|| {
            let mut rows: Vec<SweepRow> = Vec::new();
            let mut interrupted = false;
            let result = std::thread::scope(|scope| {
                let (finished, wait) = std::sync::mpsc::channel::<()>();
                let sweeping = scope.spawn(|| {
                    let mut rows = Vec::with_capacity((stop - start).min(4096));
                    let r = self.inner.run(start..stop, workers, &halt, &mut |row| {
                        rows.push(row);
                        Ok(())
                    });
                    drop(finished);
                    (r, rows)
                });
                // Ctrl-C: look at Python's signals every 100 ms while the workers run (and
                // return as soon as they are done, not at the next look).
                while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
                    wait.recv_timeout(std::time::Duration::from_millis(100))
                {
                    if Python::attach(|py| py.check_signals().is_err()) {
                        interrupted = true;
                        halt.store(true, Ordering::Relaxed);
                    }
                }
                let (r, done) = sweeping.join().expect("the sweep thread does not panic: runs' panics are caught");
                rows = done;
                r
            });
            (result, rows, interrupted)
        });
        if interrupted {
            return Err(PyKeyboardInterrupt::new_err(format!("sweep interrupted after {} runs", rows.len())));
        }
        result.map_err(PyRuntimeError::new_err)?;
        let d = PyDict::new(py);
        let header = self.inner.header();
        let n_values = self.inner.spec().parameters.len();
        d.set_item(&header[0], rows.iter().map(|r| r.run as u64).collect::<Vec<_>>().into_pyarray(py))?;
        d.set_item(
            &header[1],
            rows.iter().map(|r| if r.error.is_some() { "failed" } else { "ok" }).collect::<Vec<_>>(),
        )?;
        for k in 0..n_values {
            let column: Vec<f64> = rows.iter().map(|r| r.values[k]).collect();
            d.set_item(&header[2 + k], column.into_pyarray(py))?;
        }
        let n_metrics = header.len() - 3 - n_values;
        for k in 0..n_metrics {
            let column: Vec<f64> = rows.iter().map(|r| r.metrics[k].unwrap_or(f64::NAN)).collect();
            let array: Bound<'py, PyArray1<f64>> = column.into_pyarray(py);
            d.set_item(&header[2 + n_values + k], array)?;
        }
        d.set_item(&header[header.len() - 1], rows.iter().map(|r| r.error.clone()).collect::<Vec<_>>())?;
        Ok(d)
    }
}

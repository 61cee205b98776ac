//! `foldsim._foldsim.Scenario`: a scenario read from a file, TOML text or a dict, changed by
//! key path, and run with the GIL released.

use crate::convert;
use foldsim::observe::{Observation, Selection, row};
use foldsim::scenario::{ScenarioError, ScenarioText, SetValue};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyKeyError, PyKeyboardInterrupt, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt};
use std::path::PathBuf;

/// What `run` returns to Python: column names, one array per column, the report.
pub(crate) type RunOutput<'py> = (Vec<String>, Vec<Bound<'py, PyArray1<f64>>>, Bound<'py, PyDict>);

/// A scenario: a structure, its initial state and run settings (docs/scenario.md).
#[pyclass(module = "foldsim._foldsim")]
#[derive(Clone)]
pub struct Scenario {
    pub(crate) text: ScenarioText,
    pub(crate) inner: std::sync::Arc<foldsim::scenario::Scenario>,
    /// Made from a dict: errors are located by key path, not by line of text nobody wrote.
    from_dict: bool,
}

impl Scenario {
    /// Builds generated scenario text (labelled `name`, tables relative to the current
    /// directory).
    pub(crate) fn from_toml_text(text: &str, name: &str) -> PyResult<Self> {
        let text = ScenarioText::new(text, name, std::path::Path::new("."))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Self::build(text, false)
    }

    fn build(text: ScenarioText, from_dict: bool) -> PyResult<Self> {
        match text.build() {
            Ok(inner) => Ok(Self { text, inner: inner.into(), from_dict }),
            Err(e) => Err(error(&text, from_dict, e)),
        }
    }
}

/// A scenario error as ValueError: located by file and line, or (for a dict) by key path.
fn error(text: &ScenarioText, from_dict: bool, e: ScenarioError) -> PyErr {
    match (from_dict, e.location) {
        (true, Some((line, _))) => {
            let at = convert::path_at_line(&text.text(), line);
            PyValueError::new_err(format!("{} at {at}: {}", e.file, e.message))
        }
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A Python value to set at a key path: a number as a number, anything else as TOML.
fn set_value(value: &Bound<'_, PyAny>, path: &str) -> PyResult<SetValue> {
    if value.is_instance_of::<PyFloat>()
        || value.is_instance_of::<PyInt>() && !value.is_instance_of::<pyo3::types::PyBool>()
    {
        return Ok(SetValue::Number(value.extract()?));
    }
    let v = convert::value(value, path)?;
    Ok(SetValue::Toml(v.to_string()))
}

#[pymethods]
impl Scenario {
    /// Reads a scenario file; a bad file raises ValueError naming the file, line and key.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        let text = ScenarioText::from_file(&path).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Self::build(text, false)
    }

    /// Reads a scenario from TOML text; `name` stands for the file in messages, `base` is the
    /// directory table files are read from.
    #[staticmethod]
    #[pyo3(signature = (text, name = "scenario", base = None))]
    fn from_toml(text: &str, name: &str, base: Option<PathBuf>) -> PyResult<Self> {
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        let text = ScenarioText::new(text, name, &base).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Self::build(text, false)
    }

    /// Builds a scenario from a dict with a scenario file's structure (lists of dicts for
    /// `body` and `hinge`); errors name the key path.
    #[staticmethod]
    #[pyo3(signature = (d, name = "scenario dict", base = None))]
    fn from_dict(d: &Bound<'_, PyDict>, name: &str, base: Option<PathBuf>) -> PyResult<Self> {
        let doc = convert::document(d)?;
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        let text =
            ScenarioText::new(&doc.to_string(), name, &base).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Self::build(text, true)
    }

    /// The scenario as TOML text (what a file of it would hold).
    #[getter]
    fn text(&self) -> String {
        self.text.text()
    }

    /// The file name (or label) messages use.
    #[getter]
    fn name(&self) -> String {
        self.text.file.clone()
    }

    /// The directory table files are read from.
    #[getter]
    fn base(&self) -> PathBuf {
        self.text.base.clone()
    }

    /// The value at a key path (`hinge.h1.law.k_theta`); KeyError naming the path when the
    /// scenario has nothing there (a key it leaves out, or one that does not exist).
    fn get<'py>(&self, py: Python<'py>, path: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(text) = self.text.get(path).map_err(PyKeyError::new_err)? else {
            return Err(PyKeyError::new_err(format!(
                "{}: the scenario has no value at '{path}' (a key it leaves out takes its default, docs/scenario.md; pass a default to get() for one)",
                self.text.file
            )));
        };
        match text.parse::<toml_edit::Value>() {
            Ok(v) => convert::to_python(py, &v).map(Some),
            // A table: give it as text.
            Err(_) => Ok(Some(text.into_pyobject(py)?.into_any())),
        }
    }

    /// A copy with the values of `changes` ({key path: value}) set and checked.
    fn with_values(&self, changes: &Bound<'_, PyDict>) -> PyResult<Self> {
        let mut text = self.text.clone();
        let paths: Vec<String> = changes
            .keys()
            .iter()
            .map(|k| {
                k.extract::<String>().map_err(|_| PyTypeError::new_err("with_values() takes key paths (str) as keys"))
            })
            .collect::<PyResult<_>>()?;
        let named: Vec<&str> = paths.iter().map(String::as_str).collect();
        self.text.check_distinct(&named).map_err(PyValueError::new_err)?;
        for (k, v) in changes.iter() {
            let path: String = k.extract()?;
            text.set(&path, &set_value(&v, &path)?).map_err(PyValueError::new_err)?;
        }
        Self::build(text, self.from_dict)
    }

    /// Simulated time of a run, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.inner.settings.duration
    }

    /// The files the scenario reads (its file, if read from one, and its table files).
    #[getter]
    fn inputs(&self) -> Vec<PathBuf> {
        self.inner.inputs.clone()
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

    /// Warnings about values that are valid but probably not meant.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// The linear state-space model at time `at` of the run (or the design state with
    /// `deployed`): a dict of A, B, C, D (NumPy arrays), y0, t, residual and the names of
    /// states, inputs and outputs (docs/linear.md).
    /// With `modes`, reduced to that many modes (free-free, or with `hub_held` the hub and
    /// the modes with the hub held).
    #[pyo3(signature = (at = 0.0, deployed = false, inputs = None, outputs = None, modes = None, hub_held = false))]
    #[allow(clippy::too_many_arguments)]
    fn linearize<'py>(
        &self,
        py: Python<'py>,
        at: f64,
        deployed: bool,
        inputs: Option<Vec<String>>,
        outputs: Option<Vec<String>>,
        modes: Option<usize>,
        hub_held: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let scenario = self.text.build().map_err(|e| error(&self.text, self.from_dict, e))?;
        crate::linear::linearize(py, scenario, at, deployed, inputs, outputs, (modes, hub_held))
    }

    /// The modes at time `at` of the run (or the design state with `deployed`): every mode
    /// (dense), or the `count` lowest flexible ones (Lanczos) (docs/linear.md).
    #[pyo3(signature = (at = 0.0, deployed = false, count = None))]
    fn modes<'py>(
        &self,
        py: Python<'py>,
        at: f64,
        deployed: bool,
        count: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let scenario = self.text.build().map_err(|e| error(&self.text, self.from_dict, e))?;
        crate::linear::modes(py, scenario, at, deployed, count)
    }

    /// Starts a run advanced piece by piece (`Simulation`): `columns` as for `run`.
    #[pyo3(signature = (columns = None))]
    fn start(&self, columns: Option<Vec<String>>) -> PyResult<crate::simulation::Simulation> {
        let scenario = self.text.build().map_err(|e| error(&self.text, self.from_dict, e))?;
        crate::simulation::Simulation::start(scenario, columns)
    }

    /// How deep any two bodies overlap over a run given as its columns (`names`, `columns`:
    /// one list of values per name, every list one value per row) or as the CSV at `csv`:
    /// one dict per overlapping pair (`body_a`, `body_b`, `depth` m, `of_thickness`, `t` s),
    /// deepest first; thin plates as the contact samples describe them or, with `sharp`, as
    /// sharp prisms (docs/contact.md §3).
    #[pyo3(signature = (names = None, columns = None, csv = None, sharp = false))]
    fn overlaps<'py>(
        &self,
        py: Python<'py>,
        names: Option<Vec<String>>,
        columns: Option<Vec<Vec<f64>>>,
        csv: Option<PathBuf>,
        sharp: bool,
    ) -> PyResult<Bound<'py, pyo3::types::PyList>> {
        let table = match (names, columns, csv) {
            (Some(header), Some(columns), None) => {
                if header.len() != columns.len() {
                    return Err(PyValueError::new_err(format!(
                        "overlaps: {} names for {} columns",
                        header.len(),
                        columns.len()
                    )));
                }
                let rows = columns.first().map_or(0, Vec::len);
                if let Some((name, c)) = header.iter().zip(&columns).find(|(_, c)| c.len() != rows) {
                    return Err(PyValueError::new_err(format!(
                        "overlaps: column {name} has {} values where the first has {rows}",
                        c.len()
                    )));
                }
                let rows = (0..rows).map(|k| columns.iter().map(|c| c[k]).collect()).collect();
                foldsim::output::table::Table { header, rows }
            }
            (None, None, Some(csv)) => foldsim::output::table::Table::read(&csv).map_err(PyValueError::new_err)?,
            _ => return Err(PyTypeError::new_err("overlaps takes a run's names and columns, or a csv path")),
        };
        overlaps(py, &self.inner.model, &table, sharp)
    }

    /// Runs the scenario with the GIL released. `columns`: names or patterns as `run.columns`
    /// takes them (default: the scenario's). Returns (names, arrays, report). Ctrl-C stops
    /// the run with KeyboardInterrupt.
    #[pyo3(signature = (columns = None, progress = None))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        columns: Option<Vec<String>>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<RunOutput<'py>> {
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
            let mut progress = crate::interrupt_check(progress);
            let settings = foldsim::simulate::RunSettings { hinge_loads: selection.has_hinge_loads(), ..s.settings };
            foldsim::simulate::simulate(&s.model, &s.initial, &settings, &mut sink, Some(&mut progress))
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
        let d = report_dict(py, &s.model, &report)?;
        Ok((selection.names.clone(), arrays, d))
    }
}

/// How deep any two bodies overlap over a finished run: its columns by name (each one value
/// per row, as `run` returns them) or, with `csv`, the CSV `foldsim run` wrote; measured
/// apart from the contact code (`foldsim::verify::overlap`, docs/contact.md §3), the GIL
/// released. One dict per pair that overlaps at some row, deepest first.
fn overlaps<'py>(
    py: Python<'py>,
    model: &foldsim::model::Model,
    table: &foldsim::output::table::Table,
    sharp: bool,
) -> PyResult<Bound<'py, pyo3::types::PyList>> {
    use foldsim::verify::overlap::{Solids, deepest_overlaps};
    let kind = if sharp { Solids::Sharp } else { Solids::Sampled };
    let found = py
        .detach(|| {
            let (poses, _) = foldsim::output::table::poses_from_table(model, table)?;
            deepest_overlaps(model, &poses, kind, None)
        })
        .map_err(PyValueError::new_err)?;
    let list = pyo3::types::PyList::empty(py);
    for o in found {
        let d = PyDict::new(py);
        d.set_item("body_a", &model.bodies[o.bodies.0].name)?;
        d.set_item("body_b", &model.bodies[o.bodies.1].name)?;
        d.set_item("depth", o.depth)?;
        d.set_item("of_thickness", o.of_thickness)?;
        d.set_item("t", o.t)?;
        list.append(d)?;
    }
    Ok(list)
}

/// A run report as a dict of Python values (docs/python.md).
pub(crate) fn report_dict<'py>(
    py: Python<'py>,
    model: &foldsim::model::Model,
    report: &foldsim::simulate::RunReport,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let drift = &report.drift;
    d.set_item("simulated", report.simulated)?;
    d.set_item("wall_seconds", report.wall_seconds)?;
    d.set_item("steps_accepted", report.steps_accepted)?;
    d.set_item("steps_rejected", report.steps_rejected)?;
    d.set_item("newton_failures", report.newton_failures)?;
    d.set_item("rhs_evaluations", report.rhs_evaluations)?;
    d.set_item("newton_iterations", report.newton_iterations)?;
    d.set_item("jacobians", report.jacobians)?;
    d.set_item("refactorizations", report.refactorizations)?;
    let methods: Vec<(f64, &str, &str)> = report.methods.iter().map(|m| (m.from, m.method, m.why.as_str())).collect();
    d.set_item("methods", methods)?;
    d.set_item("rows", report.rows)?;
    // run.position_tolerance (None without): asked and estimated (m), the output run's rtol
    // and its check's, and every run made as (rtol = atol, wall s).
    match &report.position_accuracy {
        None => d.set_item("position_accuracy", py.None())?,
        Some(a) => {
            let pd = PyDict::new(py);
            pd.set_item("asked", a.asked)?;
            pd.set_item("estimated", a.estimated)?;
            pd.set_item("difference", a.difference)?;
            pd.set_item("rtol", a.rtol)?;
            pd.set_item("check_rtol", a.check_rtol)?;
            pd.set_item("runs", a.runs.clone())?;
            d.set_item("position_accuracy", pd)?;
        }
    }
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
    d.set_item("deployed_start", report.deployed_start)?;
    d.set_item("deployed_max", report.deployed_max)?;
    // Contact (None without a [contact] table): the first touch, the deepest penetration
    // and the largest force, with times and body pairs, and the energy dissipated.
    let body = |i: usize| model.bodies[i].name.clone();
    match &report.contact {
        None => d.set_item("contact", py.None())?,
        Some(c) => {
            let cd = PyDict::new(py);
            cd.set_item("first", c.first.map(|(t, a, b)| (t, body(a), body(b))))?;
            let (depth, t, a, b) = c.deepest;
            cd.set_item("deepest", (depth > 0.0).then(|| (depth, t, body(a), body(b))))?;
            let (force, t, a, b) = c.force_max;
            cd.set_item("force_max", (force > 0.0).then(|| (force, t, body(a), body(b))))?;
            cd.set_item("dissipated", report.contact_dissipated)?;
            // Every episode of every pair (docs/contact.md, *Episodes*).
            let episodes = pyo3::types::PyList::empty(py);
            for e in &report.contact_episodes {
                let ed = PyDict::new(py);
                ed.set_item("bodies", (body(e.bodies.0), body(e.bodies.1)))?;
                ed.set_item("kind", if e.resting { "resting" } else { "impact" })?;
                ed.set_item("start", e.start)?;
                ed.set_item("end", e.end)?;
                ed.set_item("impact_speed", e.impact_speed)?;
                ed.set_item("deepest", e.deepest)?;
                ed.set_item("peak_force", e.peak_force)?;
                ed.set_item("joined", e.joined)?;
                episodes.append(ed)?;
            }
            cd.set_item("episodes", episodes)?;
            d.set_item("contact", cd)?;
        }
    }
    // External loads (None without [[load]]): work (J), impulse (N·s) and angular impulse
    // about N's origin (N·m·s), N frame.
    match &report.loads {
        None => d.set_item("loads", py.None())?,
        Some(l) => {
            let ld = PyDict::new(py);
            ld.set_item("work", l.work)?;
            ld.set_item("impulse", l.impulse_in_n.as_slice().to_vec())?;
            ld.set_item("angular_impulse", l.angular_impulse_in_n.as_slice().to_vec())?;
            d.set_item("loads", ld)?;
        }
    }
    // The hub's control (None without [control]): per actuator its largest torque (N·m) and
    // momentum (N·m·s, wheels), and when its limits first cut it (s, or None).
    match &model.control {
        None => d.set_item("actuators", py.None())?,
        Some(c) => {
            let ad = PyDict::new(py);
            for (name, rec) in c.actuator_names().iter().zip(&report.actuators) {
                let one = PyDict::new(py);
                one.set_item("torque_max", rec.effort_max)?;
                one.set_item("momentum_max", rec.momentum_max)?;
                one.set_item("torque_limit_from", rec.torque_first)?;
                one.set_item("torque_limit_time", rec.torque_time)?;
                one.set_item("momentum_limit_from", rec.momentum_first)?;
                one.set_item("momentum_limit_time", rec.momentum_time)?;
                ad.set_item(*name, one)?;
            }
            d.set_item("actuators", ad)?;
        }
    }
    let hinge = |i: usize| model.hinges[i].name.clone();
    let events: Vec<(f64, String, String, String)> =
        report.events.iter().map(|e| (e.t, hinge(e.hinge), format!("{:?}", e.kind), e.description.clone())).collect();
    d.set_item("events", events)?;
    let latches: Vec<(f64, String)> = report
        .events
        .iter()
        .filter(|e| e.kind == foldsim::law::EventKind::Latch)
        .map(|e| (e.t, hinge(e.hinge)))
        .collect();
    d.set_item("latches", latches)?;
    let directions = foldsim::law::directional::DIRECTION_NAMES;
    let locks: Vec<(f64, String, String)> = report
        .lock_engagements
        .iter()
        .map(|(l, t)| (*t, hinge(l.hinge), directions[l.direction].to_string()))
        .collect();
    d.set_item("lock_engagements", locks)?;
    Ok(d)
}

//! `foldsim._foldsim.Simulation`: a run advanced piece by piece from Python (a user's own
//! controller in the loop; docs/gnc.md), over `foldsim::simulate::Stepper`.

use crate::scenario::report_dict;
use foldsim::loads::LoadFrame;
use foldsim::math::Vec3;
use foldsim::observe::{Observation, Selection, catalogue, row};
use foldsim::simulate::Stepper;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

type Dependent<'a> = Stepper<'a>;

self_cell::self_cell!(
    /// A scenario and the stepped run of it that borrows its model.
    struct Cell {
        owner: Box<foldsim::scenario::Scenario>,
        #[not_covariant]
        dependent: Dependent,
    }
);

/// A run advanced piece by piece: `advance(dt)`, the current row, commands, the rows so far.
// Not `unsendable`: a host may drop it on another thread (Basilisk does, at its end), so the
// run sits behind a mutex (it is Send; the lock is uncontended).
#[pyclass(module = "foldsim._foldsim")]
pub struct Simulation {
    cell: std::sync::Mutex<Cell>,
    /// The columns `result()` gives.
    selection: Selection,
    /// Every column's name as a Python string, made once (`state` is called every control
    /// period).
    names: Vec<Py<pyo3::types::PyString>>,
    /// The inputs by name (as the FMU and the C library name them) with their values.
    inputs: foldsim::session::Inputs,
}

impl Simulation {
    /// The run, locked for one call (a lock poisoned by an earlier panic, which pyo3 raised
    /// as an exception, still gives it).
    fn cell(&self) -> std::sync::MutexGuard<'_, Cell> {
        self.cell.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Starts a stepped run of `scenario` (its model made to take commands).
    pub(crate) fn start(mut scenario: foldsim::scenario::Scenario, columns: Option<Vec<String>>) -> PyResult<Self> {
        // A scenario without `run.columns` takes the default set of the model as it runs here
        // (taking commands, so with the work column W).
        let own_columns = scenario.columns != Selection::default_for(&scenario.model);
        scenario.model.commandable = true;
        let selection = match columns {
            Some(patterns) => Selection::matching(&scenario.model, &patterns).map_err(PyValueError::new_err)?,
            None if own_columns => scenario.columns.clone(),
            None => Selection::default_for(&scenario.model),
        };
        scenario.settings.hinge_loads = selection.has_hinge_loads();
        let names = Python::attach(|py| {
            catalogue(&scenario.model).into_iter().map(|c| pyo3::types::PyString::new(py, &c.name).unbind()).collect()
        });
        let inputs = foldsim::session::Inputs::of(&scenario.model);
        let cell = Cell::try_new(Box::new(scenario), |s| Stepper::start(&s.model, &s.initial, &s.settings))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok(Self { cell: std::sync::Mutex::new(cell), selection, names, inputs })
    }
}

/// A frame's name as a load frame.
fn frame(name: &str) -> PyResult<LoadFrame> {
    match name {
        "inertial" => Ok(LoadFrame::Inertial),
        "body" => Ok(LoadFrame::Body),
        other => Err(PyValueError::new_err(format!(
            "frame is \"inertial\" (fixed in space) or \"body\" (turning with the body), got {other:?}"
        ))),
    }
}

#[pymethods]
impl Simulation {
    /// Integrates to exactly t + dt (s).
    fn advance(&mut self, dt: f64) -> PyResult<()> {
        self.cell().with_dependent_mut(|_, s| s.advance(dt)).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    /// The time reached, s.
    #[getter]
    fn t(&self) -> f64 {
        self.cell().with_dependent(|_, s| s.time())
    }

    /// Every output column at the time reached, by name.
    fn state<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let values = self.cell().with_dependent_mut(|_, s| row(&s.current()));
        let d = PyDict::new(py);
        for (n, v) in self.names.iter().zip(values) {
            d.set_item(n.bind(py), v)?;
        }
        Ok(d)
    }

    /// Keeps no rows from now on (`result()` then has none): a host that reads `state` at its
    /// own times keeps its memory flat over a long run.
    fn discard_rows(&mut self) {
        self.cell().with_dependent_mut(|_, s| s.discard_rows());
    }

    /// The structure's mass properties at the time reached, in the hub's frame: total mass
    /// (kg), barycenter from the hub's centre of mass (m), inertia about the hub's centre of
    /// mass (kg·m², 3 × 3 rows), wheels' spin inertias included.
    fn mass_properties(&self) -> (f64, [f64; 3], [[f64; 3]; 3]) {
        self.cell().with_dependent(|_, s| {
            let (m, c, i) = foldsim::observe::mass_about_hub(s.model(), s.state());
            (
                m,
                [c.x, c.y, c.z],
                [
                    [i[(0, 0)], i[(0, 1)], i[(0, 2)]],
                    [i[(1, 0)], i[(1, 1)], i[(1, 2)]],
                    [i[(2, 0)], i[(2, 1)], i[(2, 2)]],
                ],
            )
        })
    }

    /// Every input's name (`<body>_F_x` … `<body>_T_z` in the body's frame, `<motor>_effort`,
    /// `<actuator>_torque`), as `foldsim linearize`, the FMU and the C library name them.
    #[getter]
    fn inputs(&self) -> Vec<String> {
        self.inputs.list().iter().map(|i| i.name.clone()).collect()
    }

    /// Sets an input by name from now on (its unit: N, N·m; forces and torques in the body's
    /// own frame). A body's three torque inputs make its whole torque: `set_torque` on the same
    /// body replaces it, and the next `set_input` replaces that.
    fn set_input(&mut self, name: &str, value: f64) -> PyResult<()> {
        let k = self.inputs.index(name).map_err(PyValueError::new_err)?;
        let Self { cell, inputs, .. } = self;
        let cell = cell.get_mut().unwrap_or_else(|e| e.into_inner());
        cell.with_dependent_mut(|_, s| inputs.set(s, k, value)).map_err(PyValueError::new_err)
    }

    /// Sets the torque on a body from now on: N·m, in `frame` ("inertial" or "body").
    fn set_torque(&mut self, body: &str, torque: [f64; 3], frame_name: &str) -> PyResult<()> {
        let f = frame(frame_name)?;
        self.cell().with_dependent_mut(|owner, s| {
            let b = body_index(&owner.model, body)?;
            s.set_torque(b, Vec3::from(torque), f).map_err(PyValueError::new_err)
        })
    }

    /// Sets the force on a body from now on: N, in `frame`, at `point` (m from its centre of
    /// mass, body frame).
    fn set_force(&mut self, body: &str, force: [f64; 3], frame_name: &str, point: [f64; 3]) -> PyResult<()> {
        let f = frame(frame_name)?;
        self.cell().with_dependent_mut(|owner, s| {
            let b = body_index(&owner.model, body)?;
            s.set_force(b, Vec3::from(force), Vec3::from(point), f).map_err(PyValueError::new_err)
        })
    }

    /// Sets a motor's effort from now on (N or N·m); None gives it back to its drive.
    fn set_motor(&mut self, name: &str, value: Option<f64>) -> PyResult<()> {
        self.cell().with_dependent_mut(|owner, s| {
            let m = owner.model.motors.iter().position(|m| m.name == name).ok_or_else(|| {
                let names: Vec<&str> = owner.model.motors.iter().map(|m| m.name.as_str()).collect();
                PyValueError::new_err(format!("no motor {name:?} (the motors are {names:?})"))
            })?;
            s.set_motor(m, value).map_err(PyValueError::new_err)
        })
    }

    /// Sets the control's actuator torques from now on (N·m, one per wheel or torque source
    /// in the scenario's order); None gives them back to the control law.
    fn set_wheel_torque(&mut self, values: Option<Vec<f64>>) -> PyResult<()> {
        self.cell().with_dependent_mut(|_, s| s.set_actuators(values)).map_err(PyValueError::new_err)
    }

    /// The rows so far: (names, arrays, report), as `Scenario.run` gives them.
    fn result<'py>(&self, py: Python<'py>) -> PyResult<crate::scenario::RunOutput<'py>> {
        self.cell().with_dependent(|owner, s| {
            let width = self.selection.indices.len();
            let mut values: Vec<Vec<f64>> = vec![Vec::new(); width];
            for o in s.rows() {
                let r = row(o as &Observation);
                for (k, &i) in self.selection.indices.iter().enumerate() {
                    values[k].push(r[i]);
                }
            }
            let arrays: Vec<Bound<'py, PyArray1<f64>>> = values.into_iter().map(|v| v.into_pyarray(py)).collect();
            let d = report_dict(py, &owner.model, &s.report())?;
            Ok((self.selection.names.clone(), arrays, d))
        })
    }
}

/// A body's index by name.
fn body_index(model: &foldsim::model::Model, name: &str) -> PyResult<usize> {
    model.body_index(name).ok_or_else(|| {
        let names: Vec<&str> = model.bodies.iter().map(|b| b.name.as_str()).collect();
        PyValueError::new_err(format!("no body {name:?} (the bodies are {names:?})"))
    })
}

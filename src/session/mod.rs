//! A scenario's run stepped from outside, by name: the one simulation that the C library
//! (`capi/`), the FMU (`fmu/`) and the Basilisk module drive (docs/interop.md). Inputs are
//! named as `foldsim linearize` names them ([`crate::model::inputs`]), outputs as the CSV
//! columns ([`crate::observe::catalogue`]), parameters as sweeps name scenario values
//! ([`parameters`]). It owns no physics: it holds a [`Stepper`] with the scenario it runs and
//! turns names into the stepper's commands.
//!
//! - [`Session`]: start, set inputs, advance, read outputs;
//! - [`inputs`]: inputs by name turned into a stepped run's commands (also the Python
//!   package's `Simulation.set_input`);
//! - [`parameters`]: the scenario's numbers by key path, changed before a session starts.

pub mod inputs;
pub mod parameters;

pub use inputs::Inputs;

use crate::model::inputs::Input;
use crate::observe::{catalogue, row};
use crate::scenario::Scenario;
use crate::simulate::{RunReport, Stepper};

self_cell::self_cell!(
    /// A scenario and the stepped run of it that borrows its model.
    struct Cell {
        owner: Box<Scenario>,
        #[not_covariant]
        dependent: Stepper,
    }
);

/// A scenario's run, stepped from outside with named inputs and outputs.
pub struct Session {
    cell: Cell,
    /// Every input the model takes (forces and torques on every body, motors, actuators)
    /// with its value as last set.
    inputs: Inputs,
    /// Every output column's name, in [`row`]'s order.
    outputs: Vec<String>,
    /// The outputs at the time reached, made when first read after a change.
    row: Option<Vec<f64>>,
}

impl Session {
    /// Starts a run of `scenario` at t = 0 (its model made to take commands, so the work
    /// column `W` is among the outputs). Fails as a run's start fails.
    pub fn start(mut scenario: Scenario) -> Result<Self, String> {
        scenario.model.commandable = true;
        scenario.settings.hinge_loads = false;
        let inputs = Inputs::of(&scenario.model);
        let outputs = catalogue(&scenario.model).into_iter().map(|c| c.name).collect();
        let mut cell = Cell::try_new(Box::new(scenario), |s| Stepper::start(&s.model, &s.initial, &s.settings))
            .map_err(|e| e.to_string())?;
        // Its hosts read the outputs at the time reached; rows would only grow.
        cell.with_dependent_mut(|_, s| s.discard_rows());
        Ok(Self { cell, inputs, outputs, row: None })
    }

    /// The scenario it runs.
    pub fn scenario(&self) -> &Scenario {
        self.cell.borrow_owner()
    }

    /// Every input, in the order [`Session::set_input`] takes them.
    pub fn inputs(&self) -> &[Input] {
        self.inputs.list()
    }

    /// Every output's name, in the order [`Session::output`] takes them.
    pub fn output_names(&self) -> &[String] {
        &self.outputs
    }

    /// The input named `name`'s position; the error names some valid ones.
    pub fn input_index(&self, name: &str) -> Result<usize, String> {
        self.inputs.index(name)
    }

    /// The output named `name`'s position; the error names some valid ones.
    pub fn output_index(&self, name: &str) -> Result<usize, String> {
        self.outputs.iter().position(|o| o == name).ok_or_else(|| {
            let some: Vec<&str> = self.outputs.iter().take(8).map(|o| o.as_str()).collect();
            format!("no output {name:?}: outputs are the CSV columns of docs/outputs.md, here {}, …", some.join(", "))
        })
    }

    /// Sets input `index` to `value` (in its unit, [`Input::unit`]) from now on: it acts,
    /// constant, until set again. Refused: an index out of range, a value that is not
    /// finite.
    pub fn set_input(&mut self, index: usize, value: f64) -> Result<(), String> {
        self.row = None;
        let inputs = &mut self.inputs;
        self.cell.with_dependent_mut(|_, s| inputs.set(s, index, value))
    }

    /// Input `index`'s value as last set (0 until set).
    pub fn input(&self, index: usize) -> Option<f64> {
        self.inputs.value(index)
    }

    /// Integrates to exactly `t + dt` (s) with the scenario's integrator
    /// ([`Stepper::advance`]).
    pub fn advance(&mut self, dt: f64) -> Result<(), String> {
        self.row = None;
        self.cell.with_dependent_mut(|_, s| s.advance(dt)).map_err(|e| e.to_string())
    }

    /// The time reached, s.
    pub fn time(&self) -> f64 {
        self.cell.with_dependent(|_, s| s.time())
    }

    /// Every output at the time reached, in [`Session::output_names`]' order.
    pub fn outputs(&mut self) -> &[f64] {
        if self.row.is_none() {
            self.row = Some(self.cell.with_dependent_mut(|_, s| row(&s.current())));
        }
        self.row.as_deref().unwrap_or_default()
    }

    /// Output `index` at the time reached.
    pub fn output(&mut self, index: usize) -> Result<f64, String> {
        let n = self.outputs.len();
        self.outputs()
            .get(index)
            .copied()
            .ok_or_else(|| format!("output index {index} is out of range: there are {n} outputs"))
    }

    /// The run's report so far.
    pub fn report(&self) -> RunReport {
        self.cell.with_dependent(|_, s| s.report())
    }
}

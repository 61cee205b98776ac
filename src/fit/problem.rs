//! A fit's least-squares problem: the scenario with its free values set, run with rows at the
//! measurement times ([`crate::simulate::simulate_at`]), its columns against the data (the
//! Jacobian by differences, the perturbed runs in parallel: [`super::differences`]).

use super::data::Data;
use super::params::Free;
use crate::observe::{Observation, is_hinge_load, row};
use crate::scenario::{ScenarioText, SetValue};
use crate::simulate::{RunSettings, simulate_at};

/// The scenario, the free values and the data.
#[derive(Clone, Debug)]
pub struct Problem {
    text: ScenarioText,
    /// The free parameters.
    pub free: Vec<Free>,
    /// The measurements.
    pub data: Data,
    /// Whether a measured column is a hinge load (then the runs add the locks' reactions).
    hinge_loads: bool,
}

impl Problem {
    /// The problem of fitting `free` of `text` to `data` (read against the same scenario).
    pub fn new(text: ScenarioText, free: Vec<Free>, data: Data) -> Result<Self, String> {
        let count = data.count();
        if count <= free.len() {
            return Err(format!(
                "{}: {count} measured values for {} free parameters; a fit needs more values than parameters",
                data.file,
                free.len()
            ));
        }
        let hinge_loads = data.columns.iter().any(|c| is_hinge_load(&c.name));
        Ok(Self { text, free, data, hinge_loads })
    }

    /// The scenario text with the free values set to `x`.
    pub fn scenario_at(&self, x: &[f64]) -> Result<ScenarioText, String> {
        let mut text = self.text.clone();
        for (f, v) in self.free.iter().zip(x) {
            text.set(&f.path, &SetValue::Number(*v))?;
        }
        Ok(text)
    }

    /// The run's values of the measured columns at the data's times (per column, per time),
    /// with the free values at `x`.
    pub fn predict(&self, x: &[f64]) -> Result<Vec<Vec<f64>>, String> {
        let s = self.scenario_at(x)?.build().map_err(|e| format!("the run with {}: {e}", self.describe(x)))?;
        let settings = RunSettings { hinge_loads: self.hinge_loads, ..s.settings };
        let mut out: Vec<Vec<f64>> = vec![Vec::with_capacity(self.data.times.len()); self.data.columns.len()];
        let mut sink = |o: &Observation| -> Result<(), String> {
            let r = row(o);
            for (c, m) in out.iter_mut().zip(&self.data.columns) {
                c.push(r[m.index]);
            }
            Ok(())
        };
        simulate_at(&s.model, &s.initial, &settings, &self.data.times, &mut sink)
            .map_err(|e| format!("the run with {}: {e}", self.describe(x)))?;
        if out.iter().any(|c| c.len() != self.data.times.len()) {
            return Err(format!("the run with {} did not reach every measurement time", self.describe(x)));
        }
        Ok(out)
    }

    /// The free values as `path = value` pairs, for messages.
    pub fn describe(&self, x: &[f64]) -> String {
        self.free
            .iter()
            .zip(x)
            .map(|(f, v)| format!("{} = {}", f.path, crate::math::short(*v)))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The weighted residuals `(run − measured) / σ` over every measured cell, column by
    /// column, from `predict`'s values.
    pub fn residuals_of(&self, predicted: &[Vec<f64>]) -> Vec<f64> {
        let mut r = Vec::with_capacity(self.data.count());
        for (c, p) in self.data.columns.iter().zip(predicted) {
            let w = 1.0 / c.sigma.unwrap_or(1.0);
            for (v, q) in c.values.iter().zip(p) {
                if let Some(v) = v {
                    r.push((q - v) * w);
                }
            }
        }
        r
    }
}

impl super::Fitted for Problem {
    fn free(&self) -> &[Free] {
        &self.free
    }

    fn data_summary(&self) -> String {
        format!(
            "{} values in {} column(s) of {} ({} times)",
            self.data.count(),
            self.data.columns.len(),
            self.data.file,
            self.data.times.len()
        )
    }

    fn abscissa(&self) -> String {
        "t (s)".into()
    }

    fn columns(&self, x: &[f64]) -> Result<Vec<super::Column>, String> {
        let p = self.predict(x)?;
        Ok(self
            .data
            .columns
            .iter()
            .zip(p)
            .map(|(c, fitted)| super::Column {
                name: c.name.clone(),
                unit: crate::output::units::unit_of(&c.name),
                abscissa: self.data.times.clone(),
                measured: c.values.clone(),
                fitted,
                sigma: c.sigma,
            })
            .collect())
    }

    /// The weighted residuals at `x`.
    fn residuals(&self, x: &[f64]) -> Result<Vec<f64>, String> {
        let p = self.predict(x)?;
        let r = self.residuals_of(&p);
        if r.iter().all(|v| v.is_finite()) {
            Ok(r)
        } else {
            Err(format!("the run with {} gave a non-finite value at a measurement time", self.describe(x)))
        }
    }
}

//! A fit's least-squares problem: the scenario with its free values set, run with rows at the
//! measurement times ([`crate::simulate::simulate_at`]), its columns against the data; the
//! Jacobian by central differences, the perturbed runs in parallel on every core.

use super::data::Data;
use super::params::Free;
use crate::observe::{Observation, is_hinge_load, row};
use crate::scenario::{ScenarioText, SetValue};
use crate::simulate::{RunSettings, simulate_at};
use nalgebra::DMatrix;
use rayon::prelude::*;

/// The relative step of the central differences: about the cube root of the runs' relative
/// error at rtol 1e-12..1e-15 (truncation h² against noise ε/h; Nocedal & Wright, *Numerical
/// Optimization*, §8.1).
pub const DIFFERENCE_STEP: f64 = 6e-6;

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

    /// The weighted residuals at `x`.
    pub fn residuals(&self, x: &[f64]) -> Result<Vec<f64>, String> {
        let p = self.predict(x)?;
        let r = self.residuals_of(&p);
        if r.iter().all(|v| v.is_finite()) {
            Ok(r)
        } else {
            Err(format!("the run with {} gave a non-finite value at a measurement time", self.describe(x)))
        }
    }

    /// The residuals' Jacobian at `x` (where they are `r`) by central differences of step [`DIFFERENCE_STEP`]
    /// times the parameter's size (one-sided, second order, where the step would cross a
    /// bound), the 2 per parameter runs in parallel.
    pub fn jacobian(&self, x: &[f64], r: &[f64]) -> Result<DMatrix<f64>, String> {
        let steps: Vec<(f64, f64, f64)> = self
            .free
            .iter()
            .zip(x)
            .map(|(f, &v)| {
                let width = if (f.high - f.low).is_finite() { 1e-3 * (f.high - f.low) } else { 0.0 };
                // Zero without bounds has no size of its own: 1e-6 in the key's unit.
                let h = DIFFERENCE_STEP * v.abs().max(f.start.abs()).max(width).max(1e-6);
                // Points (x + a h, x + b h) and the derivative's weights follow below.
                if v + h > f.high {
                    (-h, -2.0 * h, h)
                } else if v - h < f.low {
                    (h, 2.0 * h, h)
                } else {
                    (h, -h, h)
                }
            })
            .collect();
        let runs: Vec<(usize, f64)> = steps.iter().enumerate().flat_map(|(k, &(a, b, _))| [(k, a), (k, b)]).collect();
        let results: Vec<Result<Vec<f64>, String>> = runs
            .par_iter()
            .map(|&(k, d)| {
                let mut y = x.to_vec();
                y[k] += d;
                self.residuals(&y)
            })
            .collect();
        let m = self.data.count();
        let mut j = DMatrix::zeros(m, x.len());
        for (k, &(a, b, h)) in steps.iter().enumerate() {
            let (ra, rb) = match (&results[2 * k], &results[2 * k + 1]) {
                (Ok(ra), Ok(rb)) => (ra, rb),
                (Err(e), _) | (_, Err(e)) => {
                    // A value the scenario refuses on one side (a damping that starts at 0
                    // and would turn negative): the one-sided formula on the other side.
                    let column = self
                        .one_sided(x, r, k, if a + b == 0.0 { vec![h, -h] } else { vec![-a] })
                        .map_err(|_| e.clone())?;
                    j.set_column(k, &column);
                    continue;
                }
            };
            for i in 0..m {
                j[(i, k)] = if a + b == 0.0 {
                    (ra[i] - rb[i]) / (2.0 * h)
                } else {
                    // (−3 f(x) + 4 f(x ± h) − f(x ± 2h)) / (±2h).
                    (-3.0 * r[i] + 4.0 * ra[i] - rb[i]) / (2.0 * a)
                };
            }
        }
        Ok(j)
    }

    /// Column `k` of the Jacobian by the one-sided second-order formula, trying the step
    /// directions `tries` (signed steps) in turn until both of its runs succeed.
    fn one_sided(
        &self,
        x: &[f64],
        r: &[f64],
        k: usize,
        tries: impl IntoIterator<Item = f64>,
    ) -> Result<nalgebra::DVector<f64>, String> {
        let mut last = Err(String::new());
        for h in tries {
            let f = self.free.get(k).ok_or("no such parameter")?;
            if x[k] + 2.0 * h > f.high || x[k] + 2.0 * h < f.low {
                continue;
            }
            let at = |d: f64| {
                let mut y = x.to_vec();
                y[k] += d;
                self.residuals(&y)
            };
            match (at(h), at(2.0 * h)) {
                (Ok(ra), Ok(rb)) => {
                    return Ok(nalgebra::DVector::from_fn(r.len(), |i, _| {
                        (-3.0 * r[i] + 4.0 * ra[i] - rb[i]) / (2.0 * h)
                    }));
                }
                (Err(e), _) | (_, Err(e)) => last = Err(e),
            }
        }
        last
    }
}

//! The residuals' Jacobian by differences, the 2 per value evaluations (runs) in parallel
//! on every core: central differences of step [`DIFFERENCE_STEP`] times the value's size,
//! the one-sided second-order formula where a step would cross a bound or the model refuses
//! one side.

use super::params::Free;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// The relative step of the central differences: about the cube root of the runs' relative
/// error at rtol 1e-12..1e-15 (truncation h² against noise ε/h; Nocedal & Wright, *Numerical
/// Optimization*, §8.1).
pub const DIFFERENCE_STEP: f64 = 6e-6;

/// Residuals at a point (a run, or a law's response along a path).
pub type Residuals<'a> = dyn Fn(&[f64]) -> Result<Vec<f64>, String> + Sync + 'a;

/// The Jacobian at `x` of `residuals` (which are `r` there), for the values `free`.
pub fn jacobian(free: &[Free], x: &[f64], r: &[f64], residuals: &Residuals<'_>) -> Result<DMatrix<f64>, String> {
    let steps: Vec<(f64, f64, f64)> = free
        .iter()
        .zip(x)
        .map(|(f, &v)| {
            let width = if (f.high - f.low).is_finite() { 1e-3 * (f.high - f.low) } else { 0.0 };
            // Zero without bounds has no size of its own: 1e-6 in the key's unit.
            let h = DIFFERENCE_STEP * v.abs().max(f.start.abs()).max(width).max(1e-6);
            // The two points x + a and x + b, and the step h.
            if v + h > f.high {
                (-h, -2.0 * h, h)
            } else if v - h < f.low {
                (h, 2.0 * h, h)
            } else {
                (h, -h, h)
            }
        })
        .collect();
    let at = |k: usize, d: f64| {
        let mut y = x.to_vec();
        y[k] += d;
        residuals(&y)
    };
    let points: Vec<(usize, f64)> = steps.iter().enumerate().flat_map(|(k, &(a, b, _))| [(k, a), (k, b)]).collect();
    let results: Vec<Result<Vec<f64>, String>> = points.par_iter().map(|&(k, d)| at(k, d)).collect();
    let m = r.len();
    let mut j = DMatrix::zeros(m, x.len());
    for (k, &(a, b, h)) in steps.iter().enumerate() {
        let (ra, rb) = match (&results[2 * k], &results[2 * k + 1]) {
            (Ok(ra), Ok(rb)) => (ra, rb),
            (Err(e), _) | (_, Err(e)) => {
                // A value the model refuses on one side (a damping that starts at 0 and
                // would turn negative): the one-sided formula on the other side.
                let tries = if a + b == 0.0 { vec![h, -h] } else { vec![-a] };
                let column = one_sided(&free[k], x[k], r, tries, &|d| at(k, d)).map_err(|_| e.clone())?;
                j.set_column(k, &column);
                continue;
            }
        };
        if ra.len() != m || rb.len() != m {
            return Err("the residuals changed in number between evaluations".into());
        }
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

/// One column by the one-sided second-order formula, trying the signed steps `tries` in turn
/// until both of its evaluations (`at(step)`) succeed.
fn one_sided(
    f: &Free,
    x: f64,
    r: &[f64],
    tries: Vec<f64>,
    at: &dyn Fn(f64) -> Result<Vec<f64>, String>,
) -> Result<DVector<f64>, String> {
    let mut last = Err(String::new());
    for h in tries {
        if x + 2.0 * h > f.high || x + 2.0 * h < f.low {
            continue;
        }
        match (at(h), at(2.0 * h)) {
            (Ok(ra), Ok(rb)) if ra.len() == r.len() && rb.len() == r.len() => {
                return Ok(DVector::from_fn(r.len(), |i, _| (-3.0 * r[i] + 4.0 * ra[i] - rb[i]) / (2.0 * h)));
            }
            (Err(e), _) | (_, Err(e)) => last = Err(e),
            _ => last = Err("the residuals changed in number between evaluations".into()),
        }
    }
    last
}

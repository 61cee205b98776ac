//! Bounded nonlinear least squares: Levenberg–Marquardt with Marquardt's scaling and
//! Nielsen's damping update (Madsen, Nielsen & Tingleff, *Methods for Non-Linear Least
//! Squares Problems*, 2004, §3.2, Algorithm 3.16; the scaling as Moré, "The
//! Levenberg–Marquardt algorithm: implementation and theory", 1978), kept inside box bounds
//! by projection: a parameter at a bound whose gradient pushes it outward is held there for
//! the step (an active set), and the step is clipped to the box; the gain ratio is taken
//! with the clipped step, so every accepted step lowers the cost.
//!
//! Why our own: the `levenberg-marquardt` crate (a MINPACK port) has no bounds and builds a
//! second nalgebra (0.34 beside our 0.35); a fit's cost is its runs, not this algebra.

use nalgebra::{DMatrix, DVector};

/// When to stop.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Most iterations (Jacobians).
    pub max_iterations: usize,
    /// Stop when a step changes every parameter by at most this times its size (plus this).
    pub x_tolerance: f64,
    /// Stop when an accepted step lowers the cost by at most this fraction of it.
    pub f_tolerance: f64,
    /// Stop when the scaled projected gradient's largest entry is at most this.
    pub g_tolerance: f64,
}

impl Default for Options {
    fn default() -> Self {
        Self { max_iterations: 100, x_tolerance: 1e-10, f_tolerance: 1e-14, g_tolerance: 1e-12 }
    }
}

/// Why the iteration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The step became negligible.
    Step,
    /// The cost stopped falling.
    Cost,
    /// The (projected) gradient vanished.
    Gradient,
    /// `max_iterations` reached: not converged.
    Iterations,
}

impl Stop {
    /// A phrase for the report.
    pub fn says(&self) -> &'static str {
        match self {
            Stop::Step => "converged: the last step changed no parameter beyond 1e-10 of its size",
            Stop::Cost => "converged: the last step lowered the cost by less than 1e-14 of it",
            Stop::Gradient => "converged: the gradient vanished (within the bounds)",
            Stop::Iterations => "NOT converged: the iteration limit was reached",
        }
    }
}

/// The result.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The parameters at the optimum.
    pub x: Vec<f64>,
    /// The residuals there.
    pub residuals: Vec<f64>,
    /// Their Jacobian there (rows: residuals, columns: parameters).
    pub jacobian: DMatrix<f64>,
    /// Iterations made (Jacobians formed).
    pub iterations: usize,
    /// Residual evaluations made (besides those a Jacobian makes).
    pub evaluations: usize,
    /// Why it stopped.
    pub stop: Stop,
}

/// The residuals at a point (an error ends the fit at the start, rejects a trial step later).
pub type ResidualFn<'a, E> = dyn FnMut(&[f64]) -> Result<Vec<f64>, E> + 'a;

/// The residuals' Jacobian at a point where they are the second argument.
pub type JacobianFn<'a, E> = dyn FnMut(&[f64], &[f64]) -> Result<DMatrix<f64>, E> + 'a;

/// Half the sum of squares.
fn cost(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|x| x * x).sum::<f64>()
}

/// Minimises `½ |r(x)|²` from `x0` within `[low, high]` (per parameter; ±∞ for none), with
/// `residuals(x)` and `jacobian(x, r(x))` (an error from either at the start is returned; at a
/// trial point a failed residual is a rejected step, as a point of infinite cost).
pub fn minimize<E>(
    x0: &[f64],
    low: &[f64],
    high: &[f64],
    residuals: &mut ResidualFn<'_, E>,
    jacobian: &mut JacobianFn<'_, E>,
    options: &Options,
) -> Result<Solution, E> {
    let n = x0.len();
    let mut x: Vec<f64> = x0.iter().zip(low.iter().zip(high)).map(|(x, (l, h))| x.clamp(*l, *h)).collect();
    let mut r = residuals(&x)?;
    let mut evaluations = 1;
    let mut f = cost(&r);
    let mut j = jacobian(&x, &r)?;
    let mut iterations = 1;
    // Marquardt's scaling: the largest column norms seen.
    let mut scale = DVector::from_fn(n, |k, _| j.column(k).norm());
    let mut mu = -1.0;
    let mut nu = 2.0;
    loop {
        let rv = DVector::from_column_slice(&r);
        let g = j.transpose() * &rv;
        let a = j.transpose() * &j;
        for k in 0..n {
            scale[k] = scale[k].max(j.column(k).norm());
        }
        // A parameter at a bound whose descent direction (−g) leaves the box is held.
        let held: Vec<bool> =
            (0..n).map(|k| (x[k] <= low[k] && g[k] > 0.0) || (x[k] >= high[k] && g[k] < 0.0)).collect();
        let gmax =
            (0..n).filter(|&k| !held[k]).map(|k| g[k].abs() / scale[k].max(f64::MIN_POSITIVE)).fold(0.0, f64::max);
        if gmax <= options.g_tolerance * (2.0 * f).sqrt().max(f64::MIN_POSITIVE) || f == 0.0 {
            return Ok(Solution { x, residuals: r, jacobian: j, iterations, evaluations, stop: Stop::Gradient });
        }
        if mu < 0.0 {
            mu = 1e-3 * (0..n).map(|k| a[(k, k)] / scale[k].powi(2).max(f64::MIN_POSITIVE)).fold(0.0, f64::max);
        }
        // Inner loop: damped steps until one lowers the cost.
        loop {
            let free: Vec<usize> = (0..n).filter(|&k| !held[k]).collect();
            let m = free.len();
            let mut lhs = DMatrix::from_fn(m, m, |p, q| a[(free[p], free[q])]);
            for p in 0..m {
                lhs[(p, p)] += mu * scale[free[p]].powi(2).max(f64::MIN_POSITIVE);
            }
            let rhs = DVector::from_fn(m, |p, _| -g[free[p]]);
            let Some(step) = lhs.cholesky().map(|c| c.solve(&rhs)) else {
                mu *= nu;
                nu *= 2.0;
                if !mu.is_finite() {
                    return Ok(Solution { x, residuals: r, jacobian: j, iterations, evaluations, stop: Stop::Step });
                }
                continue;
            };
            let mut trial = x.clone();
            for (p, &k) in free.iter().enumerate() {
                trial[k] = (x[k] + step[p]).clamp(low[k], high[k]);
            }
            let s = DVector::from_fn(n, |k, _| trial[k] - x[k]);
            let small = (0..n).all(|k| s[k].abs() <= options.x_tolerance * (x[k].abs() + options.x_tolerance));
            // The model's predicted reduction with the clipped step.
            let predicted = -(g.dot(&s) + 0.5 * s.dot(&(&a * &s)));
            let trial_r = residuals(&trial);
            evaluations += 1;
            let trial_f = trial_r.as_ref().map_or(f64::INFINITY, |r| cost(r));
            let rho = if predicted > 0.0 { (f - trial_f) / predicted } else { -1.0 };
            if rho > 1e-4 && trial_f.is_finite() {
                let drop = f - trial_f;
                x = trial;
                r = trial_r.ok().expect("finite cost");
                f = trial_f;
                mu *= (1.0 / 3.0_f64).max(1.0 - (2.0 * rho - 1.0).powi(3));
                nu = 2.0;
                if small {
                    let j_end = jacobian(&x, &r)?;
                    return Ok(Solution {
                        x,
                        residuals: r,
                        jacobian: j_end,
                        iterations,
                        evaluations,
                        stop: Stop::Step,
                    });
                }
                if drop <= options.f_tolerance * (f + drop) {
                    let j_end = jacobian(&x, &r)?;
                    return Ok(Solution {
                        x,
                        residuals: r,
                        jacobian: j_end,
                        iterations,
                        evaluations,
                        stop: Stop::Cost,
                    });
                }
                break;
            }
            if small {
                return Ok(Solution { x, residuals: r, jacobian: j, iterations, evaluations, stop: Stop::Step });
            }
            mu *= nu;
            nu *= 2.0;
        }
        j = jacobian(&x, &r)?;
        if iterations >= options.max_iterations {
            return Ok(Solution { x, residuals: r, jacobian: j, iterations, evaluations, stop: Stop::Iterations });
        }
        iterations += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Res = Result<Vec<f64>, String>;

    /// Rosenbrock as least squares, r = (10 (x₂ − x₁²), 1 − x₁): the minimum (1, 1) from the
    /// classic start (−1.2, 1), to 1e-9 (the tolerances' 1e-10 times the condition).
    #[test]
    fn rosenbrock_from_the_classic_start() {
        let mut r = |x: &[f64]| -> Res { Ok(vec![10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]]) };
        let mut j = |x: &[f64], _: &[f64]| -> Result<DMatrix<f64>, String> {
            Ok(DMatrix::from_row_slice(2, 2, &[-20.0 * x[0], 10.0, -1.0, 0.0]))
        };
        let inf = f64::INFINITY;
        let s = minimize(&[-1.2, 1.0], &[-inf, -inf], &[inf, inf], &mut r, &mut j, &Options::default()).unwrap();
        assert!((s.x[0] - 1.0).abs() < 1e-9 && (s.x[1] - 1.0).abs() < 1e-9, "{:?} after {:?}", s.x, s.stop);
        assert_ne!(s.stop, Stop::Iterations);
    }

    /// A bound that cuts off the unconstrained minimum: r = (x₁ − 3, x₂ + 1) within x₁ ≤ 2,
    /// x₂ ≥ 0 ends exactly at the corner (2, 0), held there.
    #[test]
    fn bounds_hold_the_optimum_at_the_box() {
        let mut r = |x: &[f64]| -> Res { Ok(vec![x[0] - 3.0, x[1] + 1.0]) };
        let mut j = |_: &[f64], _: &[f64]| -> Result<DMatrix<f64>, String> { Ok(DMatrix::identity(2, 2)) };
        let s = minimize(&[0.5, 0.5], &[-10.0, 0.0], &[2.0, 10.0], &mut r, &mut j, &Options::default()).unwrap();
        assert_eq!(s.x, vec![2.0, 0.0], "{:?}", s.stop);
    }

    /// An exponential decay y = a e^{−b t} fitted to exact data from far off: (a, b) = (2, 0.7)
    /// recovered to 1e-10 (exact data: the residual vanishes at the truth).
    #[test]
    fn exponential_decay_recovered_from_exact_data() {
        let t: Vec<f64> = (0..20).map(|k| 0.25 * k as f64).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.7 * t).exp()).collect();
        let mut r = |x: &[f64]| -> Res { Ok(t.iter().zip(&y).map(|(t, y)| x[0] * (-x[1] * t).exp() - y).collect()) };
        let mut j = |x: &[f64], _: &[f64]| -> Result<DMatrix<f64>, String> {
            Ok(DMatrix::from_fn(t.len(), 2, |i, k| {
                let e = (-x[1] * t[i]).exp();
                if k == 0 { e } else { -x[0] * t[i] * e }
            }))
        };
        let s = minimize(&[0.5, 3.0], &[0.0, 0.0], &[10.0, 10.0], &mut r, &mut j, &Options::default()).unwrap();
        assert!((s.x[0] - 2.0).abs() < 1e-10 && (s.x[1] - 0.7).abs() < 1e-10, "{:?} {:?}", s.x, s.stop);
    }
}

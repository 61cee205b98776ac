//! What the data say about the fitted values: standard errors and correlations from the
//! Jacobian at the optimum and the residual variance (the linearised covariance
//! `s² (JᵀJ)⁻¹`, `s² = |r|² / (m − p)`: Bates & Watts, *Nonlinear Regression Analysis and
//! Its Applications*, 1988, §2.3; what `scipy.optimize.curve_fit` reports by default), and
//! which values they do not determine.

use nalgebra::{DMatrix, DVector};

/// Below this fraction of the largest singular value of the column-scaled Jacobian a
/// direction of the parameters counts as undetermined (the information matrix is then
/// numerically singular: its condition number beyond 1e16 against the differences' ~1e-8).
pub const SINGULAR: f64 = 1e-8;

/// One parameter's statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// The fitted value.
    pub value: f64,
    /// Its standard error (in the parameter's unit); `None` where the data do not determine
    /// it (a zero or singular direction) or it is pinned at a bound.
    pub standard_error: Option<f64>,
    /// Why the value is not to be trusted as a measurement, if so.
    pub warning: Option<String>,
}

/// The statistics of a fit.
#[derive(Clone, Debug)]
pub struct Statistics {
    /// Per parameter.
    pub estimates: Vec<Estimate>,
    /// The correlation matrix of the parameters with a standard error (NaN elsewhere).
    pub correlation: DMatrix<f64>,
    /// The residual variance `s² = |r|² / (m − p)` (weighted residuals; ≈ 1 when the given
    /// σ are the noise's).
    pub variance: f64,
    /// Degrees of freedom, m − p (p the rank of the free parameters' Jacobian: those not pinned
    /// at a bound, less the directions the data do not see).
    pub dof: usize,
    /// The condition number of the column-scaled Jacobian (∞ when singular).
    pub condition: f64,
}

/// The statistics at `x` (within `low`..`high`) of residuals `r` with Jacobian `j`.
pub fn statistics(x: &[f64], low: &[f64], high: &[f64], r: &[f64], j: &DMatrix<f64>) -> Statistics {
    let n = x.len();
    let pinned: Vec<bool> = (0..n).map(|k| x[k] <= low[k] || x[k] >= high[k]).collect();
    let free: Vec<usize> = (0..n).filter(|&k| !pinned[k]).collect();
    let m = r.len();
    let squares = r.iter().map(|v| v * v).sum::<f64>();
    // Until the rank is known (below): every free parameter counted.
    let mut dof = m.saturating_sub(free.len()).max(1);
    let mut variance = squares / dof as f64;
    let norms: Vec<f64> = free.iter().map(|&k| j.column(k).norm()).collect();
    // The Jacobian of the free parameters, columns scaled to unit norm (zero columns kept 0).
    let scaled = DMatrix::from_fn(m, free.len(), |i, p| if norms[p] > 0.0 { j[(i, free[p])] / norms[p] } else { 0.0 });
    let mut estimates: Vec<Estimate> =
        x.iter().map(|&value| Estimate { value, standard_error: None, warning: None }).collect();
    let mut cov = DMatrix::from_element(n, n, f64::NAN);
    let mut condition = f64::INFINITY;
    if !free.is_empty() {
        let svd = scaled.clone().svd(false, true);
        let v_t = svd.v_t.expect("asked for");
        let s = &svd.singular_values;
        let smax = s.max();
        let smin = s.min();
        if smin > 0.0 {
            condition = smax / smin;
        }
        // Directions the data do not see: the parameters with weight in them.
        let null: Vec<DVector<f64>> =
            (0..s.len()).filter(|&i| s[i] <= SINGULAR * smax).map(|i| v_t.row(i).transpose()).collect();
        let in_null = |p: usize| null.iter().any(|v| v[p].abs() > 0.1);
        // The degrees of freedom count the directions the data see (the rank).
        dof = m.saturating_sub(s.len() - null.len()).max(1);
        variance = squares / dof as f64;
        // Pseudo-inverse of the scaled information matrix over the seen directions.
        let mut inv = DMatrix::zeros(free.len(), free.len());
        for i in (0..s.len()).filter(|&i| s[i] > SINGULAR * smax) {
            let v = v_t.row(i).transpose();
            inv += &v * v.transpose() / (s[i] * s[i]);
        }
        for (p, &k) in free.iter().enumerate() {
            if norms[p] == 0.0 || in_null(p) {
                estimates[k].warning = Some(if norms[p] == 0.0 {
                    "not determined: the data do not change with it at all".into()
                } else {
                    "not determined: the data change with it only together with other parameters (a singular information matrix)".into()
                });
                continue;
            }
            for (q, &l) in free.iter().enumerate() {
                if norms[q] > 0.0 && !in_null(q) {
                    cov[(k, l)] = variance * inv[(p, q)] / (norms[p] * norms[q]);
                }
            }
            let se = cov[(k, k)].sqrt();
            estimates[k].standard_error = Some(se);
            if se.is_nan() || se >= x[k].abs() {
                estimates[k].warning = Some(format!(
                    "not determined: its standard error ({se:.3e}) is as large as the value itself; the data hardly depend on it"
                ));
            }
        }
    }
    for k in (0..n).filter(|&k| pinned[k]) {
        let side = if x[k] <= low[k] { "lower" } else { "upper" };
        estimates[k].warning = Some(format!(
            "at its {side} bound: the data push it beyond the range given; no standard error (widen the bound if it may go further)"
        ));
    }
    let correlation = DMatrix::from_fn(n, n, |a, b| {
        if a == b && cov[(a, a)].is_finite() { 1.0 } else { cov[(a, b)] / (cov[(a, a)] * cov[(b, b)]).sqrt() }
    });
    Statistics { estimates, correlation, variance, dof, condition }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line y = a + b t through points with residuals of known spread: the
    /// standard errors are the textbook ones, s √((XᵀX)⁻¹)ₖₖ (to 1e-12), and a third
    /// parameter the residuals do not depend on is flagged, not given an error.
    #[test]
    fn line_errors_and_an_undetermined_parameter() {
        let t: Vec<f64> = (0..10).map(|k| k as f64).collect();
        let r: Vec<f64> = (0..10).map(|k| if k % 2 == 0 { 0.1 } else { -0.1 }).collect();
        let j = DMatrix::from_fn(10, 3, |i, k| match k {
            0 => 1.0,
            1 => t[i],
            _ => 0.0,
        });
        let s = statistics(&[1.0, 2.0, 0.5], &[-9.0; 3], &[9.0; 3], &r, &j);
        let x = j.columns(0, 2).into_owned();
        let inv = (x.transpose() * &x).try_inverse().unwrap();
        let s2 = r.iter().map(|v| v * v).sum::<f64>() / 8.0;
        for k in 0..2 {
            let want = (s2 * inv[(k, k)]).sqrt();
            let got = s.estimates[k].standard_error.unwrap();
            assert!((got - want).abs() <= 1e-12 * want, "{k}: {got} vs {want}");
        }
        assert!(s.estimates[2].standard_error.is_none() && s.estimates[2].warning.is_some());
        let rho = inv[(0, 1)] / (inv[(0, 0)] * inv[(1, 1)]).sqrt();
        assert!((s.correlation[(0, 1)] - rho).abs() < 1e-12);
    }
}

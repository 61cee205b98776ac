//! Anderson acceleration of the implicit methods' simplified Newton iterations.
//!
//! With a Jacobian kept across steps, Newton's iteration `x ← x + W⁻¹(−R(x))` is a fixed-point
//! iteration that converges only linearly once the Jacobian is stale, often by 0.5–0.9 an
//! iteration and oscillating (a rotating error: the structure has turned since the Jacobian
//! was formed), until it runs out of iterations and the step is retaken. Anderson's mixing
//! (D. G. Anderson, "Iterative procedures for nonlinear integral equations", J. ACM 12, 1965;
//! in the form of H. F. Walker & P. Ni, "Anderson acceleration for fixed-point iterations",
//! SIAM J. Numer. Anal. 49, 2011, Type II) takes the next iterate as the combination of the
//! last few that makes the linearised increment least, the secant information the stale
//! Jacobian lacks: `x⁺ = x + f − (ΔX + ΔF) γ`, `γ = argmin ‖f − ΔF γ‖` with `f` the Newton
//! increment at `x` and `ΔX`, `ΔF` the differences of the last iterates and increments. The
//! fixed point, and so the converged stage, is the same: only the way to it changes.
//!
//! The least squares are in the integrator's error weights (so a component counts as the
//! convergence test counts it) and by normal equations of at most [`DEPTH`] unknowns; a
//! history whose equations are ill-conditioned is cut to its newest differences.

use nalgebra::{DMatrix, DVector};

/// Differences kept (Anderson's m). 1, 2, 3 and 5 measured alike on the 228- and 996-panel
/// starshades and the thick flasher example (within the runs' spread).
pub const DEPTH: usize = 3;

/// A Newton iteration is *slow* when its increment shrank by less than this factor: from
/// then on (for the rest of that solve) the iterates are mixed. A Newton iteration with a
/// fresh Jacobian near its solution contracts much faster and is left as it is (mixing
/// from the second iteration on cost the starshade's tight-tolerance runs up to 20 %; from
/// 0.2 the same runs as plain Newton within their spread).
pub const SLOW: f64 = 0.2;

/// One Newton solve's acceleration state; [`Anderson::reset`] before each new solve.
#[derive(Clone, Debug, Default)]
pub struct Anderson {
    /// The last iterate and its increment.
    x_last: Vec<f64>,
    f_last: Vec<f64>,
    has_last: bool,
    /// Differences of iterates and of increments, oldest first.
    dx: Vec<Vec<f64>>,
    df: Vec<Vec<f64>>,
    /// Difference vectors of earlier solves, for reuse (a fresh vector of thousands of
    /// bodies' states costs page faults).
    spare: Vec<Vec<f64>>,
}

impl Anderson {
    /// Forgets the history (a new stage or step, or a new Jacobian).
    pub fn reset(&mut self) {
        self.has_last = false;
        self.spare.append(&mut self.dx);
        self.spare.append(&mut self.df);
    }

    /// Advances `x` (the iterate at which the increment `f = W⁻¹(−R(x))` was formed) to the
    /// next iterate; `w` are the error weights per component (1 / (atol + rtol |y|), rates
    /// scaled as the convergence test scales them).
    pub fn advance(&mut self, x: &mut [f64], f: &[f64], w: &[f64]) {
        let n = x.len();
        if self.has_last {
            let (mut dx, mut df) = if self.dx.len() == DEPTH {
                (self.dx.remove(0), self.df.remove(0))
            } else {
                let mut fresh = || {
                    let mut v = self.spare.pop().unwrap_or_default();
                    v.resize(n, 0.0);
                    v
                };
                (fresh(), fresh())
            };
            for k in 0..n {
                dx[k] = x[k] - self.x_last[k];
                df[k] = f[k] - self.f_last[k];
            }
            self.dx.push(dx);
            self.df.push(df);
        }
        self.x_last.clear();
        self.x_last.extend_from_slice(x);
        self.f_last.clear();
        self.f_last.extend_from_slice(f);
        self.has_last = true;
        let gamma = loop {
            if self.df.is_empty() {
                break Vec::new();
            }
            match self.coefficients(f, w) {
                Some(g) => break g,
                None => {
                    // Ill-conditioned: drop the oldest difference, down to none.
                    self.spare.push(self.dx.remove(0));
                    self.spare.push(self.df.remove(0));
                }
            }
        };
        for k in 0..n {
            let mut step = f[k];
            for (j, g) in gamma.iter().enumerate() {
                step -= g * (self.dx[j][k] + self.df[j][k]);
            }
            x[k] += step;
        }
    }

    /// `γ = argmin ‖diag(w) (f − ΔF γ)‖` by its normal equations, or `None` when they are
    /// too ill-conditioned to trust (the differences nearly dependent).
    fn coefficients(&self, f: &[f64], w: &[f64]) -> Option<Vec<f64>> {
        let m = self.df.len();
        let mut a = DMatrix::<f64>::zeros(m, m);
        let mut b = DVector::<f64>::zeros(m);
        for k in 0..f.len() {
            let w2 = w[k] * w[k];
            for (i, dfi) in self.df.iter().enumerate() {
                let di = dfi[k] * w2;
                b[i] += di * f[k];
                for (j, dfj) in self.df.iter().enumerate().take(i + 1) {
                    a[(i, j)] += di * dfj[k];
                }
            }
        }
        a.fill_upper_triangle_with_lower_triangle();
        // A pivot of the Cholesky factor below 1e-10 of its diagonal means a difference
        // nearly in the span of the others.
        let diagonal = a.diagonal();
        let cholesky = a.cholesky()?;
        let l = cholesky.l_dirty();
        if !(0..m).all(|i| l[(i, i)] * l[(i, i)] > 1e-10 * diagonal[i]) {
            return None;
        }
        let g = cholesky.solve(&b);
        g.iter().all(|x| x.is_finite()).then(|| g.iter().copied().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear fixed-point iteration `x ← x + f`, `f = M (b − x)` with `M` a poor inverse
    /// (plain iteration contracts by 0.9 an iteration, rotating): Anderson's converges in far
    /// fewer iterations, to the same fixed point.
    #[test]
    fn converges_to_the_same_fixed_point_faster() {
        // Error propagation I − M with eigenvalues 0.9 e^{±0.5i} and 0.5.
        let (r, c, s) = (0.9f64, 0.5f64.cos(), 0.5f64.sin());
        let e = [[r * c, -r * s, 0.0], [r * s, r * c, 0.0], [0.0, 0.0, 0.5]];
        let b = [1.0, -2.0, 3.0];
        let increment = |x: &[f64]| -> Vec<f64> {
            // f = (I − E)(b − x).
            (0..3).map(|i| (b[i] - x[i]) - (0..3).map(|j| e[i][j] * (b[j] - x[j])).sum::<f64>()).collect()
        };
        let iterations = |accelerate: bool| {
            let mut x = vec![0.0; 3];
            let mut a = Anderson::default();
            for k in 1..=500 {
                let f = increment(&x);
                if f.iter().map(|v| v.abs()).fold(0.0, f64::max) < 1e-12 {
                    return (k, x);
                }
                if accelerate {
                    a.advance(&mut x, &f, &[1.0; 3]);
                } else {
                    x.iter_mut().zip(&f).for_each(|(x, f)| *x += f);
                }
            }
            (500, x)
        };
        let (plain, x_plain) = iterations(false);
        let (fast, x_fast) = iterations(true);
        for i in 0..3 {
            assert!((x_plain[i] - b[i]).abs() < 1e-10 && (x_fast[i] - b[i]).abs() < 1e-10);
        }
        // A linear problem of dimension 3: Anderson with 3 differences is GMRES-like and
        // ends within a few iterations of the dimension; plain iteration needs ~260.
        assert!(plain > 200, "{plain}");
        assert!(fast <= 8, "{fast}");
    }
}

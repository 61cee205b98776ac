//! A fit's report as text: the values with their standard errors and bounds, the warnings,
//! the correlations, the residuals per column, and what it cost.

use super::{Fit, Fitted};
use std::fmt::Write;

impl Fit {
    /// The report for `problem`.
    pub fn text(&self, problem: &dyn Fitted) -> String {
        let mut s = String::new();
        let st = &self.statistics;
        let free = problem.free();
        let _ = writeln!(s, "fit of {} parameter(s) to {}", free.len(), problem.data_summary());
        let _ = writeln!(
            s,
            "  {} after {} iterations, {} runs, {:.2} s",
            self.solution.stop.says(),
            self.solution.iterations,
            self.runs,
            self.wall_seconds
        );
        let _ = writeln!(
            s,
            "  weighted residual norm {:.6e} at the start, {:.6e} fitted; residual variance s² = {:.4e} ({} degrees of freedom){}",
            self.norm.0,
            self.norm.1,
            st.variance,
            st.dof,
            if self.columns.iter().all(|c| c.sigma.is_some()) {
                " (≈ 1 if the σ given are the noise's)"
            } else {
                ""
            }
        );
        let width = free.iter().map(|f| f.path.len()).max().unwrap_or(0).max(9);
        let _ = writeln!(
            s,
            "  {:width$}  {:>14}  {:>12}  {:>8}  {:>14}  bounds",
            "parameter", "fitted", "std. error", "rel.", "start"
        );
        for (f, e) in free.iter().zip(&st.estimates) {
            let (se, rel) = match e.standard_error {
                Some(se) => (format!("{se:.4e}"), format!("{:.3} %", 100.0 * se / e.value.abs())),
                None => ("–".into(), "–".into()),
            };
            let bound = |b: f64| if b.is_finite() { format!("{b}") } else { String::new() };
            let _ = writeln!(
                s,
                "  {:width$}  {:>14.8e}  {:>12}  {:>8}  {:>14.6e}  {}:{}",
                f.path,
                e.value,
                se,
                rel,
                f.start,
                bound(f.low),
                bound(f.high)
            );
        }
        for (f, e) in free.iter().zip(&st.estimates) {
            if let Some(w) = &e.warning {
                let _ = writeln!(s, "  WARNING {}: {w}", f.path);
            }
        }
        let n = free.len();
        if n > 1 {
            let _ = writeln!(s, "  correlations (condition number of the scaled Jacobian {:.3e}):", st.condition);
            for (a, f) in free.iter().enumerate() {
                let row: Vec<String> = (0..n)
                    .map(|b| {
                        let c = st.correlation[(a, b)];
                        if c.is_finite() { format!("{c:>7.3}") } else { format!("{:>7}", "–") }
                    })
                    .collect();
                let _ = writeln!(s, "    {:width$}  {}", f.path, row.join(" "));
            }
        }
        let _ = writeln!(s, "  residuals (fitted model − data), root mean square per column, in its unit:");
        for (c, (rms, count)) in self.columns.iter().zip(&self.rms) {
            let sigma = c.sigma.map(|v| format!(" (σ given {v:.3e})")).unwrap_or_default();
            let _ = writeln!(s, "    {:16} {rms:.4e} {} over {count} values{sigma}", c.name, c.unit);
        }
        s
    }
}

//! A run's summary metrics: statistics of output columns taken row by row as the run streams
//! them (nothing stored), and times and conservation figures from its report.

use super::spec::{Metric, Statistic};
use crate::model::Model;
use crate::observe::{Observation, catalogue, row};
use crate::simulate::RunReport;

/// The metrics every sweep reports after the requested ones, with their units.
pub const BUILT_IN: [(&str, &str); 6] = [
    ("deployment_time", "s: first time the structure reaches 90 % of its deployed radius (empty if it does not)"),
    ("energy_drift", "J: max |E(t) − E(0)| over the output rows"),
    ("energy_balance", "J: max |(E + D)(t) − (E + D)(0)|, D the energy the hinges dissipated"),
    ("momentum_drift", "kg·m/s: max |P(t) − P(0)|"),
    ("angular_momentum_drift", "kg·m²/s: max |H(t) − H(0)| about the inertial origin"),
    ("steps", "accepted integrator steps"),
];

/// How one metric is found in a run of a given model.
#[derive(Clone, Debug)]
pub(super) enum Resolved {
    Column { index: usize, statistic: Statistic },
    Latch(usize),
    Lock(usize),
}

/// Resolves metric names against `model` (columns by name, hinges by name).
pub(super) fn resolve(metrics: &[(String, Metric)], model: &Model) -> Result<Vec<Resolved>, String> {
    let columns = catalogue(model);
    let hinge = |name: &str, metric: &str| {
        model.hinges.iter().position(|h| h.name == name).ok_or_else(|| {
            let names: Vec<&str> = model.hinges.iter().take(8).map(|h| h.name.as_str()).collect();
            format!("metric '{metric}': no hinge named '{name}' (hinges: {}, …)", names.join(", "))
        })
    };
    metrics
        .iter()
        .map(|(name, m)| match m {
            Metric::Column { column, statistic } => match columns.iter().position(|c| &c.name == column) {
                Some(index) => Ok(Resolved::Column { index, statistic: *statistic }),
                None => Err(format!(
                    "metric '{name}': no output column named '{column}' (columns are named as in the output CSV; docs/outputs.md lists them)"
                )),
            },
            Metric::Latch(h) => hinge(h, name).map(Resolved::Latch),
            Metric::Lock(h) => hinge(h, name).map(Resolved::Lock),
        })
        .collect()
}

/// Column statistics, updated once per output row.
pub(super) struct Tracker<'r> {
    metrics: &'r [Resolved],
    /// Per metric: its value so far (`None`: no row yet, or no crossing yet).
    values: Vec<Option<f64>>,
    /// The previous row's time and the tracked columns' values (for crossings).
    previous: Option<(f64, Vec<f64>)>,
}

impl<'r> Tracker<'r> {
    pub(super) fn new(metrics: &'r [Resolved]) -> Self {
        Self { metrics, values: vec![None; metrics.len()], previous: None }
    }

    pub(super) fn record(&mut self, o: &Observation) {
        let r = row(o);
        let now: Vec<f64> = self
            .metrics
            .iter()
            .map(|m| match m {
                Resolved::Column { index, .. } => r[*index],
                _ => f64::NAN,
            })
            .collect();
        for (k, m) in self.metrics.iter().enumerate() {
            let Resolved::Column { statistic, .. } = m else { continue };
            let x = now[k];
            let v = &mut self.values[k];
            *v = match (*statistic, *v) {
                (Statistic::Final, _) => Some(x),
                (Statistic::Min, Some(m)) => Some(m.min(x)),
                (Statistic::Max, Some(m)) => Some(m.max(x)),
                (Statistic::Min | Statistic::Max, None) => Some(x),
                (Statistic::Crosses { .. }, Some(t)) => Some(t),
                (Statistic::Crosses { value, direction }, None) => match &self.previous {
                    None => (x == value).then_some(o.t),
                    Some((t0, before)) => crossing(*t0, before[k], o.t, x, value, direction),
                },
            };
        }
        self.previous = Some((o.t, now));
    }

    /// The metrics' values: the tracked statistics, and the event times from `report`.
    pub(super) fn finish(self, report: &RunReport) -> Vec<Option<f64>> {
        let mut out = self.values;
        for (k, m) in self.metrics.iter().enumerate() {
            match m {
                Resolved::Latch(h) => {
                    out[k] = report
                        .events
                        .iter()
                        .find(|e| e.hinge == *h && e.kind == crate::law::EventKind::Latch)
                        .map(|e| e.t);
                }
                Resolved::Lock(h) => {
                    out[k] = report.lock_engagements.iter().find(|(l, _)| l.hinge == *h).map(|(_, t)| *t);
                }
                Resolved::Column { .. } => {}
            }
        }
        let d = &report.drift;
        out.extend([
            report.deployed_90,
            Some(d.energy),
            Some(d.energy_balance),
            Some(d.momentum),
            Some(d.angular_momentum),
            Some(report.steps_accepted as f64),
        ]);
        out
    }
}

/// When the segment from (t0, x0) to (t1, x1) reaches `level` (linear between the rows), in
/// `direction` (+1 up, −1 down, 0 either); `None` if it does not. A segment that starts on
/// the level counts only if the previous one did not end there (it was counted then).
fn crossing(t0: f64, x0: f64, t1: f64, x1: f64, level: f64, direction: i8) -> Option<f64> {
    let (a, b) = (x0 - level, x1 - level);
    let rising = a < 0.0 && b >= 0.0;
    let falling = a > 0.0 && b <= 0.0;
    let ok = match direction {
        1 => rising,
        -1 => falling,
        _ => rising || falling,
    };
    ok.then(|| if b == 0.0 { t1 } else { t0 + (t1 - t0) * a / (a - b) })
}

#[cfg(test)]
mod tests {
    use super::crossing;

    #[test]
    fn crossings_interpolate_and_respect_direction() {
        assert_eq!(crossing(1.0, 0.0, 2.0, 2.0, 0.5, 0), Some(1.25));
        assert_eq!(crossing(1.0, 0.0, 2.0, 2.0, 0.5, -1), None);
        assert_eq!(crossing(1.0, 2.0, 2.0, 0.0, 0.5, -1), Some(1.75));
        assert_eq!(crossing(1.0, 2.0, 2.0, 0.5, 0.5, 0), Some(2.0));
        assert_eq!(crossing(1.0, 0.5, 2.0, 2.0, 0.5, 0), None, "counted when the level was reached");
        assert_eq!(crossing(1.0, 0.0, 2.0, 0.4, 0.5, 0), None);
    }
}

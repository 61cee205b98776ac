//! A run made again from its start (a position tolerance's next run), projected against the
//! run before it rather than along its own trend ([`Rerun`]).

/// A run made again from its start at another tolerance (a position tolerance's next run),
/// projected against the run before it: the same motion, whose wall time to each simulated
/// time differs from the run before's by a factor that changes slowly, where its own trend
/// knows nothing of what is to come (a thick flasher's packed start: "about 18.5 h left" at
/// 0.0001 s of a run that took minutes). The projection is the run before's whole wall time
/// times that factor at the simulated time reached.
#[derive(Clone, Debug, Default)]
pub struct Rerun {
    /// The run before: (simulated s, wall s since its start), simulated ascending, and its
    /// whole wall time, s.
    before: Vec<(f64, f64)>,
    before_wall: f64,
    /// This run: its start (wall s) and its points as `before`'s.
    start: f64,
    now: Vec<(f64, f64)>,
}

impl Rerun {
    /// Adds a point of this run: `simulated` s reached at `wall` s (since the watch began).
    pub fn add(&mut self, wall: f64, simulated: f64) {
        let point = (simulated, wall - self.start);
        // Points closer than 1 % of the run's wall time replace the last (as `Trend::add`).
        let n = self.now.len();
        if n > 1 && point.1 - self.now[n - 2].1 < 0.01 * point.1 {
            self.now[n - 1] = point;
        } else {
            self.now.push(point);
        }
    }

    /// The run before ended and a new one begins at `wall` s: the run just made becomes the
    /// one to project against, its wall time counted to `wall`.
    pub fn begin_again(&mut self, wall: f64) {
        self.before = std::mem::take(&mut self.now);
        self.before_wall = wall - self.start;
        self.start = wall;
    }

    /// The wall time left in this run at `wall` s, having reached `simulated` s, projected
    /// against the run before; `None` before anything was simulated or without a run before.
    pub fn left(&self, wall: f64, simulated: f64) -> Option<f64> {
        let &(last_t, _) = self.before.last()?;
        if simulated <= 0.0 || self.before_wall <= 0.0 {
            return None;
        }
        // The run before's wall time at `simulated`, interpolated linearly.
        let at = if simulated >= last_t {
            self.before_wall
        } else {
            let k = self.before.partition_point(|p| p.0 <= simulated);
            let (t0, w0) = if k == 0 { (0.0, 0.0) } else { self.before[k - 1] };
            let (t1, w1) = self.before[k];
            w0 + (w1 - w0) * (simulated - t0) / (t1 - t0).max(f64::MIN_POSITIVE)
        };
        (at > 0.0).then(|| ((wall - self.start) * (self.before_wall / at - 1.0)).max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::estimate::Trend;

    /// A run made again at a tolerance that costs 2.5 times the wall time throughout (a packed
    /// start at 50 times the later pace in both) is projected exactly against the run before
    /// from its first points, where its own trend projects it many times too long.
    #[test]
    fn a_run_made_again_is_projected_against_the_one_before() {
        // Wall time to simulated time t in the first run: 10 s for the first 0.01 s, then
        // 2 s per simulated second, to 1 s: 11.98 s.
        let wall_at = |t: f64| if t <= 0.01 { 1000.0 * t } else { 10.0 + 2.0 * (t - 0.01) };
        let mut rerun = Rerun::default();
        let mut trend = Trend::default();
        for i in 0..=1000 {
            let t = i as f64 * 1e-3;
            rerun.add(wall_at(t), t);
        }
        let first = wall_at(1.0);
        rerun.begin_again(first);
        trend.begin_again(first);
        assert_eq!(rerun.left(first, 0.0), None);
        for i in 1..=5 {
            let t = i as f64 * 1e-3;
            let wall = first + 2.5 * wall_at(t);
            rerun.add(wall, t);
            trend.add(wall, t, Some(i));
            let left = rerun.left(wall, t).unwrap();
            let exact = 2.5 * first - (wall - first);
            assert!((left - exact).abs() < 1e-9 * exact, "{left} vs {exact}");
        }
        let own = trend.projected(1.0) - (first + 2.5 * wall_at(5e-3));
        assert!(own > 20.0 * 2.5 * first, "the trend alone: {own} s left");
        assert_eq!(Rerun::default().left(1.0, 0.5), None, "no run before");
    }
}

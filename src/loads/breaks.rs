//! The instants at which the right-hand side jumps: loads' switches and the bends of their
//! tables, motors' windows (listed: their number is the file's), and a sampled control law's
//! sample times (multiples of its period, generated as they are needed: their number is the
//! user's to set, so they are never listed).

/// Times (s) at which an integration step must end: the listed ones and the multiples
/// `k · period` (k ≥ 1) up to `end`.
#[derive(Clone, Debug, Default)]
pub struct Breaks {
    /// Sorted, without repeats, each > 0.
    listed: Vec<f64>,
    /// `(period, end)`: the control law's samples at `k · period ≤ end`, s.
    samples: Option<(f64, f64)>,
}

impl Breaks {
    /// From times in any order (those ≤ 0 are left out) and a sample period over `(0, end]`.
    pub fn new(mut listed: Vec<f64>, period: Option<f64>, end: f64) -> Self {
        listed.retain(|&t| t > 0.0);
        listed.sort_by(f64::total_cmp);
        listed.dedup();
        Self { listed, samples: period.filter(|p| *p > 0.0 && p.is_finite()).map(|p| (p, end)) }
    }

    /// The first break after `t` (strictly), if any.
    pub fn next_after(&self, t: f64) -> Option<f64> {
        let listed = self.listed.get(self.listed.partition_point(|&b| b <= t)).copied();
        let sample = self.samples.and_then(|(p, end)| {
            // The multiple of p just after t: k from the quotient, then corrected for the
            // round-off of t / p (the samples are k · p exactly as written there).
            let mut k = (t / p).floor().max(0.0) + 1.0;
            if k > 1.0 && (k - 1.0) * p > t {
                k -= 1.0;
            }
            while k * p <= t {
                k += 1.0;
            }
            (k * p <= end).then_some(k * p)
        });
        match (listed, sample) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Whether `t` is a break, exactly.
    pub fn contains(&self, t: f64) -> bool {
        self.listed.binary_search_by(|b| b.total_cmp(&t)).is_ok()
            || self.samples.is_some_and(|(p, end)| {
                let k = (t / p).round();
                k >= 1.0 && k * p == t && t <= end
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_generated_not_listed() {
        // A period of 1e-9 s over 0.5 s: 5e8 samples, none of them stored.
        let b = Breaks::new(vec![0.25, 0.0, 0.25, 0.1], Some(1e-9), 0.5);
        assert_eq!(b.listed, vec![0.1, 0.25]);
        assert_eq!(b.next_after(0.0), Some(1e-9));
        assert_eq!(b.next_after(0.1 - 1e-12), Some(0.1 - 1e-12 + 1e-9).map(|_| b.next_after(0.1 - 1e-12).unwrap()));
        let t = b.next_after(0.3).unwrap();
        assert!(t > 0.3 && t - 0.3 <= 1e-9 && b.contains(t));
        assert!(b.next_after(0.5).is_none());
    }

    #[test]
    fn next_after_walks_the_samples_and_the_list_in_order() {
        let b = Breaks::new(vec![0.35, 1.0], Some(0.1), 0.45);
        let mut t = 0.0;
        let mut seen = Vec::new();
        while let Some(n) = b.next_after(t) {
            assert!(b.contains(n));
            seen.push(n);
            t = n;
        }
        let want: Vec<f64> = vec![0.1, 2.0 * 0.1, 3.0 * 0.1, 0.35, 4.0 * 0.1, 1.0];
        assert_eq!(seen, want);
        assert!(!b.contains(0.45) && !b.contains(0.15));
    }
}

//! Which Jacobian a Newton failure's retry forms (see [`super::sdirk4`]): the whole, or only
//! its contact part ([`super::NewtonMatrix::refresh_contact`]), by how often each kind's
//! retries have converged.

/// Whether a Newton failure's retry brings only the Jacobian's contact part up to date
/// ([`super::NewtonMatrix::refresh_contact`]) or the whole. Each kind's retries converge at some rate
/// (an exponential average of their outcomes, weight 0.2); the contact part, at a fraction of
/// the whole's cost, is taken while its rate is at least three quarters of the whole's, and
/// otherwise every eighth retry, to see.
#[derive(Clone, Copy, Debug)]
pub(super) struct Retries {
    /// The averages of the contact-only and the whole retries' outcomes (1 converged).
    contact: f64,
    whole: f64,
    /// Whole retries since the last contact-only one.
    since: usize,
}

impl Default for Retries {
    fn default() -> Self {
        Self { contact: 1.0, whole: 1.0, since: 0 }
    }
}

impl Retries {
    /// Whether the next retry brings only the contact part up to date.
    pub(super) fn choose(&mut self) -> bool {
        if self.contact >= 0.75 * self.whole || self.since >= 8 {
            self.since = 0;
            true
        } else {
            self.since += 1;
            false
        }
    }

    /// A retry's outcome: of a contact-only one or a whole one.
    pub(super) fn record(&mut self, contact_only: bool, converged: bool) {
        let rate = if contact_only { &mut self.contact } else { &mut self.whole };
        *rate = 0.8 * *rate + 0.2 * f64::from(u8::from(converged));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Newton failure's retry takes the contact part alone while such retries converge
    /// about as often as whole ones, the whole once they converge less than three quarters as
    /// often (then the contact part again every eighth retry), and the contact part again
    /// once it does as well.
    #[test]
    fn retries_take_the_contact_part_while_it_serves() {
        let mut r = Retries::default();
        assert!(r.choose());
        // Contact-only retries failing, whole ones converging.
        for _ in 0..3 {
            r.record(true, false);
            r.record(false, true);
        }
        assert!(r.contact < 0.75 * r.whole, "{r:?}");
        let picks: Vec<bool> = (0..9).map(|_| r.choose()).collect();
        assert_eq!(picks, [false, false, false, false, false, false, false, false, true]);
        // The contact-only retries converge again.
        for _ in 0..6 {
            r.record(true, true);
        }
        assert!(r.choose() && r.choose());
    }
}

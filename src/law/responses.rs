//! The parts a direction of a [`super::directional::DirectionalLaw`] is built from beyond a
//! plain table: a tape spring's two branches and its slip element's force, a response
//! tabulated against two coordinates, and an end stop or latch (docs/hinge-laws.md).

use super::SlipMode;
use super::table::{Outside, Table};

/// Tape-spring response: separate branches for increasing and decreasing coordinate.
#[derive(Clone, Debug, PartialEq)]
pub struct TapeSpring {
    /// Branch while the coordinate increases (loading for a positive fold).
    pub increasing: Table,
    /// Branch while the coordinate decreases (unloading for a positive fold); also the
    /// elastic reference whose integral is the stored energy.
    pub decreasing: Table,
    /// Stiffness of the elastic transition between branches after a reversal, N·m/rad or N/m.
    pub transition_stiffness: f64,
    /// The data points of both branches, merged (kinks of the response, located as events).
    pub knots: Vec<f64>,
}

impl TapeSpring {
    /// A tape spring from its two branches and transition stiffness.
    pub fn new(increasing: Table, decreasing: Table, transition_stiffness: f64) -> Self {
        let mut knots: Vec<f64> = increasing.points().iter().chain(decreasing.points()).copied().collect();
        knots.sort_by(f64::total_cmp);
        knots.dedup();
        Self { increasing, decreasing, transition_stiffness, knots }
    }

    /// Gap between branches `f_inc(u) − f_dec(u)` and its derivative.
    pub(super) fn gap(&self, u: f64) -> (f64, f64) {
        let (fi, dfi) = self.increasing.eval(u);
        let (fd, dfd) = self.decreasing.eval(u);
        (fi - fd, dfi - dfd)
    }

    /// Slip force `s` in a mode.
    pub(super) fn slip(&self, u: f64, mode: SlipMode) -> f64 {
        match mode {
            SlipMode::Decreasing => 0.0,
            SlipMode::Increasing => self.gap(u).0,
            SlipMode::Stick { q_r, s_r } => s_r + self.transition_stiffness * (u - q_r),
        }
    }
}

/// A response tabulated against this direction's coordinate `u` and another's, `v`: one 1-D
/// table in u per grid value of v, interpolated linearly in v.
///
/// Its energy is `V(u, v) = ∫₀ᵘ f(s, v) ds`; unless f does not depend on v, the force is not
/// the gradient of a potential (the other direction feels no `∂V/∂v`), so the law reports the
/// power `−(∂V/∂v) v̇` as dissipation, of either sign, and `E + D` stays constant.
#[derive(Clone, Debug, PartialEq)]
pub struct Table2 {
    /// Index (0..6) of the direction whose coordinate is v.
    pub other: usize,
    /// Grid values of v (minus that direction's rest value), increasing.
    pub v: Vec<f64>,
    /// One table in u per grid value of v.
    pub lines: Vec<Table>,
    /// Outside the v grid: `Clamp` holds the end line, `Extend` continues linearly, `Error`
    /// stops the run at an accepted state beyond it.
    pub outside: Outside,
}

impl Table2 {
    /// Interval index and weight β of v (f = (1 − β) line_j + β line_{j+1}), and whether v
    /// is beyond the grid with the clamp policy (then β is held at the end and V does not
    /// change with v).
    pub(super) fn locate(&self, v: f64) -> (usize, f64, bool) {
        let n = self.v.len();
        let j = match self.v.binary_search_by(|x| x.total_cmp(&v)) {
            Ok(i) => i.min(n - 2),
            Err(i) => i.saturating_sub(1).min(n - 2),
        };
        let beta = (v - self.v[j]) / (self.v[j + 1] - self.v[j]);
        match self.outside {
            Outside::Clamp if !(0.0..=1.0).contains(&beta) => (j, beta.clamp(0.0, 1.0), true),
            _ => (j, beta, false),
        }
    }

    /// Force, energy `V(u, v)` and `∂V/∂v`.
    pub(super) fn eval(&self, u: f64, v: f64) -> (f64, f64, f64) {
        let (j, beta, held) = self.locate(v);
        let (a, b) = (&self.lines[j], &self.lines[j + 1]);
        let f = (1.0 - beta) * a.eval(u).0 + beta * b.eval(u).0;
        let (va, vb) = (a.integral(u), b.integral(u));
        let dv = if held { 0.0 } else { (vb - va) / (self.v[j + 1] - self.v[j]) };
        (f, (1.0 - beta) * va + beta * vb, dv)
    }
}

/// An end stop at `at`: a stiff damped spring that acts while the coordinate is beyond it,
/// and, with `lock`, holds the coordinate at `at` from its first contact on (a latch). With a
/// `band`, two stops: the coordinate is free within `at ± band` and met by the spring beyond
/// either end (a slack membrane that goes taut either way).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    /// Stop position (coordinate, not offset by rest), m or rad; with a band, its middle.
    pub at: f64,
    /// True if the free side is `q ≥ at` (the stop resists going below), false if `q ≤ at`
    /// (without a band).
    pub free_above: bool,
    /// Half-width of the free band about `at` (m or rad), 0 for a one-sided stop.
    pub band: f64,
    /// Contact stiffness, N/m or N·m/rad.
    pub stiffness: f64,
    /// Contact damping, N·s/m or N·m·s/rad.
    pub damping: f64,
    /// Latch: once reached, the stop holds on both sides for the rest of the run.
    pub lock: bool,
}

impl Stop {
    /// How far `q` is beyond the stop: positive where the stop acts (m or rad).
    pub fn beyond(&self, q: f64) -> f64 {
        if self.band > 0.0 {
            (q - self.at).abs() - self.band
        } else if self.free_above {
            self.at - q
        } else {
            q - self.at
        }
    }

    /// The stop spring's extension at `q` (m or rad): `q` less the end it meets (the nearer
    /// end of a band), so that its force `stiffness · extension` pushes back into the free side.
    pub fn extension(&self, q: f64) -> f64 {
        if self.band > 0.0 { q - self.at - self.band.copysign(q - self.at) } else { q - self.at }
    }

    /// The end of the stop that `q` meets or leaves (m or rad): `at`, or for a band the
    /// nearer of `at ± band` (what the event messages name).
    pub fn end_at(&self, q: f64) -> f64 {
        if self.band > 0.0 { self.at + self.band.copysign(q - self.at) } else { self.at }
    }
}

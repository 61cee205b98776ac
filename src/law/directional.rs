//! A hinge law built direction by direction (docs/model.md §4, law 4 and the hinge-law issue):
//! each of the six relative coordinates — δx, δy, δz (A0 components) and three rotation
//! coordinates — has its own response, rest value, damping and optional end stop or latch.
//!
//! Rotation coordinates are either the Euler angles `φ = (roll, pitch, yaw)` of `[A A0]`
//! (directions `rx`, `ry`, `rz` = about axes 1, 2, 3, as in the paper's eq. 15b) or the
//! rotation vector `r` of `[A A0]` (no singularity short of a 180° fold). A response `f_i`
//! is a generalized restoring force on coordinate `q_i`: the generalized force is `−f_i`, so
//! forces are `F = (f_x, f_y, f_z)` and the torque is `B(θ)⁻ᵀ` (Euler) or `J_r(r)⁻ᵀ` (rotation
//! vector) applied to the rotational `f`. Responses that depend only on their own coordinate
//! have a potential, so the law is conservative unless it damps, slips or hits a damped stop.
//!
//! Tape-spring hysteresis is a Prandtl slip element on the decreasing branch: the force is
//! `f_dec(u) + s` with `0 ≤ s ≤ gap(u) = f_inc(u) − f_dec(u)`; `s` sticks (changes
//! elastically with the transition stiffness `k₀`) after a reversal and slides along either
//! branch once it reaches it: on the decreasing branch while u decreases, on the increasing
//! branch while the elastic path would cross it, `(k₀ − gap′(u)) u̇ ≥ 0` (for `gap′ < k₀`:
//! while u increases). The force is continuous, the dissipation `gap (k₀ − gap′) u̇ / k₀` is
//! never negative, and the mode is discrete memory changed by located events.

pub use super::responses::{Stop, Table2, TapeSpring};
use super::table::{Outside, Table, piece, piece_bounds, synced_piece};
use super::{Bounds, DirectionMemory, EventKind, HingeLaw, HingeState, HingeWrench, JacobianDual, LawMemory, SlipMode};
use crate::math::{Real, re, real, rotation_vector, rotation_vector_rate_matrix_inverse};
use nalgebra::{Matrix3, Vector3};

/// Names of the six directions, in order.
pub const DIRECTION_NAMES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// Which rotation coordinates the rotational directions use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Angles {
    /// 3-2-1 Euler angles: rx = roll θ3, ry = pitch θ2, rz = yaw θ1 (singular at pitch ±90°).
    Euler,
    /// Rotation vector of `[A A0]` (axis × angle, |r| ≤ π).
    RotationVector,
}

/// The response of one direction to its coordinate `u = q − rest`.
#[derive(Clone, Debug, PartialEq)]
pub enum Response {
    /// No force.
    Free,
    /// `f = k u`.
    Linear {
        /// Stiffness, N/m or N·m/rad.
        k: f64,
    },
    /// `f = table(u)`.
    Table(Table),
    /// Hysteretic tape spring.
    TapeSpring(TapeSpring),
    /// Held rigid at its initial value by a constraint (no force from the law).
    Locked,
    /// `f = table(u, v)`: coupled to a second direction's coordinate `v` (e.g. fold moment
    /// against fold angle and twist).
    Table2(Table2),
}

/// One direction of a [`DirectionalLaw`].
#[derive(Clone, Debug, PartialEq)]
pub struct Direction {
    /// Response to `u = q − rest`.
    pub response: Response,
    /// Rest value (preload: the coordinate at which the response is zero), m or rad.
    pub rest: f64,
    /// Viscous damping on the coordinate rate, N·s/m or N·m·s/rad.
    pub damping: f64,
    /// Optional end stop or latch.
    pub stop: Option<Stop>,
}

impl Direction {
    /// A free direction: no force.
    pub fn free() -> Self {
        Self { response: Response::Free, rest: 0.0, damping: 0.0, stop: None }
    }

    /// A linear spring about zero.
    pub fn linear(k: f64) -> Self {
        Self { response: Response::Linear { k }, rest: 0.0, damping: 0.0, stop: None }
    }

    /// Restoring force, stored energy (with `energy`; else 0: the tables' integrals are not
    /// needed for the motion) and dissipation power at coordinate q, rate qd; `other` is the
    /// (coordinate − rest, rate) of a coupled direction, if any.
    fn evaluate(&self, q: f64, qd: f64, m: &DirectionMemory, other: (f64, f64), energy: bool) -> (f64, f64, f64) {
        let u = q - self.rest;
        let (mut f, mut v, mut p) = match &self.response {
            Response::Free | Response::Locked => (0.0, 0.0, 0.0),
            Response::Table2(t) => {
                let (f, v, dv) = t.eval(u, other.0);
                (f, v, -dv * other.1)
            }
            Response::Linear { k } => (k * u, 0.5 * k * u * u, 0.0),
            Response::Table(t) => (t.eval(u).0, if energy { t.integral(u) } else { 0.0 }, 0.0),
            Response::TapeSpring(ts) => {
                let s = ts.slip(u, m.slip);
                let k0 = ts.transition_stiffness;
                let f = ts.decreasing.eval(u).0 + s;
                let v = if energy { ts.decreasing.integral(u) + 0.5 * s * s / k0 } else { 0.0 };
                let p = if m.slip == SlipMode::Increasing {
                    let (gap, dgap) = ts.gap(u);
                    gap * (k0 - dgap) * qd / k0
                } else {
                    0.0
                };
                (f, v, p)
            }
        };
        f += self.damping * qd;
        p += self.damping * qd * qd;
        if let Some(stop) = &self.stop
            && (m.in_contact || m.latched)
        {
            let pen = stop.extension(q);
            f += stop.stiffness * pen + stop.damping * qd;
            v += 0.5 * stop.stiffness * pen * pen;
            p += stop.damping * qd * qd;
        }
        (f, v, p)
    }

    /// Derivatives of [`Direction::evaluate`]'s force with the memory held:
    /// `(∂f/∂q, ∂f/∂q̇, ∂f/∂v, ∂f/∂v̇)`, v the coupled direction's coordinate. Exact: the
    /// responses are piecewise smooth and the memory fixes the piece.
    fn slopes(&self, q: f64, m: &DirectionMemory, other: f64) -> [f64; 4] {
        let u = q - self.rest;
        let mut d = match &self.response {
            Response::Free | Response::Locked => [0.0; 4],
            Response::Linear { k } => [*k, 0.0, 0.0, 0.0],
            Response::Table(t) => [t.eval(u).1, 0.0, 0.0, 0.0],
            Response::Table2(t) => {
                let (j, beta, held) = t.locate(other);
                let ((fa, da), (fb, db)) = (t.lines[j].eval(u), t.lines[j + 1].eval(u));
                let df_dv = if held { 0.0 } else { (fb - fa) / (t.v[j + 1] - t.v[j]) };
                [(1.0 - beta) * da + beta * db, 0.0, df_dv, 0.0]
            }
            Response::TapeSpring(ts) => {
                let slope = match m.slip {
                    SlipMode::Decreasing => ts.decreasing.eval(u).1,
                    SlipMode::Increasing => ts.increasing.eval(u).1,
                    SlipMode::Stick { .. } => ts.decreasing.eval(u).1 + ts.transition_stiffness,
                };
                [slope, 0.0, 0.0, 0.0]
            }
        };
        d[1] += self.damping;
        if let Some(stop) = &self.stop
            && (m.in_contact || m.latched)
        {
            d[0] += stop.stiffness;
            d[1] += stop.damping;
        }
        d
    }

    /// Upper bounds on this direction's stiffness and damping over every state and memory.
    fn bounds(&self) -> Bounds {
        let stiffness = match &self.response {
            Response::Free | Response::Locked => 0.0,
            Response::Linear { k } => k.abs(),
            Response::Table(t) => t.max_slope(),
            Response::Table2(t) => t.lines.iter().map(Table::max_slope).fold(0.0, f64::max),
            Response::TapeSpring(ts) => {
                ts.increasing.max_slope().max(ts.decreasing.max_slope() + ts.transition_stiffness.abs())
            }
        };
        let stop = self.stop.map(|s| (s.stiffness.abs(), s.damping.abs())).unwrap_or_default();
        Bounds { stiffness: stiffness + stop.0, damping: self.damping.abs() + stop.1 }
    }

    fn conservative(&self) -> bool {
        self.damping == 0.0
            && !matches!(self.response, Response::TapeSpring(_) | Response::Table2(_))
            && self.stop.is_none_or(|s| s.damping == 0.0)
    }

    fn has_events(&self) -> bool {
        matches!(self.response, Response::TapeSpring(_) | Response::Table(_) | Response::Table2(_))
            || self.stop.is_some()
    }
}

/// A law given direction by direction (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalLaw {
    /// Rotation coordinates.
    pub angles: Angles,
    /// x, y, z, rx, ry, rz.
    pub directions: [Direction; 6],
}

/// Event slots per direction: 0–1 the slip element or a table's data points in u, 2 the
/// stop, 3–4 a 2-D table's grid lines in v or a tape spring's data points.
const SLOTS: usize = 5;

impl DirectionalLaw {
    /// Coordinates and rates `(q, q̇)` of the six directions, and for rotation vectors the
    /// matrix `J_r(r)⁻¹`.
    fn coordinates<T: Real>(&self, s: &HingeState<T>) -> ([T; 6], [T; 6], Option<Matrix3<T>>) {
        let d = s.delta_in_a0;
        let dd = s.delta_rate_in_a0;
        match self.angles {
            Angles::Euler => {
                let phi = s.theta.phi();
                let rate = s.trig.rates_from_omega(&s.omega_rel_in_a);
                ([d.x, d.y, d.z, phi.x, phi.y, phi.z], [dd.x, dd.y, dd.z, rate.z, rate.y, rate.x], None)
            }
            Angles::RotationVector => {
                let r = rotation_vector(&s.dcm_a_a0);
                let j_inv = rotation_vector_rate_matrix_inverse(&r);
                let rate = j_inv * s.omega_rel_in_a;
                ([d.x, d.y, d.z, r.x, r.y, r.z], [dd.x, dd.y, dd.z, rate.x, rate.y, rate.z], Some(j_inv))
            }
        }
    }

    /// The wrench of generalized forces `f` on the six coordinates: `F = (f_x, f_y, f_z)`,
    /// `τ = B(θ)⁻ᵀ` or `J_r(r)⁻ᵀ` applied to the rotational ones.
    fn wrench_of<T: Real>(s: &HingeState<T>, f: &[T; 6], j_inv: Option<Matrix3<T>>) -> HingeWrench<T> {
        let torque_in_a = match j_inv {
            None => s.trig.torque_from_generalized(&Vector3::new(f[5], f[4], f[3])),
            Some(j_inv) => j_inv.transpose() * Vector3::new(f[3], f[4], f[5]),
        };
        HingeWrench { force_in_a0: Vector3::new(f[0], f[1], f[2]), torque_in_a }
    }

    fn any_events(&self) -> bool {
        self.directions.iter().any(Direction::has_events)
    }

    /// Sets the bookkeeping pieces of direction i (at u = q − rest) from the coordinates;
    /// with `sync`, bringing those the memory holds up to date (see [`synced_piece`]).
    fn set_pieces(&self, i: usize, u: f64, q: &[f64; 6], m: &mut DirectionMemory, sync: bool) {
        let at =
            |knots: &[f64], current: i64, x: f64| if sync { synced_piece(knots, current, x) } else { piece(knots, x) };
        match &self.directions[i].response {
            Response::Table(t) => m.piece = at(t.points(), m.piece, u),
            Response::Table2(t2) => {
                m.piece = at(t2.lines[0].points(), m.piece, u);
                m.piece_2 = at(&t2.v, m.piece_2, q[t2.other] - self.directions[t2.other].rest);
            }
            Response::TapeSpring(ts) => m.piece_2 = at(&ts.knots, m.piece_2, u),
            _ => {}
        }
    }

    /// Direction i's force, energy (with `energy`, else 0) and dissipation power.
    fn evaluate(&self, i: usize, q: &[f64; 6], qd: &[f64; 6], memory: &LawMemory, energy: bool) -> (f64, f64, f64) {
        let d = &self.directions[i];
        let other = match &d.response {
            Response::Table2(t) => (q[t.other] - self.directions[t.other].rest, qd[t.other]),
            _ => (0.0, 0.0),
        };
        d.evaluate(q[i], qd[i], &memory.directions[i], other, energy)
    }
}

impl HingeLaw for DirectionalLaw {
    fn wrench(&self, state: &HingeState, memory: &LawMemory) -> HingeWrench {
        self.wrench_and_dissipation(state, memory).0
    }

    fn wrench_and_dissipation(&self, state: &HingeState, memory: &LawMemory) -> (HingeWrench, f64) {
        let (q, qd, j_inv) = self.coordinates(state);
        let mut f = [0.0; 6];
        let mut p = 0.0;
        for (i, fi) in f.iter_mut().enumerate() {
            let (force, _, power) = self.evaluate(i, &q, &qd, memory, false);
            *fi = force;
            p += power;
        }
        (Self::wrench_of(state, &f, j_inv), p)
    }

    /// Each direction's force as its value at the state's real part plus its exact slopes
    /// (`Direction::slopes`) times the coordinates' dual parts: the chain rule, with the
    /// memory (branch, contact) held as the Jacobian requires.
    fn wrench_dual(&self, state: &HingeState<JacobianDual>, memory: &LawMemory) -> Option<HingeWrench<JacobianDual>> {
        let (q, qd, j_inv) = self.coordinates(state);
        let (q0, qd0) = (q.map(re), qd.map(re));
        let mut f = [JacobianDual::from_re(0.0); 6];
        for (i, fi) in f.iter_mut().enumerate() {
            let d = &self.directions[i];
            let o = match &d.response {
                Response::Table2(t) => Some(t.other),
                _ => None,
            };
            let other = o.map_or(0.0, |o| q0[o] - self.directions[o].rest);
            let (force, _, _) = self.evaluate(i, &q0, &qd0, memory, false);
            let [dq, dqd, dv, dvd] = d.slopes(q0[i], &memory.directions[i], other);
            let mut v = real::<JacobianDual>(force) + (q[i] - q0[i]) * dq + (qd[i] - qd0[i]) * dqd;
            if let Some(o) = o {
                v += (q[o] - q0[o]) * dv + (qd[o] - qd0[o]) * dvd;
            }
            *fi = v;
        }
        Some(Self::wrench_of(state, &f, j_inv))
    }

    fn stored_energy(&self, state: &HingeState, memory: &LawMemory) -> f64 {
        let (q, qd, _) = self.coordinates(state);
        (0..6).map(|i| self.evaluate(i, &q, &qd, memory, true).1).sum()
    }

    fn dissipation_power(&self, state: &HingeState, memory: &LawMemory) -> f64 {
        let (q, qd, _) = self.coordinates(state);
        (0..6).map(|i| self.evaluate(i, &q, &qd, memory, false).2).sum()
    }

    fn conserves_energy(&self) -> bool {
        self.directions.iter().all(Direction::conservative)
    }

    fn uses_euler_angles(&self) -> bool {
        self.angles == Angles::Euler
    }

    fn name(&self) -> &'static str {
        "directional"
    }

    fn initial_memory(&self, state: &HingeState) -> LawMemory {
        let (q, qd, _) = self.coordinates(state);
        let mut m = LawMemory::default();
        for (i, d) in self.directions.iter().enumerate() {
            let u = q[i] - d.rest;
            self.set_pieces(i, u, &q, &mut m.directions[i], false);
            if let Response::TapeSpring(ts) = &d.response {
                // Moving: the branch of the motion. At rest: the branch it is about to take
                // under its own restoring force.
                m.directions[i].slip = if qd[i] > 0.0 || (qd[i] == 0.0 && ts.decreasing.eval(u).0 < 0.0) {
                    SlipMode::Increasing
                } else {
                    SlipMode::Decreasing
                };
            }
            if let Some(stop) = &d.stop {
                let pen = stop.beyond(q[i]);
                m.directions[i].in_contact = pen > 0.0;
                m.directions[i].latched = pen > 0.0 && stop.lock;
            }
        }
        m
    }

    fn event_count(&self) -> usize {
        if self.any_events() { 6 * SLOTS } else { 0 }
    }

    fn event_values(&self, state: &HingeState, memory: &LawMemory, out: &mut [f64]) {
        let (q, qd, _) = self.coordinates(state);
        for (i, d) in self.directions.iter().enumerate() {
            let m = &memory.directions[i];
            let slots = &mut out[SLOTS * i..SLOTS * (i + 1)];
            slots.fill(1.0);
            let u = q[i] - d.rest;
            let bounds = |(lo, hi): (f64, f64), x: f64| {
                (if lo.is_finite() { x - lo } else { 1.0 }, if hi.is_finite() { hi - x } else { 1.0 })
            };
            match &d.response {
                Response::Table(t) => (slots[0], slots[1]) = bounds(t.piece_bounds(m.piece), u),
                Response::Table2(t2) => {
                    (slots[0], slots[1]) = bounds(t2.lines[0].piece_bounds(m.piece), u);
                    let v = q[t2.other] - self.directions[t2.other].rest;
                    (slots[3], slots[4]) = bounds(piece_bounds(&t2.v, m.piece_2), v);
                }
                Response::TapeSpring(ts) => (slots[3], slots[4]) = bounds(piece_bounds(&ts.knots, m.piece_2), u),
                _ => {}
            }
            if let Response::TapeSpring(ts) = &d.response {
                match m.slip {
                    // Pinned at the increasing branch while the elastic path would not
                    // pull below it: (k₀ − gap′) q̇ ≥ 0 (for gap′ < k₀ simply q̇ ≥ 0).
                    SlipMode::Increasing => slots[0] = (ts.transition_stiffness - ts.gap(u).1) * qd[i],
                    SlipMode::Decreasing => slots[0] = -qd[i],
                    SlipMode::Stick { .. } => {
                        let s = ts.slip(u, m.slip);
                        slots[0] = s;
                        slots[1] = ts.gap(u).0 - s;
                    }
                }
            }
            if let Some(stop) = &d.stop
                && !m.latched
            {
                let beyond = stop.beyond(q[i]);
                slots[2] = if m.in_contact { beyond } else { -beyond };
            }
        }
    }

    fn bookkeeping_event(&self, k: usize) -> bool {
        let (i, slot) = (k / SLOTS, k % SLOTS);
        matches!(
            (&self.directions[i].response, slot),
            (Response::Table(_) | Response::Table2(_), 0 | 1) | (Response::Table2(_) | Response::TapeSpring(_), 3 | 4)
        )
    }

    fn slip_event(&self, k: usize) -> bool {
        let (i, slot) = (k / SLOTS, k % SLOTS);
        matches!((&self.directions[i].response, slot), (Response::TapeSpring(_), 0 | 1))
    }

    fn apply_event(&self, k: usize, state: &HingeState, memory: &mut LawMemory) -> (EventKind, String) {
        let (q, _, _) = self.coordinates(state);
        let (i, slot) = (k / SLOTS, k % SLOTS);
        let d = &self.directions[i];
        let m = &mut memory.directions[i];
        let name = DIRECTION_NAMES[i];
        let u = q[i] - d.rest;
        match (slot, &d.response, m.slip) {
            (0, Response::TapeSpring(ts), SlipMode::Increasing) => {
                m.slip = SlipMode::Stick { q_r: u, s_r: ts.gap(u).0 };
                (EventKind::Branch, format!("{name}: reversal at {:.6} (increasing → elastic)", q[i]))
            }
            (0, Response::TapeSpring(_), SlipMode::Decreasing) => {
                m.slip = SlipMode::Stick { q_r: u, s_r: 0.0 };
                (EventKind::Branch, format!("{name}: reversal at {:.6} (decreasing → elastic)", q[i]))
            }
            (0, Response::TapeSpring(_), SlipMode::Stick { .. }) => {
                m.slip = SlipMode::Decreasing;
                (EventKind::Branch, format!("{name}: slides on the decreasing branch at {:.6}", q[i]))
            }
            (1, Response::TapeSpring(_), SlipMode::Stick { .. }) => {
                m.slip = SlipMode::Increasing;
                (EventKind::Branch, format!("{name}: slides on the increasing branch at {:.6}", q[i]))
            }
            (0, Response::Table(_) | Response::Table2(_), _) => {
                m.piece -= 1;
                (EventKind::Branch, format!("{name}: crosses a table point downward at {:.6}", q[i]))
            }
            (1, Response::Table(_) | Response::Table2(_), _) => {
                m.piece += 1;
                (EventKind::Branch, format!("{name}: crosses a table point upward at {:.6}", q[i]))
            }
            (3, _, _) => {
                m.piece_2 -= 1;
                (EventKind::Branch, format!("{name}: crosses a table grid line downward"))
            }
            (4, _, _) => {
                m.piece_2 += 1;
                (EventKind::Branch, format!("{name}: crosses a table grid line upward"))
            }
            (2, _, _) => {
                let stop = d.stop.as_ref().expect("stop events come from a stop");
                if m.in_contact {
                    m.in_contact = false;
                    (EventKind::Separation, format!("{name}: leaves the stop at {:.6}", q[i]))
                } else {
                    m.in_contact = true;
                    if stop.lock {
                        m.latched = true;
                        (EventKind::Latch, format!("{name}: latched at {:.6}", stop.end_at(q[i])))
                    } else {
                        (EventKind::Contact, format!("{name}: hits the stop at {:.6}", stop.end_at(q[i])))
                    }
                }
            }
            _ => (EventKind::Branch, String::new()),
        }
    }

    fn stiffness_bounds(&self) -> [Bounds; 6] {
        std::array::from_fn(|i| self.directions[i].bounds())
    }

    fn locked_directions(&self) -> [bool; 6] {
        std::array::from_fn(|i| self.directions[i].response == Response::Locked)
    }

    fn sync_memory(&self, state: &HingeState, memory: &mut LawMemory) {
        let (q, _, _) = self.coordinates(state);
        for (i, d) in self.directions.iter().enumerate() {
            self.set_pieces(i, q[i] - d.rest, &q, &mut memory.directions[i], true);
        }
    }

    fn check(&self, state: &HingeState, _memory: &LawMemory) -> Result<(), String> {
        if self.angles == Angles::RotationVector {
            super::check_rotation_vector(state)?;
        }
        let (q, _, _) = self.coordinates(state);
        for (i, d) in self.directions.iter().enumerate() {
            let u = q[i] - d.rest;
            if let Response::Table2(t2) = &d.response {
                let v = q[t2.other] - self.directions[t2.other].rest;
                let (a, b) = (t2.v[0], t2.v[t2.v.len() - 1]);
                if t2.outside == Outside::Error && !(a..=b).contains(&v) {
                    return Err(format!(
                        "direction {}: coupled coordinate {} − rest = {v:.6} is outside the table's range [{a}, {b}] (outside = \"error\")",
                        DIRECTION_NAMES[i], DIRECTION_NAMES[t2.other]
                    ));
                }
            }
            let tables: Vec<&Table> = match &d.response {
                Response::Table(t) => vec![t],
                Response::TapeSpring(ts) => vec![&ts.increasing, &ts.decreasing],
                Response::Table2(t2) => t2.lines.iter().collect(),
                _ => vec![],
            };
            for t in tables {
                if t.outside() == Outside::Error && !t.contains(u) {
                    let (a, b) = t.range();
                    return Err(format!(
                        "direction {}: coordinate − rest = {u:.6} is outside the table's range [{a}, {b}] (outside = \"error\")",
                        DIRECTION_NAMES[i]
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::table::Interpolation;
    use super::*;
    use crate::math::{Euler321, Vec3};

    fn tape() -> TapeSpring {
        let inc = [(-0.1, -2.0), (0.0, 0.0), (0.02, 8.0), (0.1, 0.8), (3.0, 0.9)];
        let dec = [(-0.1, -3.0), (0.0, 0.0), (0.02, 0.3), (0.1, 0.3), (3.0, 0.4)];
        TapeSpring::new(
            Table::new(&inc, Interpolation::Pchip, Outside::Extend).unwrap(),
            Table::new(&dec, Interpolation::Pchip, Outside::Extend).unwrap(),
            500.0,
        )
    }

    /// A located crossing of a data point moves the memory's piece once. The run resyncs
    /// the bookkeeping at the accepted state and then applies the event; the state sits on
    /// the knot to within the retaken step's local error, past it or a hair short, and in
    /// neither case may the resync and the event together move the piece twice (which the
    /// next step undid at once with a spurious opposite crossing: a quarter of the z-fold
    /// example's events). Afterwards no event function is below round-off.
    #[test]
    fn crossing_a_knot_moves_the_piece_once() {
        let mut dirs: [Direction; 6] = std::array::from_fn(|_| Direction::linear(100.0));
        dirs[5] = Direction { response: Response::TapeSpring(tape()), rest: 0.0, damping: 0.0, stop: None };
        let table =
            Table::new(&[(-1.0, -5.0), (0.0, 0.0), (0.3, 1.0), (1.0, 3.0)], Interpolation::Linear, Outside::Clamp)
                .unwrap();
        dirs[3] = Direction { response: Response::Table(table), rest: 0.0, damping: 0.0, stop: None };
        let law = DirectionalLaw { angles: Angles::Euler, directions: dirs };
        // rz crosses the tape spring's knot at 0.02 upward, rx the table's point at 0.3.
        let at = |rz: f64, rx: f64| HingeState::at(Vec3::zeros(), Euler321::new(rz, 0.0, rx));
        for (direction, knot) in [(5, 0.02), (3, 0.3)] {
            for offset in [1e-12, -1e-12] {
                let u = |d: f64| if direction == 5 { at(knot + d, 0.1) } else { at(0.01, knot + d) };
                let mut m = law.initial_memory(&u(-1e-3));
                let before = (m.directions[direction].piece, m.directions[direction].piece_2);
                let state = u(offset);
                law.sync_memory(&state, &mut m);
                let upward = if direction == 5 { SLOTS * direction + 4 } else { SLOTS * direction + 1 };
                law.apply_event(upward, &state, &mut m);
                let after = (m.directions[direction].piece, m.directions[direction].piece_2);
                let moved = if direction == 5 { after.1 - before.1 } else { after.0 - before.0 };
                assert_eq!(moved, 1, "direction {direction}, {offset:e} past the knot");
                let mut g = vec![0.0; law.event_count()];
                law.event_values(&state, &m, &mut g);
                let lowest = g.iter().fold(f64::INFINITY, |a, &b| a.min(b));
                assert!(lowest >= -1e-9, "direction {direction}, {offset:e}: an event function at {lowest:e}");
            }
        }
    }

    /// A band stop's events name the end that is met or left (the band's middle, `at`, is no
    /// place the coordinate reaches there: the 6 × 3 thick flasher's membranes printed "hits
    /// the stop at 0.000000" and "leaves the stop at -0.050000" for one end).
    #[test]
    fn band_stop_events_name_the_end_met() {
        let band = Stop { at: 0.01, free_above: true, band: 0.05, stiffness: 1e4, damping: 3.0, lock: false };
        let mut dirs: [Direction; 6] = std::array::from_fn(|_| Direction::linear(100.0));
        dirs[1] = Direction { stop: Some(band), ..Direction::linear(100.0) };
        let law = DirectionalLaw { angles: Angles::Euler, directions: dirs };
        for (y, end) in [(-0.04, "-0.040000"), (0.06, "0.060000")] {
            let state = HingeState::at(Vec3::new(0.0, y, 0.0), Euler321::default());
            let mut m = law.initial_memory(&HingeState::at(Vec3::zeros(), Euler321::default()));
            let (kind, hit) = law.apply_event(SLOTS + 2, &state, &mut m);
            assert!(matches!(kind, EventKind::Contact) && hit == format!("y: hits the stop at {end}"), "{hit}");
            let (_, left) = law.apply_event(SLOTS + 2, &state, &mut m);
            assert_eq!(left, format!("y: leaves the stop at {end}"));
        }
    }

    /// Along any path and in every mode, the law's power balance holds:
    /// f·q̇ = dV/dt + P_dissipated, checked by a central difference along a path (1e-6).
    #[test]
    fn power_balance_in_every_mode() {
        let mut dirs: [Direction; 6] = std::array::from_fn(|_| Direction::linear(100.0));
        dirs[5] = Direction {
            response: Response::TapeSpring(tape()),
            rest: 0.1,
            damping: 0.05,
            stop: Some(Stop { at: 0.1, free_above: true, band: 0.0, stiffness: 1e3, damping: 2.0, lock: false }),
        };
        dirs[3] = Direction {
            response: Response::Table(
                Table::new(&[(-1.0, -5.0), (0.0, 0.0), (1.0, 3.0)], Interpolation::Linear, Outside::Clamp).unwrap(),
            ),
            rest: 0.0,
            damping: 0.0,
            stop: None,
        };
        let line = |scale: f64| {
            Table::new(
                &[(-2.0, -3.0 * scale), (0.0, 0.0), (0.5, 1.0 * scale), (2.0, 2.5 * scale)],
                Interpolation::Pchip,
                Outside::Extend,
            )
            .unwrap()
        };
        dirs[4] = Direction {
            response: Response::Table2(Table2 {
                other: 3,
                v: vec![-1.0, 0.0, 0.7],
                lines: vec![line(0.5), line(1.0), line(2.0)],
                outside: Outside::Extend,
            }),
            rest: 0.05,
            damping: 0.0,
            stop: None,
        };
        // x: a band stop (free within ±0.005 m), met beyond its upper end along the path; y: the
        // same band met beyond its lower end.
        let band = Stop { at: 0.0, free_above: true, band: 0.005, stiffness: 1e4, damping: 3.0, lock: false };
        dirs[0] = Direction { stop: Some(band), damping: 0.2, ..Direction::linear(100.0) };
        dirs[1] = Direction { stop: Some(Stop { at: -0.01, ..band }), ..Direction::linear(100.0) };
        for angles in [Angles::Euler, Angles::RotationVector] {
            let law = DirectionalLaw { angles, directions: dirs.clone() };
            let mut g = vec![0.0; law.event_count()];
            for (x, inside) in [(0.0, true), (0.0049, true), (0.0051, false), (-0.0051, false)] {
                let state = HingeState::at(Vec3::new(x, 0.0, 0.0), Euler321::default());
                let m = law.initial_memory(&state);
                assert_eq!(m.directions[0].in_contact, !inside, "x = {x}");
                law.event_values(&state, &m, &mut g);
                assert!((g[2] - (0.005 - x.abs()).abs()).abs() < 1e-15, "x = {x}: {}", g[2]);
            }
            for slip in [SlipMode::Decreasing, SlipMode::Increasing, SlipMode::Stick { q_r: 0.5, s_r: 0.2 }] {
                let mut m = LawMemory::default();
                m.directions[5].slip = slip;
                m.directions[5].in_contact = true;
                m.directions[0].in_contact = true;
                m.directions[1].in_contact = true;
                // A path: angles and δ moving with constant rates.
                let omega = Vec3::new(0.2, -0.3, 0.7);
                let path = |t: f64| {
                    let theta = Euler321::new(0.4 + 0.7 * t, 0.1 - 0.3 * t, -0.2 + 0.2 * t);
                    let delta = Vec3::new(0.01, -0.02, 0.005) + Vec3::new(0.1, 0.2, -0.1) * t;
                    let mut s = HingeState::at(delta, theta);
                    s.delta_rate_in_a0 = Vec3::new(0.1, 0.2, -0.1);
                    s.omega_rel_in_a = theta.rate_matrix() * Vec3::new(0.7, -0.3, 0.2);
                    s
                };
                let _ = omega;
                let s0 = path(0.0);
                let h = 1e-6;
                let dv = (law.stored_energy(&path(h), &m) - law.stored_energy(&path(-h), &m)) / (2.0 * h);
                let w = law.wrench(&s0, &m);
                let power = w.force_in_a0.dot(&s0.delta_rate_in_a0) + w.torque_in_a.dot(&s0.omega_rel_in_a);
                let p = law.dissipation_power(&s0, &m);
                assert!((power - dv - p).abs() < 1e-6 * power.abs().max(1.0), "{angles:?} {slip:?}: {power} {dv} {p}");
            }
        }
    }
}

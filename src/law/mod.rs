//! Hinge laws (docs/model.md §4): the map from a hinge's relative state to its force and torque.
//!
//! Every law implements [`HingeLaw`]. The engine applies the returned force and torque as the
//! wrench pair of docs/architecture.md, which is the generalized force of docs/model.md §4 (paper eq. 14):
//! a torque `τ` (A components) does virtual work `−τ · δω_rel`, so a law that wants the
//! generalized force `g` on the Euler angles returns `τ = B(θ)⁻ᵀ g`.
//!
//! Laws may keep discrete memory across steps ([`LawMemory`]: a hysteresis branch, a latch)
//! and declare event functions whose zero crossings the simulator locates in time; between
//! events the response is smooth.

pub mod directional;
pub mod responses;
pub mod table;

use crate::math::{
    Euler321, EulerTrig, Mat3, Real, Vec3, const_mat_vec, rotation_vector, rotation_vector_rate_matrix_inverse,
};
use nalgebra::{Matrix3, Vector3};
use std::fmt::Debug;

/// The dual numbers the implicit path differentiates a hinge with: derivatives with respect
/// to one body's 13 state numbers (see [`crate::state`]); the Jacobian evaluates a hinge
/// once for its parent's and once for its child's (`crate::dynamics::jacobian`).
pub type JacobianDual = num_dual::DualSVec64<13>;

/// Relative state of one hinge (docs/model.md §2), in f64 or, for the Jacobian, dual numbers.
#[derive(Clone, Copy, Debug)]
pub struct HingeState<T: nalgebra::Scalar = f64> {
    /// `δ = ᴬ⁰(R_A − R_A0)`: A's origin relative to A0's origin, A0 components, m.
    pub delta_in_a0: Vector3<T>,
    /// Time derivative of the A0 components of δ, m/s.
    pub delta_rate_in_a0: Vector3<T>,
    /// 3-2-1 angles of `[A A0]`, tracked continuously (docs/model.md §7), rad.
    pub theta: Euler321<T>,
    /// `[A A0]`.
    pub dcm_a_a0: Matrix3<T>,
    /// `ω_{A/A0}` in A components, rad/s.
    pub omega_rel_in_a: Vector3<T>,
    /// Sines and cosines of θ's pitch and roll (what `B(θ)` needs), from `[A A0]`.
    pub trig: EulerTrig<T>,
}

impl Default for HingeState {
    fn default() -> Self {
        Self {
            delta_in_a0: Vec3::zeros(),
            delta_rate_in_a0: Vec3::zeros(),
            theta: Euler321::default(),
            dcm_a_a0: Mat3::identity(),
            omega_rel_in_a: Vec3::zeros(),
            trig: EulerTrig::default(),
        }
    }
}

impl HingeState {
    /// A state at rest with the given displacement and angles (for tests and tools).
    pub fn at(delta_in_a0: Vec3, theta: Euler321) -> Self {
        Self { delta_in_a0, theta, dcm_a_a0: theta.to_dcm(), trig: theta.trig(), ..Default::default() }
    }
}

/// Force and torque a hinge law returns (docs/model.md §4).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HingeWrench<T: nalgebra::Scalar = f64> {
    /// Restoring force `F`, A0 components, N. The child receives `−F` at A's origin, the
    /// parent `+F` at the same point.
    pub force_in_a0: Vector3<T>,
    /// Restoring torque `τ`, A components, N·m. The child receives `−τ`, the parent `+τ`.
    pub torque_in_a: Vector3<T>,
}

/// Mode of a hysteretic (tape-spring) direction: a Prandtl slip element on top of the
/// decreasing branch (see [`directional`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum SlipMode {
    /// Sliding along the branch for a decreasing coordinate.
    #[default]
    Decreasing,
    /// Sliding along the branch for an increasing coordinate.
    Increasing,
    /// Between branches after a reversal at `q_r` with slip force `s_r`: elastic.
    Stick {
        /// Coordinate at the reversal (m or rad).
        q_r: f64,
        /// Slip force at the reversal (N or N·m).
        s_r: f64,
    },
}

/// What kind of change a law event made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventKind {
    /// A hysteresis branch change (reversal, or reaching a branch).
    Branch,
    /// An end stop came into contact.
    Contact,
    /// An end stop released.
    Separation,
    /// A latch engaged and holds from now on.
    Latch,
}

/// Discrete memory of one direction of a hinge.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DirectionMemory {
    /// Hysteresis mode.
    pub slip: SlipMode,
    /// The end stop is in contact.
    pub in_contact: bool,
    /// The latch has engaged and holds for good.
    pub latched: bool,
    /// Piece of a table response the coordinate is in (see `Table::piece`): crossing a data
    /// point is an event, so the integrator never steps over a kink of the response.
    pub piece: i64,
    /// Second bookkeeping piece: a 2-D table's grid interval in the coupled coordinate, or the
    /// interval of a tape spring's data points.
    pub piece_2: i64,
}

/// Discrete memory a law keeps across steps, per direction (x, y, z, rx, ry, rz).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LawMemory {
    /// Per direction.
    pub directions: [DirectionMemory; 6],
}

/// A copy of a law in a new box (laws are `Clone`; this makes `Box<dyn HingeLaw>` so).
pub trait CloneLaw {
    /// The law, copied into a new allocation.
    fn clone_box(&self) -> Box<dyn HingeLaw>;
}

impl<L: HingeLaw + Clone + 'static> CloneLaw for L {
    fn clone_box(&self) -> Box<dyn HingeLaw> {
        Box::new(self.clone())
    }
}

/// A hinge's force and torque response.
pub trait HingeLaw: Debug + Send + Sync + CloneLaw {
    /// Force (A0 components, N) and torque (A components, N·m) at this relative state.
    fn wrench(&self, state: &HingeState, memory: &LawMemory) -> HingeWrench;

    /// [`HingeLaw::wrench`] in dual numbers, with the memory held: what the implicit path's
    /// exact Jacobian needs. `None` if the law cannot (the Jacobian then falls back to
    /// finite differences).
    fn wrench_dual(&self, _state: &HingeState<JacobianDual>, _memory: &LawMemory) -> Option<HingeWrench<JacobianDual>> {
        None
    }

    /// Energy stored in the hinge, J. For a law with a potential this is that potential;
    /// for the paper-linear law it is the same quadratic form, reported for comparison
    /// although the law's torque is not its gradient (docs/model.md §4).
    fn stored_energy(&self, state: &HingeState, memory: &LawMemory) -> f64;

    /// Power the hinge takes from the bodies beyond the rate of its stored energy, W:
    /// `F·δ̇ + τ·ω_rel − dV/dt`. Positive for dissipation (damping, hysteresis, stops); for
    /// the paper-linear law it is the power of its non-potential torque, of either sign.
    fn dissipation_power(&self, state: &HingeState, memory: &LawMemory) -> f64;

    /// [`HingeLaw::wrench`] and [`HingeLaw::dissipation_power`] together, as the
    /// right-hand side needs both (laws override it to share the work).
    fn wrench_and_dissipation(&self, state: &HingeState, memory: &LawMemory) -> (HingeWrench, f64) {
        (self.wrench(state, memory), self.dissipation_power(state, memory))
    }

    /// True if the law's forces derive from [`HingeLaw::stored_energy`] and nothing
    /// dissipates, so that `E = T + V` is conserved.
    fn conserves_energy(&self) -> bool;

    /// True if the law is built on the 3-2-1 Euler angles and so is singular at pitch ±90°.
    fn uses_euler_angles(&self) -> bool {
        true
    }

    /// Short name for reports.
    fn name(&self) -> &'static str;

    /// Memory at the initial state.
    fn initial_memory(&self, _state: &HingeState) -> LawMemory {
        LawMemory::default()
    }

    /// Number of event functions (zero for smooth laws).
    fn event_count(&self) -> usize {
        0
    }

    /// Event function values, one per [`HingeLaw::event_count`]: each is ≥ 0 while the
    /// current memory holds and crosses below zero when it must change.
    fn event_values(&self, _state: &HingeState, _memory: &LawMemory, _out: &mut [f64]) {}

    /// Whether event `k` only keeps bookkeeping that does not change the response (a table's
    /// piece: the force is continuous across its points), which [`HingeLaw::sync_memory`]
    /// also brings up to date: the run may then step across it without landing on it.
    fn bookkeeping_event(&self, _k: usize) -> bool {
        false
    }

    /// Whether event `k` switches a slip element's mode (a tape spring's reversal or slide),
    /// where the force is continuous across the switch: a run may take such an event at the
    /// end of the step after it rather than at its very start (see `crate::simulate`'s event
    /// handling, where it would otherwise chatter at one instant).
    fn slip_event(&self, _k: usize) -> bool {
        false
    }

    /// Applies event `k`, just crossed at `state`, to the memory; says what happened.
    fn apply_event(&self, _k: usize, _state: &HingeState, _memory: &mut LawMemory) -> (EventKind, String) {
        (EventKind::Branch, String::new())
    }

    /// Directions (x, y, z, rx, ry, rz) held rigid at their initial values by constraints
    /// (see [`crate::dynamics::locks`]); rotational ones are 3-2-1 Euler angles.
    fn locked_directions(&self) -> [bool; 6] {
        [false; 6]
    }

    /// Brings bookkeeping memory that does not change the response (such as which piece of
    /// a table the coordinate is in) up to date at an accepted state.
    fn sync_memory(&self, _state: &HingeState, _memory: &mut LawMemory) {}

    /// Checks an accepted state (e.g. a table's range with the `error` policy).
    fn check(&self, _state: &HingeState, _memory: &LawMemory) -> Result<(), String> {
        Ok(())
    }

    /// Per direction (x, y, z, rx, ry, rz): upper bounds on the stiffness `|∂f/∂q|` (N/m,
    /// N·m/rad) and the damping `|∂f/∂q̇|` (N·s/m, N·m·s/rad) the law can present anywhere,
    /// for the run's time-scale estimates (its step budget, and naming the stiffest hinge
    /// when a run cannot go on). Zero for free and locked directions.
    fn stiffness_bounds(&self) -> [Bounds; 6];
}

/// Upper bounds on one direction's stiffness and damping (see
/// [`HingeLaw::stiffness_bounds`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Bounds {
    /// Stiffness `|∂f/∂q|`, N/m or N·m/rad.
    pub stiffness: f64,
    /// Damping `|∂f/∂q̇|`, N·s/m or N·m·s/rad.
    pub damping: f64,
}

/// The two wrench methods of [`HingeLaw`] for a law whose `wrench_t` is generic over the
/// scalar: f64 for the right-hand side, dual numbers for the Jacobian.
macro_rules! generic_wrench {
    () => {
        fn wrench(&self, state: &HingeState, _memory: &LawMemory) -> HingeWrench {
            self.wrench_t(state)
        }

        fn wrench_dual(
            &self,
            state: &HingeState<JacobianDual>,
            _memory: &LawMemory,
        ) -> Option<HingeWrench<JacobianDual>> {
            Some(self.wrench_t(state))
        }
    };
}

/// Stiffness and damping matrices shared by laws 1 and 2 of docs/model.md §4.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearGains {
    /// Translational stiffness `K_F`, N/m, acting on δ in A0 components.
    pub k_f: Mat3,
    /// Rotational stiffness `K_θ`, N·m/rad, acting on `φ = [θ3, θ2, θ1]`.
    pub k_theta: Mat3,
    /// Translational damping `C_F`, N·s/m, acting on δ̇ (A0 components).
    pub c_f: Mat3,
    /// Rotational damping `C_θ`, N·m·s/rad, acting on `ω_rel` (A components).
    pub c_theta: Mat3,
}

impl LinearGains {
    fn spring_energy(&self, state: &HingeState) -> f64 {
        let phi = state.theta.phi();
        0.5 * state.delta_in_a0.dot(&(self.k_f * state.delta_in_a0)) + 0.5 * phi.dot(&(self.k_theta * phi))
    }

    fn damping_force<T: Real>(&self, state: &HingeState<T>) -> Vector3<T> {
        const_mat_vec(&self.c_f, &state.delta_rate_in_a0)
    }

    fn damping_torque<T: Real>(&self, state: &HingeState<T>) -> Vector3<T> {
        const_mat_vec(&self.c_theta, &state.omega_rel_in_a)
    }

    /// `K_F δ + C_F δ̇`, the force of laws 1, 2 and the rotation-vector law.
    fn force<T: Real>(&self, state: &HingeState<T>) -> Vector3<T> {
        const_mat_vec(&self.k_f, &state.delta_in_a0) + self.damping_force(state)
    }

    /// Gershgorin bounds per direction: row sums of |K| and |C| (the translations from
    /// `K_F`, `C_F`; the rotations from `K_θ` on φ = (roll, pitch, yaw) = (rx, ry, rz) and
    /// `C_θ` on ω_rel).
    fn bounds(&self) -> [Bounds; 6] {
        let row = |m: &Mat3, i: usize| m.row(i).iter().map(|x| x.abs()).sum::<f64>();
        std::array::from_fn(|d| {
            let (k, c, i) = if d < 3 { (&self.k_f, &self.c_f, d) } else { (&self.k_theta, &self.c_theta, d - 3) };
            Bounds { stiffness: row(k, i), damping: row(c, i) }
        })
    }

    fn undamped(&self) -> bool {
        self.c_f.iter().all(|&c| c == 0.0) && self.c_theta.iter().all(|&c| c == 0.0)
    }

    /// Damping power `δ̇ᵀC_Fδ̇ + ω_relᵀC_θω_rel`, W.
    fn damping_power(&self, state: &HingeState) -> f64 {
        state.delta_rate_in_a0.dot(&self.damping_force(state)) + state.omega_rel_in_a.dot(&self.damping_torque(state))
    }

    /// Rate of the quadratic form `½ δᵀK_Fδ + ½ φᵀK_θφ`, W.
    fn spring_energy_rate(&self, state: &HingeState) -> f64 {
        let sym = |m: &Mat3| (m + m.transpose()) * 0.5;
        let theta_rate = state.trig.rates_from_omega(&state.omega_rel_in_a);
        let phi_rate = Vec3::new(theta_rate.z, theta_rate.y, theta_rate.x);
        let phi = state.theta.phi();
        state.delta_in_a0.dot(&(sym(&self.k_f) * state.delta_rate_in_a0)) + phi.dot(&(sym(&self.k_theta) * phi_rate))
    }
}

/// Law 1, "paper linear" (docs/model.md §4, paper eq. 15):
/// `F = K_F δ + C_F δ̇`, `τ = K_θ φ + C_θ ω_rel`, `φ = [θ3, θ2, θ1]`.
///
/// Conserves momentum but not energy, even undamped: `−B(θ)ᵀ K_θ φ` is not a gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperLinear {
    /// Stiffness and damping.
    pub gains: LinearGains,
}

impl PaperLinear {
    fn wrench_t<T: Real>(&self, state: &HingeState<T>) -> HingeWrench<T> {
        let g = &self.gains;
        HingeWrench {
            force_in_a0: g.force(state),
            torque_in_a: const_mat_vec(&g.k_theta, &state.theta.phi()) + g.damping_torque(state),
        }
    }
}

impl HingeLaw for PaperLinear {
    generic_wrench!();

    fn stored_energy(&self, state: &HingeState, _memory: &LawMemory) -> f64 {
        self.gains.spring_energy(state)
    }

    fn dissipation_power(&self, state: &HingeState, memory: &LawMemory) -> f64 {
        let w = self.wrench(state, memory);
        w.force_in_a0.dot(&state.delta_rate_in_a0) + w.torque_in_a.dot(&state.omega_rel_in_a)
            - self.gains.spring_energy_rate(state)
    }

    fn conserves_energy(&self) -> bool {
        false
    }

    fn name(&self) -> &'static str {
        "paper-linear"
    }

    fn stiffness_bounds(&self) -> [Bounds; 6] {
        self.gains.bounds()
    }
}

/// Law 2, "Euler potential" (docs/model.md §4): `V = ½ δᵀ K_F δ + ½ φᵀ K_θ φ` with generalized
/// force `−∂V/∂q`, plus the damping of law 1. `K_F` and `K_θ` must be symmetric.
///
/// The torque is `τ = B(θ)⁻ᵀ (∂φ/∂θ)ᵀ K_θ φ + C_θ ω_rel`, singular at pitch ±90°.
/// Undamped, it conserves `E = T + V` exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerPotential {
    /// Stiffness (symmetric) and damping.
    pub gains: LinearGains,
}

impl EulerPotential {
    fn wrench_t<T: Real>(&self, state: &HingeState<T>) -> HingeWrench<T> {
        let g = &self.gains;
        let k_phi = const_mat_vec(&g.k_theta, &state.theta.phi());
        // ∂V/∂θ = (∂φ/∂θ)ᵀ K_θ φ; φ reverses θ, so the gradient is K_θ φ reversed.
        let dv_dtheta = Vector3::new(k_phi.z, k_phi.y, k_phi.x);
        HingeWrench {
            force_in_a0: g.force(state),
            torque_in_a: state.trig.torque_from_generalized(&dv_dtheta) + g.damping_torque(state),
        }
    }
}

impl HingeLaw for EulerPotential {
    generic_wrench!();

    fn stored_energy(&self, state: &HingeState, _memory: &LawMemory) -> f64 {
        self.gains.spring_energy(state)
    }

    fn dissipation_power(&self, state: &HingeState, _memory: &LawMemory) -> f64 {
        self.gains.damping_power(state)
    }

    fn conserves_energy(&self) -> bool {
        self.gains.undamped()
    }

    fn name(&self) -> &'static str {
        "euler-potential"
    }

    fn stiffness_bounds(&self) -> [Bounds; 6] {
        self.gains.bounds()
    }
}

/// Linear law on the rotation vector (axis × angle) of `[A A0]`:
/// `V = ½ δᵀ K_F δ + ½ rᵀ K_r r`, `r` with |r| ≤ π, plus damping `C_F δ̇` and `C_θ ω_rel`.
///
/// The torque is `τ = J_r(r)⁻ᵀ K_r r` (`J_r` the right Jacobian of SO(3)), which has no
/// singularity short of a 180° fold, so it carries fold angles Euler angles cannot. For an
/// isotropic `K_r = k I` it is simply `k r`. Undamped, it conserves `E = T + V`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotationVectorLinear {
    /// `K_F`, `C_F`, `C_θ` as for law 2; `k_theta` is `K_r` (N·m/rad), acting on r.
    pub gains: LinearGains,
}

impl RotationVectorLinear {
    fn wrench_t<T: Real>(&self, state: &HingeState<T>) -> HingeWrench<T> {
        let g = &self.gains;
        let r = rotation_vector(&state.dcm_a_a0);
        let torque = rotation_vector_rate_matrix_inverse(&r).transpose() * (const_mat_vec(&g.k_theta, &r));
        HingeWrench { force_in_a0: g.force(state), torque_in_a: torque + g.damping_torque(state) }
    }
}

impl HingeLaw for RotationVectorLinear {
    generic_wrench!();

    fn stored_energy(&self, state: &HingeState, _memory: &LawMemory) -> f64 {
        let r = rotation_vector(&state.dcm_a_a0);
        let d = state.delta_in_a0;
        0.5 * d.dot(&(self.gains.k_f * d)) + 0.5 * r.dot(&(self.gains.k_theta * r))
    }

    fn dissipation_power(&self, state: &HingeState, _memory: &LawMemory) -> f64 {
        self.gains.damping_power(state)
    }

    fn conserves_energy(&self) -> bool {
        self.gains.undamped()
    }

    fn uses_euler_angles(&self) -> bool {
        false
    }

    fn name(&self) -> &'static str {
        "rotation-vector"
    }

    fn stiffness_bounds(&self) -> [Bounds; 6] {
        self.gains.bounds()
    }

    fn check(&self, state: &HingeState, _memory: &LawMemory) -> Result<(), String> {
        check_rotation_vector(state)
    }
}

/// How near a 180° rotation a rotation-vector law may come before the run stops, rad.
pub const HALF_TURN_MARGIN: f64 = 1e-3;

/// Rotation-vector laws are defined for rotations short of 180°: there the rotation vector
/// jumps from r to −r (the same rotation, the other way round).
pub(crate) fn check_rotation_vector(state: &HingeState) -> Result<(), String> {
    let angle = rotation_vector(&state.dcm_a_a0).norm();
    if angle > std::f64::consts::PI - HALF_TURN_MARGIN {
        return Err(format!(
            "the hinge rotated {:.4}° from A0: rotation-vector laws are defined for rotations short of 180°, where the rotation vector flips",
            angle.to_degrees()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gains() -> LinearGains {
        LinearGains {
            k_f: Mat3::from_diagonal(&Vec3::new(100.0, 200.0, 300.0)),
            k_theta: Mat3::new(10.0, 1.0, 0.0, 1.0, 20.0, 2.0, 0.0, 2.0, 30.0),
            c_f: Mat3::zeros(),
            c_theta: Mat3::zeros(),
        }
    }

    /// The Euler-potential torque must do the virtual work of −∂V/∂θ: for any angle rate,
    /// τ · (B θ̇) = (∂V/∂θ) · θ̇. Checked against a central difference of V (error ~1e-9).
    #[test]
    fn euler_potential_torque_is_gradient_of_v() {
        let law = EulerPotential { gains: gains() };
        let state = HingeState::at(Vec3::new(0.01, -0.02, 0.03), Euler321::new(0.7, -0.4, 1.9));
        let m = LawMemory::default();
        let w = law.wrench(&state, &m);
        let b = state.theta.rate_matrix();
        for k in 0..3 {
            let mut e = Vec3::zeros();
            e[k] = 1.0;
            let h = 1e-6;
            let shifted = |s: f64| {
                let v = state.theta.as_vector() + e * s;
                HingeState::at(state.delta_in_a0, Euler321::new(v.x, v.y, v.z))
            };
            let dv = (law.stored_energy(&shifted(h), &m) - law.stored_energy(&shifted(-h), &m)) / (2.0 * h);
            let work = w.torque_in_a.dot(&(b * e));
            assert!((work - dv).abs() < 1e-7 * dv.abs().max(1.0), "k={k}: {work} vs {dv}");
        }
    }

    /// The rotation-vector torque does the virtual work of −∂V: τ · ω = dV/dt for a motion
    /// with angular velocity ω, at a fold of 150° (beyond where Euler laws are usable).
    #[test]
    fn rotation_vector_torque_is_gradient_of_v() {
        let law = RotationVectorLinear { gains: gains() };
        let m = LawMemory::default();
        let r0 = Vec3::new(0.3, -2.4, 1.0).normalize() * 150f64.to_radians();
        let dcm = |r: &Vec3| nalgebra::Rotation3::new(*r).into_inner().transpose(); // [A A0]
        let at = |c: Mat3| HingeState { dcm_a_a0: c, ..Default::default() };
        let w = law.wrench(&at(dcm(&r0)), &m);
        for omega in [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.3, -0.2, 0.9)] {
            // [A A0](t) for ω_{A/A0} in A: d[A A0]/dt = −[ω×][A A0].
            let h = 1e-6;
            let rot = |s: f64| nalgebra::Rotation3::new(-omega * s).into_inner() * dcm(&r0);
            let dv = (law.stored_energy(&at(rot(h)), &m) - law.stored_energy(&at(rot(-h)), &m)) / (2.0 * h);
            let work = w.torque_in_a.dot(&omega);
            assert!((work - dv).abs() < 1e-6 * dv.abs().max(1.0), "{work} vs {dv}");
        }
    }
}

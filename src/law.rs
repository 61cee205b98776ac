//! Hinge laws (MODEL.md §4): the map from a hinge's relative state to its force and torque.
//!
//! Every law implements [`HingeLaw`]. The engine applies the returned force and torque as the
//! wrench pair of DESIGN.md §1, which is the generalized force of MODEL.md §4 (paper eq. 14):
//! a torque `τ` (A components) does virtual work `−τ · δω_rel`, so a law that wants the
//! generalized force `g` on the Euler angles returns `τ = B(θ)⁻ᵀ g`.

use crate::math::{Euler321, Mat3, Vec3};
use std::fmt::Debug;

/// Relative state of one hinge (MODEL.md §2).
#[derive(Clone, Copy, Debug, Default)]
pub struct HingeState {
    /// `δ = ᴬ⁰(R_A − R_A0)`: A's origin relative to A0's origin, A0 components, m.
    pub delta_in_a0: Vec3,
    /// Time derivative of the A0 components of δ, m/s.
    pub delta_rate_in_a0: Vec3,
    /// 3-2-1 angles of `[A A0]`, tracked continuously (MODEL.md §7), rad.
    pub theta: Euler321,
    /// `ω_{A/A0}` in A components, rad/s.
    pub omega_rel_in_a: Vec3,
}

/// Force and torque a hinge law returns (MODEL.md §4).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HingeWrench {
    /// Restoring force `F`, A0 components, N. The child receives `−F` at A's origin, the
    /// parent `+F` at the same point.
    pub force_in_a0: Vec3,
    /// Restoring torque `τ`, A components, N·m. The child receives `−τ`, the parent `+τ`.
    pub torque_in_a: Vec3,
}

/// A hinge's force and torque response.
pub trait HingeLaw: Debug + Send + Sync {
    /// Force (A0 components, N) and torque (A components, N·m) at this relative state.
    fn wrench(&self, state: &HingeState) -> HingeWrench;

    /// Energy stored in the hinge, J. For a law with a potential this is that potential;
    /// for the paper-linear law it is the same quadratic form, reported for comparison
    /// although the law's torque is not its gradient (MODEL.md §4).
    fn stored_energy(&self, state: &HingeState) -> f64;

    /// True if the law's forces derive from [`HingeLaw::stored_energy`] and nothing
    /// dissipates, so that `E = T + V` is conserved.
    fn conserves_energy(&self) -> bool;

    /// Short name for reports.
    fn name(&self) -> &'static str;
}

/// Stiffness and damping matrices shared by laws 1 and 2 of MODEL.md §4.
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

    fn damping_force(&self, state: &HingeState) -> Vec3 {
        self.c_f * state.delta_rate_in_a0
    }

    fn damping_torque(&self, state: &HingeState) -> Vec3 {
        self.c_theta * state.omega_rel_in_a
    }

    fn undamped(&self) -> bool {
        self.c_f.iter().all(|&c| c == 0.0) && self.c_theta.iter().all(|&c| c == 0.0)
    }
}

/// Law 1, "paper linear" (MODEL.md §4, paper eq. 15):
/// `F = K_F δ + C_F δ̇`, `τ = K_θ φ + C_θ ω_rel`, `φ = [θ3, θ2, θ1]`.
///
/// Conserves momentum but not energy, even undamped: `−B(θ)ᵀ K_θ φ` is not a gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperLinear {
    /// Stiffness and damping.
    pub gains: LinearGains,
}

impl HingeLaw for PaperLinear {
    fn wrench(&self, state: &HingeState) -> HingeWrench {
        let g = &self.gains;
        HingeWrench {
            force_in_a0: g.k_f * state.delta_in_a0 + g.damping_force(state),
            torque_in_a: g.k_theta * state.theta.phi() + g.damping_torque(state),
        }
    }

    fn stored_energy(&self, state: &HingeState) -> f64 {
        self.gains.spring_energy(state)
    }

    fn conserves_energy(&self) -> bool {
        false
    }

    fn name(&self) -> &'static str {
        "paper-linear"
    }
}

/// Law 2, "Euler potential" (MODEL.md §4): `V = ½ δᵀ K_F δ + ½ φᵀ K_θ φ` with generalized
/// force `−∂V/∂q`, plus the damping of law 1. `K_F` and `K_θ` must be symmetric.
///
/// The torque is `τ = B(θ)⁻ᵀ (∂φ/∂θ)ᵀ K_θ φ + C_θ ω_rel`, singular at pitch ±90°.
/// Undamped, it conserves `E = T + V` exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerPotential {
    /// Stiffness (symmetric) and damping.
    pub gains: LinearGains,
}

impl HingeLaw for EulerPotential {
    fn wrench(&self, state: &HingeState) -> HingeWrench {
        let g = &self.gains;
        let k_phi = g.k_theta * state.theta.phi();
        // ∂V/∂θ = (∂φ/∂θ)ᵀ K_θ φ; φ reverses θ, so the gradient is K_θ φ reversed.
        let dv_dtheta = Vec3::new(k_phi.z, k_phi.y, k_phi.x);
        HingeWrench {
            force_in_a0: g.k_f * state.delta_in_a0 + g.damping_force(state),
            torque_in_a: state.theta.torque_from_generalized(&dv_dtheta) + g.damping_torque(state),
        }
    }

    fn stored_energy(&self, state: &HingeState) -> f64 {
        self.gains.spring_energy(state)
    }

    fn conserves_energy(&self) -> bool {
        self.gains.undamped()
    }

    fn name(&self) -> &'static str {
        "euler-potential"
    }
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
        let state = HingeState {
            delta_in_a0: Vec3::new(0.01, -0.02, 0.03),
            theta: Euler321::new(0.7, -0.4, 1.9),
            ..Default::default()
        };
        let w = law.wrench(&state);
        let b = state.theta.rate_matrix();
        for k in 0..3 {
            let mut e = Vec3::zeros();
            e[k] = 1.0;
            let h = 1e-6;
            let shifted = |s: f64| {
                let v = state.theta.as_vector() + e * s;
                HingeState { theta: Euler321::new(v.x, v.y, v.z), ..state }
            };
            let dv = (law.stored_energy(&shifted(h)) - law.stored_energy(&shifted(-h))) / (2.0 * h);
            let work = w.torque_in_a.dot(&(b * e));
            assert!((work - dv).abs() < 1e-7 * dv.abs().max(1.0), "k={k}: {work} vs {dv}");
        }
    }
}

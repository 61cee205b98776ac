//! Generalized-α's tests at fixed steps (`super`).

use super::*;
use crate::integrate::DenseNewton;

/// `x'' = −ω² x` as a first-order system.
struct Oscillator(f64);
impl OdeSystem for Oscillator {
    fn rhs(&self, _t: f64, y: &[f64], d: &mut [f64]) {
        d[0] = y[1];
        d[1] = -self.0 * self.0 * y[0];
    }
}

/// The state at `tf` from x = 1, ẋ = 0 at steps of `h`, Newton to 1e-13.
fn run(omega: f64, h: f64, rho_inf: f64, tf: f64) -> (Vec<f64>, Stats) {
    let sys = Oscillator(omega);
    let mut newton = DenseNewton::new(&sys, 2);
    let mut end = vec![];
    let stats = integrate_generalized_alpha(
        &sys,
        &mut newton,
        AlphaSteps::Fixed(h),
        rho_inf,
        1e-13,
        1e-13,
        Limits::default(),
        0.0,
        tf,
        &[1.0, 0.0],
        |s: &Step<'_>| -> Result<Control, ()> {
            end = s.y.to_vec();
            Ok(Control::Continue)
        },
    )
    .unwrap();
    (end, stats)
}

/// Second order (JWH's γ = ½ + α_m − α_f): halving the step quarters the error of a
/// resolved oscillation, within 10 % (the next term is O(h) smaller at ωh ≤ 0.02).
#[test]
fn second_order_on_a_resolved_oscillation() {
    for rho_inf in [0.0, 0.5, 0.9] {
        let exact = [2f64.cos(), -2f64.sin()];
        let err = |h: f64| {
            let (y, _) = run(1.0, h, rho_inf, 2.0);
            ((y[0] - exact[0]).powi(2) + (y[1] - exact[1]).powi(2)).sqrt()
        };
        let (e1, e2) = (err(0.02), err(0.01));
        assert!((e1 / e2 - 4.0).abs() < 0.4, "rho_inf {rho_inf}: error ratio {} (errors {e1:e}, {e2:e})", e1 / e2);
    }
}

/// The damping of a vibration far beyond the step (ωh = 1e6): its amplitude falls by ρ∞
/// per step (JWH eq. 21: the spectral radius at infinite frequency). The amplification's
/// two roots tend to one double root there, so the amplitude goes as n ρ∞ⁿ: over steps
/// 100 to 200 the rate per step is ρ∞ · 2^(1/100) (0.7 % above ρ∞), and the roots are
/// O(1/√(ωh)) = 0.1 % apart; 1.5 % bounds both. At ρ∞ = 1 (the trapezoidal rule) nothing
/// is lost, to round-off.
#[test]
fn unresolved_vibrations_lose_rho_inf_per_step() {
    let (omega, h) = (1e6, 1.0);
    for rho_inf in [0.5, 0.8, 0.9, 1.0] {
        let amplitude = |y: &[f64]| (y[0] * y[0] + (y[1] / omega).powi(2)).sqrt();
        let (y100, _) = run(omega, h, rho_inf, 100.0);
        let (y200, _) = run(omega, h, rho_inf, 200.0);
        let per_step = (amplitude(&y200) / amplitude(&y100)).powf(0.01);
        let bound = if rho_inf == 1.0 { 1e-9 } else { 0.015 * rho_inf };
        assert!((per_step - rho_inf).abs() < bound, "rho_inf {rho_inf}: {per_step} per step");
    }
}

/// The spectral-radius parameters (JWH eq. 21) and their second-order condition.
#[test]
fn parameters_from_rho_inf() {
    let p = AlphaParameters::from_rho_inf(1.0);
    assert_eq!((p.alpha_m, p.alpha_f, p.gamma), (0.5, 0.5, 0.5));
    let p = AlphaParameters::from_rho_inf(0.0);
    assert_eq!((p.alpha_m, p.alpha_f, p.gamma), (1.5, 1.0, 1.0));
}

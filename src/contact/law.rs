//! The compliant contact law of one contact point (docs/contact.md §2).
//!
//! Normal force, after Hunt & Crossley (1975) in the form of Lankarani & Nikravesh (1990) and
//! Flores et al. (2011):
//!
//! ```text
//! f_n = max(0, K δ^n (1 + χ δ̇ / v₀))
//! ```
//!
//! with δ the penetration (m), δ̇ its rate (m/s, > 0 approaching), v₀ the approach speed when
//! the point came into contact, K the stiffness (N/m^n) and n the exponent. The damping factor
//! χ is the one that gives the coefficient of restitution `e` asked for exactly: the law in
//! the scaled variables x = δ/δ*, s = t v₀/δ* (δ*^(n+1) = m v₀²/K) is
//! `x'' = −xⁿ max(0, 1 + χ x')`, x(0) = 0, x'(0) = 1, whatever the mass, stiffness and speed,
//! so `e(χ) = −x'` at separation is one function of χ (for each n), which [`damping_factor`]
//! inverts numerically, starting from Flores et al.'s closed form χ ≈ 8(1 − e)/(5e). (Flores'
//! form gives e within a few per cent for e ≥ 0.5 and drifts below that; docs/contact.md
//! has the table.)
//!
//! Friction: regularised Coulomb, `f_t = −μ f_n v_t / √(|v_t|² + v_s²)` with v_t the slip
//! velocity and v_s the slip speed below which the law is viscous (Exudyn's regularised
//! friction uses a linear zone of the same kind).

use crate::math::{Real, re, real};
use nalgebra::Vector3;

/// The contact law's parameters (the scenario's `[contact]` table).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactLaw {
    /// Normal stiffness K, N/m^exponent, per contact point (> 0).
    pub stiffness: f64,
    /// Exponent n of the penetration (1 ≤ n ≤ 3; 1.5 is Hertz's).
    pub exponent: f64,
    /// Coefficient of restitution e of a normal impact, in [`MIN_RESTITUTION`, 1].
    pub restitution: f64,
    /// Coulomb friction coefficient μ (≥ 0).
    pub friction: f64,
    /// Slip speed v_s, m/s (> 0): below it friction is viscous, above it Coulomb.
    pub slip_speed: f64,
    /// Least approach speed v₀ a point's damping is scaled by, m/s (> 0): a point that comes
    /// into contact slower than this (a resting contact) is damped as if it came at this speed.
    pub min_impact_speed: f64,
    /// Distance at which a pair starts being tracked, m (≥ 0).
    pub margin: f64,
    /// The damping factor χ that gives `restitution` (from [`damping_factor`]).
    pub chi: f64,
}

/// The smallest coefficient of restitution accepted: the damping needed grows like 1/e
/// without bound as e → 0 (Flores' χ = 8(1 − e)/(5e)), making the contact as stiff in its
/// damping as one likes.
pub const MIN_RESTITUTION: f64 = 0.01;

/// What one contact point does: its normal force and the energy flows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointForce<T = f64> {
    /// Normal force magnitude f_n, N (≥ 0).
    pub normal: T,
    /// Its elastic part K δ^n, N.
    pub elastic: T,
    /// Power dissipated by the damping, W (≥ 0): (f_n − K δⁿ) δ̇.
    pub damping_power: T,
}

impl ContactLaw {
    /// The law with the damping factor for `restitution`.
    pub fn new(
        stiffness: f64,
        exponent: f64,
        restitution: f64,
        friction: f64,
        slip_speed: f64,
        min_impact_speed: f64,
        margin: f64,
    ) -> Self {
        let chi = damping_factor(restitution, exponent);
        Self { stiffness, exponent, restitution, friction, slip_speed, min_impact_speed, margin, chi }
    }

    /// Normal force at penetration `depth` (m, > 0) closing at `rate` (m/s, > 0 approaching)
    /// for a point that came into contact at `impact_speed` (m/s; `None`: it comes into
    /// contact now, at `rate`). Generic over the scalar (the exact Jacobian runs it in dual
    /// numbers; the clamp is chosen on the real part).
    pub fn normal<T: Real>(&self, depth: T, rate: T, impact_speed: Option<f64>) -> PointForce<T> {
        // δ^1.5 as δ √δ: the default exponent, at a fraction of pow's cost.
        let power = if self.exponent == 1.5 { depth * depth.sqrt() } else { depth.powf(real(self.exponent)) };
        let elastic = power * real(self.stiffness);
        let v0: T = match impact_speed {
            Some(v) => real(v.max(self.min_impact_speed)),
            None if re(rate) > self.min_impact_speed => rate,
            None => real(self.min_impact_speed),
        };
        let factor = real::<T>(1.0) + rate * real(self.chi) / v0;
        let normal = if re(factor) > 0.0 { elastic * factor } else { real(0.0) };
        PointForce { normal, elastic, damping_power: (normal - elastic) * rate }
    }

    /// Elastic energy stored at penetration `depth`, J: K δ^(n+1) / (n+1).
    pub fn energy(&self, depth: f64) -> f64 {
        let power = if self.exponent == 1.5 { depth * depth * depth.sqrt() } else { depth.powf(self.exponent + 1.0) };
        self.stiffness * power / (self.exponent + 1.0)
    }

    /// Friction force on the sliding body for slip velocity `slip` (m/s, tangential) under
    /// normal force `normal` (N): `−μ f_n v_t / √(|v_t|² + v_s²)`.
    pub fn friction_force<T: Real>(&self, normal: T, slip: &Vector3<T>) -> Vector3<T> {
        let s = slip.norm_squared() + real(self.slip_speed * self.slip_speed);
        slip * (-normal * real(self.friction) / s.sqrt())
    }
}

/// The coefficient of restitution of the scaled law with damping factor `chi` and exponent
/// `n`: `x'' = −xⁿ max(0, 1 + χ x')` from x = 0, x' = 1 until x returns to 0; e = −x' there.
/// Classical Runge–Kutta on a step of 1/4000 of the undamped contact time, the crossing
/// located by cubic Hermite interpolation: e to ~1e-8 (the force has a kink at x = 0).
pub fn restitution_of(chi: f64, n: f64) -> f64 {
    let f = |x: f64, v: f64| -> f64 { -(x.max(0.0)).powf(n) * (1.0 + chi * v).max(0.0) };
    // The undamped scaled contact lasts 2 ∫₀^xm dx/√(1 − 2x^(n+1)/(n+1)), a few units.
    let h = 1e-3;
    let (mut x, mut v) = (0.0_f64, 1.0_f64);
    for _ in 0..10_000_000 {
        let (k1x, k1v) = (v, f(x, v));
        let (k2x, k2v) = (v + 0.5 * h * k1v, f(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
        let (k3x, k3v) = (v + 0.5 * h * k2v, f(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
        let (k4x, k4v) = (v + h * k3v, f(x + h * k3x, v + h * k3v));
        let xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        let vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if xn <= 0.0 && vn < 0.0 {
            // Hermite cubic on [0, h] through (x, v), (xn, vn): find its root by bisection,
            // then the velocity there.
            let p = |s: f64| -> (f64, f64) {
                let (s2, s3) = (s * s, s * s * s);
                let pos = (2.0 * s3 - 3.0 * s2 + 1.0) * x
                    + (s3 - 2.0 * s2 + s) * h * v
                    + (-2.0 * s3 + 3.0 * s2) * xn
                    + (s3 - s2) * h * vn;
                let vel = ((6.0 * s2 - 6.0 * s) * x + (3.0 * s2 - 4.0 * s + 1.0) * h * v + (-6.0 * s2 + 6.0 * s) * xn)
                    / h
                    + (3.0 * s2 - 2.0 * s) * vn;
                (pos, vel)
            };
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if p(mid).0 > 0.0 { lo = mid } else { hi = mid }
            }
            return -p(0.5 * (lo + hi)).1;
        }
        if vn >= 0.0 && xn > 0.0 && v < 0.0 {
            // Stopped inside (overdamped by the clamp): no rebound.
            return 0.0;
        }
        x = xn;
        v = vn;
    }
    0.0
}

/// The damping factor χ that gives restitution `e` for exponent `n` (see the module
/// documentation): bisection on [`restitution_of`], which decreases with χ, to 1e-10 in e.
pub fn damping_factor(e: f64, n: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    // Flores et al.'s closed form as the first guess, then a bracket around it.
    let guess = 8.0 * (1.0 - e) / (5.0 * e);
    let (mut lo, mut hi) = (0.0, guess.max(1e-3));
    while restitution_of(hi, n) > e {
        lo = hi;
        hi *= 2.0;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if restitution_of(mid, n) > e {
            lo = mid
        } else {
            hi = mid
        }
        if hi - lo < 1e-12 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derivative the exact Jacobian takes of the normal force equals the force's own
    /// rate of change (central differences, 1e-6 relative: their truncation), for a point in
    /// contact since earlier (impact speed held) and for one that comes into contact now,
    /// whose impact speed is its approach speed: then the damping factor is 1 + χ whatever
    /// that speed, and the force does not change with it (the Jacobian took the speed for a
    /// constant, and Newton met damping that the force did not have).
    #[test]
    fn the_normal_forces_derivative_is_its_rate_of_change() {
        use num_dual::Dual64;
        let law = ContactLaw::new(1e8, 1.5, 0.3, 0.2, 1e-3, 1e-3, 0.0);
        for held in [Some(0.4), None] {
            for rate in [0.3, 2e-4, -1e-4] {
                let depth = 2e-5;
                let f = |d: f64, r: f64| law.normal(d, r, held).normal;
                let exact_d = law.normal(Dual64::new(depth, 1.0), Dual64::from(rate), held).normal.eps;
                let exact_r = law.normal(Dual64::from(depth), Dual64::new(rate, 1.0), held).normal.eps;
                let (hd, hr) = (1e-6 * depth, 1e-7 * rate.abs());
                let fd_d = (f(depth + hd, rate) - f(depth - hd, rate)) / (2.0 * hd);
                let fd_r = (f(depth, rate + hr) - f(depth, rate - hr)) / (2.0 * hr);
                assert!((exact_d - fd_d).abs() <= 1e-6 * fd_d.abs().max(1e-9), "{held:?} {rate}: {exact_d} vs {fd_d}");
                assert!((exact_r - fd_r).abs() <= 1e-6 * fd_r.abs().max(1e-9), "{held:?} {rate}: {exact_r} vs {fd_r}");
            }
        }
    }

    /// Without damping the scaled law rebounds at the speed it came in (energy is
    /// conserved): e = 1 to the integration's accuracy.
    #[test]
    fn undamped_rebound_is_elastic() {
        assert!((restitution_of(0.0, 1.5) - 1.0).abs() < 1e-7);
        let e1 = restitution_of(0.0, 1.0);
        assert!((e1 - 1.0).abs() < 1e-7, "{e1}");
    }

    /// The linear law (n = 1) with damping proportional to δ δ̇ has no closed form, but the
    /// inversion must return the e asked for, and e must fall as χ grows.
    #[test]
    fn inversion_returns_the_restitution_asked_for() {
        for e in [0.05, 0.2, 0.5, 0.9, 0.99] {
            let chi = damping_factor(e, 1.5);
            assert!((restitution_of(chi, 1.5) - e).abs() < 1e-8, "e = {e}: χ = {chi}");
        }
        assert!(restitution_of(1.0, 1.5) > restitution_of(2.0, 1.5));
    }
}

//! A crease's hinge law as the sheet builder writes it (docs/flasher.md, *Thick panels*):
//! law 2 (Euler potential) about the fold axis, A's z axis; and for a thick panel's crease
//! whose edges meet at flat, the same springs as a `directional` law with an end stop at
//! flat on the side away from its stowed fold (the panels' edges meet there: a thick crease
//! with its axis off the mid-plane folds one way only).

/// The response of one kind of crease, the fold about A's z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseLaw {
    /// Stiffness of the three translations, N/m.
    pub k_translation: f64,
    /// Stiffness of the two rotations that are not the fold, N·m/rad.
    pub k_rotation: f64,
    /// Fold stiffness, N·m/rad (rest at the deployed design).
    pub k_fold: f64,
    /// Fold damping, N·m·s/rad.
    pub c_fold: f64,
    /// Damping of the translations, N·s/m.
    pub c_translation: f64,
    /// Damping of the two rotations that are not the fold, N·m·s/rad.
    pub c_rotation: f64,
    /// Stiffness of the stop at flat of a thick crease, N·m/rad (0: no stop).
    pub k_stop: f64,
}

/// The coefficient of restitution of thick panels meeting: face on face (the `[contact]`
/// table the flasher generator writes) and edge on edge at a crease's stop at flat.
pub const RESTITUTION: f64 = 0.3;

/// A fold at least this far from flat when stowed (rad) gets a stop at flat; a crease stowed
/// flat (the triangle model's diagonals) bends either way and gets none.
pub const LEAST_STOPPED_FOLD: f64 = 1e-3;

/// A crease's end stop at flat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoldStop {
    /// Stiffness beyond the stop, N·m/rad.
    pub stiffness: f64,
    /// Damping beyond the stop, N·m·s/rad.
    pub damping: f64,
    /// The fold is free above flat (its stowed fold is positive).
    pub free_above: bool,
}

impl FoldStop {
    /// A stop of `stiffness` (N·m/rad) for a fold stowed at `fold` (rad), damped so that two
    /// bodies of moments of inertia `inertia` (kg·m², each about the fold axis; `None`: a body
    /// that does not turn, the hub) meeting at it part with `RESTITUTION`: a linear
    /// spring and dashpot on the reduced inertia `I` parts after half a damped period with
    /// `e = exp(−πζ/√(1 − ζ²))`, so `ζ = −ln e / √(π² + ln² e)` and `c = 2ζ√(k I)` (the
    /// linear spring–dashpot's coefficient of restitution, contact ending where the spring's
    /// extension returns to zero: Schwager & Pöschel, Phys. Rev. E 78, 051304, 2008, §II).
    pub fn new(stiffness: f64, fold: f64, inertia: [Option<f64>; 2]) -> Self {
        let reduced = match inertia {
            [Some(a), Some(b)] => a * b / (a + b),
            [Some(a), None] | [None, Some(a)] => a,
            [None, None] => 0.0,
        };
        let log_e = RESTITUTION.ln();
        let zeta = -log_e / (std::f64::consts::PI.powi(2) + log_e * log_e).sqrt();
        Self { stiffness, damping: 2.0 * zeta * (stiffness * reduced).sqrt(), free_above: fold > 0.0 }
    }
}

impl CreaseLaw {
    /// The law's scenario text (`law = { ... }`), with `stop` as a directional law.
    pub fn text(&self, stop: Option<&FoldStop>) -> String {
        let l = self;
        match stop {
            None => format!(
                "law = {{ type = \"euler-potential\", k_f = {:e}, k_theta = [{:e}, {:e}, {:e}], c_f = {:e}, c_theta = [{:e}, {:e}, {:e}] }}",
                l.k_translation,
                l.k_rotation,
                l.k_rotation,
                l.k_fold,
                l.c_translation,
                l.c_rotation,
                l.c_rotation,
                l.c_fold
            ),
            Some(s) => {
                let t = format!("{{ k = {:e}, damping = {:e} }}", l.k_translation, l.c_translation);
                let r = format!("{{ k = {:e}, damping = {:e} }}", l.k_rotation, l.c_rotation);
                format!(
                    "law = {{ type = \"directional\", angles = \"euler\", x = {t}, y = {t}, z = {t}, rx = {r}, ry = {r}, rz = {{ k = {:e}, damping = {:e}, stop = {{ at_deg = 0.0, free = \"{}\", stiffness = {:e}, damping = {:e} }} }} }}",
                    l.k_fold,
                    l.c_fold,
                    if s.free_above { "above" } else { "below" },
                    s.stiffness,
                    s.damping
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Vec3};

    /// The damping gives the restitution asked for: a unit inertia on the stop's spring and
    /// dashpot, met at 1 rad/s, integrated finely until it parts (to 1e-6; classical Runge–Kutta's
    /// error at 3e4 steps per half period is below 1e-12, the crossing interpolated
    /// within its step to ~1e-8).
    #[test]
    fn stop_parts_with_the_restitution_asked_for() {
        for (k, i) in [(1e4, 0.05), (1e3, 2.0)] {
            let s = FoldStop::new(k, -1.0, [Some(2.0 * i), Some(2.0 * i)]);
            assert!(!s.free_above);
            // Beyond the stop: i ψ̈ = −k ψ − c ψ̇, from ψ = 0, ψ̇ = 1, until ψ is back at 0.
            let (mut psi, mut rate, h) = (0.0_f64, 1.0_f64, 1e-4 / (k / i).sqrt());
            let acc = |p: f64, r: f64| (-k * p - s.damping * r) / i;
            loop {
                // Classical Runge–Kutta.
                let (k1p, k1r) = (rate, acc(psi, rate));
                let (k2p, k2r) = (rate + 0.5 * h * k1r, acc(psi + 0.5 * h * k1p, rate + 0.5 * h * k1r));
                let (k3p, k3r) = (rate + 0.5 * h * k2r, acc(psi + 0.5 * h * k2p, rate + 0.5 * h * k2r));
                let (k4p, k4r) = (rate + h * k3r, acc(psi + h * k3p, rate + h * k3r));
                let (p0, r0) = (psi, rate);
                psi += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
                rate += h / 6.0 * (k1r + 2.0 * k2r + 2.0 * k3r + k4r);
                if psi < 0.0 {
                    // The rate where ψ crosses zero, linear within the step (error ~h²).
                    rate = r0 + (rate - r0) * p0 / (p0 - psi);
                    break;
                }
            }
            assert!((-rate - RESTITUTION).abs() < 1e-6, "k {k}, I {i}: parts at {}", -rate);
        }
    }

    /// A unit square plate of unit mass about its edge: m/3 (parallel axes from m/12).
    #[test]
    fn plate_about_its_edge() {
        let plate = crate::model::Shape::Plate {
            vertices: vec![
                Vec3::new(-0.5, -0.5, 0.0),
                Vec3::new(0.5, -0.5, 0.0),
                Vec3::new(0.5, 0.5, 0.0),
                Vec3::new(-0.5, 0.5, 0.0),
            ],
            thickness: 0.0,
        };
        let m = plate.mass_properties(1.0);
        let i = crate::math::inertia_about_line(
            m.mass,
            &m.inertia_about_centroid,
            (&Vec3::zeros(), &Mat3::identity()),
            &Vec3::new(0.5, 0.0, 0.0),
            &Vec3::y(),
        );
        assert!((i - 1.0 / 3.0).abs() < 1e-12, "{i}");
    }
}

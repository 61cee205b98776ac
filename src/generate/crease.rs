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
    /// A thick crease's membrane hinge (`None`: a pin on its axis).
    pub membrane: Option<Membrane>,
}

/// A membrane hinge: the panels of a thick crease bonded to a flexible membrane that spans a
/// gap of finite width at the fold line (Zirbel et al., "Accommodating thickness in
/// origami-based deployable arrays", J. Mech. Des. 135, 111005, 2013). The membrane lets the
/// two panels' edges move across the fold line (A0's x and y) while it is slack, resisting
/// only by its bending, and holds them once taut; along the fold line and in the two
/// rotations off the fold it is as stiff as a pin (docs/flasher.md, *Membrane hinges*).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Membrane {
    /// Bending stiffness per unit length of fold line, `D = E t³ / (12 (1 − ν²))`, N·m.
    pub bending: f64,
    /// Width of the membrane across the fold line: the relative travel of the panels' edges
    /// across it, each way, before it is taut, m.
    pub width: f64,
    /// Damping ratio of the panels' motion across the fold line while the membrane is slack
    /// (on the two panels' reduced mass).
    pub damping_ratio: f64,
}

impl Membrane {
    /// Stiffness across the fold line of a membrane strip of `length` (m, the crease's) while
    /// slack, N/m: a strip clamped to both panels and one edge moved sideways is a
    /// fixed–guided beam, `12 EI / w³` (small deflection; L. L. Howell, *Compliant
    /// Mechanisms*, Wiley 2001, §5.1, the fixed–guided segment), with `EI = D · length` for a
    /// plate strip in cylindrical bending.
    pub fn stiffness(&self, length: f64) -> f64 {
        12.0 * self.bending * length / self.width.powi(3)
    }

    /// One direction's response (`x` or `y`): the strip's stiffness `k_m` within ±width,
    /// damped at `damping_ratio` on the panels' reduced mass `mass` (kg: `c = 2ζ√(k_m m)`),
    /// and beyond it a stop whose spring is the hinge's translational one (`k_taut`: the
    /// membrane taut), free within the band (docs/hinge-laws.md, *stop*), damped so that the
    /// panels part from it with [`RESTITUTION`] ([`restitution_damping`] on `mass`), as at a
    /// crease's stop at flat: with the hinge's own translational damping (1e1 N·s/m, 0.5 % of
    /// critical on 1 kg at 1e6 N/m) the membranes of a thick flasher rang between slack and
    /// taut for the whole run (the 6 × 3's 5,939 stop events against 2,213).
    fn response(&self, length: f64, mass: f64, k_taut: f64) -> String {
        let k = self.stiffness(length);
        let damping = 2.0 * self.damping_ratio * (k * mass).sqrt();
        format!(
            "{{ k = {k:e}, damping = {damping:e}, stop = {{ at = 0.0, free = \"within\", band = {:e}, stiffness = {:e}, damping = {:e} }} }}",
            self.width,
            k_taut,
            restitution_damping(k_taut, mass)
        )
    }
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
    /// that does not turn, the hub) meeting at it part with `RESTITUTION`
    /// ([`restitution_damping`] on their reduced inertia).
    pub fn new(stiffness: f64, fold: f64, inertia: [Option<f64>; 2]) -> Self {
        let reduced = match inertia {
            [Some(a), Some(b)] => a * b / (a + b),
            [Some(a), None] | [None, Some(a)] => a,
            [None, None] => 0.0,
        };
        Self { stiffness, damping: restitution_damping(stiffness, reduced), free_above: fold > 0.0 }
    }
}

/// The damping (N·s/m, or N·m·s/rad for a rotation) of a linear spring of `stiffness` (N/m,
/// N·m/rad) on a reduced mass or inertia `reduced` (kg, kg·m²) that parts with
/// [`RESTITUTION`]: a linear spring and dashpot parts after half a damped period with
/// `e = exp(−πζ/√(1 − ζ²))`, so `ζ = −ln e / √(π² + ln² e)` and `c = 2ζ√(k m)` (the linear
/// spring–dashpot's coefficient of restitution, contact ending where the spring's extension
/// returns to zero: Schwager & Pöschel, Phys. Rev. E 78, 051304, 2008, §II).
pub fn restitution_damping(stiffness: f64, reduced: f64) -> f64 {
    let log_e = RESTITUTION.ln();
    let zeta = -log_e / (std::f64::consts::PI.powi(2) + log_e * log_e).sqrt();
    2.0 * zeta * (stiffness * reduced).sqrt()
}

impl CreaseLaw {
    /// The law's scenario text (`law = { ... }`): law 2, or with a `stop` or a membrane (across
    /// the fold line of a crease `length` m long, between panels of reduced mass `mass` kg) a
    /// directional law.
    pub fn text(&self, stop: Option<&FoldStop>, length: f64, mass: f64) -> String {
        let l = self;
        if stop.is_none() && l.membrane.is_none() {
            return format!(
                "law = {{ type = \"euler-potential\", k_f = {:e}, k_theta = [{:e}, {:e}, {:e}], c_f = {:e}, c_theta = [{:e}, {:e}, {:e}] }}",
                l.k_translation,
                l.k_rotation,
                l.k_rotation,
                l.k_fold,
                l.c_translation,
                l.c_rotation,
                l.c_rotation,
                l.c_fold
            );
        }
        let t = format!("{{ k = {:e}, damping = {:e} }}", l.k_translation, l.c_translation);
        let r = format!("{{ k = {:e}, damping = {:e} }}", l.k_rotation, l.c_rotation);
        let across = match &l.membrane {
            Some(m) => m.response(length, mass, l.k_translation),
            None => t.clone(),
        };
        let stop = match stop {
            Some(s) => format!(
                ", stop = {{ at_deg = 0.0, free = \"{}\", stiffness = {:e}, damping = {:e} }}",
                if s.free_above { "above" } else { "below" },
                s.stiffness,
                s.damping
            ),
            None => String::new(),
        };
        format!(
            "law = {{ type = \"directional\", angles = \"euler\", x = {across}, y = {across}, z = {t}, rx = {r}, ry = {r}, rz = {{ k = {:e}, damping = {:e}{stop} }} }}",
            l.k_fold, l.c_fold
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Vec3};

    /// The damping gives the restitution asked for: the reduced inertia (or mass) on the
    /// stop's spring and dashpot, met at 1 rad/s (m/s), integrated finely until it parts (to
    /// 1e-6; classical Runge–Kutta's error at 3e4 steps per half period is below 1e-12, the
    /// crossing interpolated within its step to ~1e-8). Two crease stops at flat, and a
    /// membrane's taut stop as the generator writes it (its damping read from the text).
    #[test]
    fn stop_parts_with_the_restitution_asked_for() {
        let m = Membrane { bending: 4.6e-4, width: 0.05, damping_ratio: 1.0 };
        let text = m.response(1.2, 0.7, 1e6);
        let taut = text.rsplit("damping = ").next().and_then(|d| d.trim_end_matches([' ', '}']).parse::<f64>().ok());
        let taut = taut.unwrap_or_else(|| panic!("no taut damping in {text}"));
        let stops = [(1e4, 0.05), (1e3, 2.0)].map(|(k, i)| {
            let s = FoldStop::new(k, -1.0, [Some(2.0 * i), Some(2.0 * i)]);
            assert!(!s.free_above);
            (k, i, s.damping)
        });
        for (k, i, damping) in stops.into_iter().chain([(1e6, 0.7, taut)]) {
            // Beyond the stop: i ψ̈ = −k ψ − c ψ̇, from ψ = 0, ψ̇ = 1, until ψ is back at 0.
            let (mut psi, mut rate, h) = (0.0_f64, 1.0_f64, 1e-4 / (k / i).sqrt());
            let acc = |p: f64, r: f64| (-k * p - damping * r) / i;
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

    /// A membrane crease's law, as the scenario loader reads it back: across the fold line
    /// (x, y) the strip's `12 D L / w³`, and beyond ±w the taut membrane's (the hinge's
    /// translational stiffness) besides, its energy the integral; along it (z) and in the rotations off the fold the pin's
    /// stiffness. To round-off (1e-9 relative: the table's points are written to 17 digits).
    #[test]
    fn a_membrane_crease_reads_back_as_its_strip_and_taut_membrane() {
        let m = Membrane { bending: 3e-5, width: 0.05, damping_ratio: 0.5 };
        let length = 1.5;
        let law = CreaseLaw {
            k_translation: 1e7,
            k_rotation: 1e4,
            k_fold: 0.2,
            c_fold: 1.0,
            c_translation: 100.0,
            c_rotation: 1.0,
            k_stop: 1e4,
            membrane: Some(m),
        };
        let stop = FoldStop::new(1e4, -1.0, [Some(0.1), None]);
        let text = format!(
            "[run]\nduration = 1.0\noutput_step = 0.1\nrtol = 1e-8\natol = 1e-8\n[[body]]\nname = \"hub\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n[[body]]\nname = \"p\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n[[hinge]]\nname = \"h\"\nparent = \"hub\"\nchild = \"p\"\na0 = {{ position = [1.0, 0.0, 0.0] }}\na = {{ child_com = [1.0, 0.0, 0.0] }}\n{}\n",
            law.text(Some(&stop), length, 2.0)
        );
        let s = crate::scenario::Scenario::from_toml(&text, "membrane").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let hinge_law = &s.model.hinges[0].law;
        let k = 12.0 * 3e-5 * length / 0.05_f64.powi(3);
        assert!((m.stiffness(length) - k).abs() < 1e-12 * k);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-9);
        for (axis, u, f, e) in [
            (0, 0.02, k * 0.02, 0.5 * k * 0.02 * 0.02),
            (1, -0.03, -k * 0.03, 0.5 * k * 0.03 * 0.03),
            (0, 0.07, k * 0.07 + 1e7 * 0.02, 0.5 * k * 0.07 * 0.07 + 0.5 * 1e7 * 0.02 * 0.02),
            (1, -0.06, -k * 0.06 - 1e7 * 0.01, 0.5 * k * 0.06 * 0.06 + 0.5 * 1e7 * 0.01 * 0.01),
            (2, 0.001, 1e7 * 0.001, 0.5 * 1e7 * 0.001 * 0.001),
        ] {
            let mut delta = Vec3::zeros();
            delta[axis] = u;
            let state = crate::law::HingeState::at(delta, crate::math::Euler321::default());
            // The memory as a run would hold it there (the taut stop in contact beyond ±w).
            let memory = hinge_law.initial_memory(&state);
            let w = hinge_law.wrench(&state, &memory);
            let v = hinge_law.stored_energy(&state, &memory);
            assert!(close(w.force_in_a0[axis], f), "axis {axis} at {u} m: {} N against {f}", w.force_in_a0[axis]);
            assert!(close(v, e), "axis {axis} at {u} m: {v} J against {e}");
        }
        // Off the fold: the pin's rotational stiffness (pitch 1e-3 rad: k θ to first order).
        let state =
            crate::law::HingeState::at(Vec3::zeros(), crate::math::Euler321 { yaw: 0.0, pitch: 1e-3, roll: 0.0 });
        let w = hinge_law.wrench(&state, &hinge_law.initial_memory(&state));
        assert!((w.torque_in_a.norm() - 10.0).abs() < 1e-4, "{}", w.torque_in_a);
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

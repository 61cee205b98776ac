//! What went wrong at a state: the body whose state or acceleration is not finite, or the
//! hinge whose load is, so that a run that cannot go on names them.

use super::Dynamics;
use crate::state::{BODY_STATE_LEN, BodyMotion, OMEGA, POS, QUAT, VEL};

impl Dynamics<'_> {
    /// The first non-finite quantity at state `y`, named: a body's state, a hinge's force or
    /// torque, or a body's acceleration (in that order, which is the order of cause). `None`
    /// if everything is finite.
    pub fn non_finite_cause(&self, y: &[f64]) -> Option<String> {
        let model = self.model();
        for (i, b) in model.bodies.iter().enumerate() {
            let s = &y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for (part, range) in [
                ("position", POS..POS + 3),
                ("attitude", QUAT..QUAT + 4),
                ("velocity", VEL..VEL + 3),
                ("angular velocity", OMEGA..OMEGA + 3),
            ] {
                if s[range].iter().any(|x| !x.is_finite()) {
                    return Some(format!("body '{}': its {part} is not finite", b.name));
                }
            }
        }
        let refs = self.theta_refs();
        let memories = self.memories();
        for (i, h) in model.hinges.iter().enumerate() {
            let (p, c) = (BodyMotion::from_state(y, h.parent), BodyMotion::from_state(y, h.child));
            let k = crate::kinematics::hinge_kinematics(h, &p, &c, &refs[i]);
            let w = h.law.wrench(&k.state, &memories[i]);
            let describe = |what: &str, v: &crate::math::Vec3, unit: &str| {
                format!(
                    "hinge '{}': its {what} is not finite ({:e}, {:e}, {:e} {unit}) at δ = ({:e}, {:e}, {:e}) m: a stiffness, damping or displacement too large for f64",
                    h.name, v.x, v.y, v.z, k.state.delta_in_a0.x, k.state.delta_in_a0.y, k.state.delta_in_a0.z
                )
            };
            if w.force_in_a0.iter().any(|x| !x.is_finite()) {
                return Some(describe("force", &w.force_in_a0, "N, A0 components"));
            }
            if w.torque_in_a.iter().any(|x| !x.is_finite()) {
                return Some(describe("torque", &w.torque_in_a, "N·m, A components"));
            }
        }
        drop((refs, memories));
        let dydt = self.uncounted_rhs(y);
        for (i, b) in model.bodies.iter().enumerate() {
            let d = &dydt[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            // Beyond 1e100 m/s² (or rad/s²) no step can follow the body (its squares overflow
            // the error norms): name the loads on it, which a user set, before its hinges.
            let loads: Vec<String> =
                model.loads.iter().filter(|l| l.body == i).map(|l| format!("'{}'", l.name)).collect();
            let largest = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            if !loads.is_empty() && largest >= 1e100 {
                return Some(format!(
                    "body '{}': its acceleration is {largest:.3e} (m/s² or rad/s²), beyond what a step can follow: the loads on it ({}) are too large for its mass {:e} kg and inertia",
                    b.name,
                    loads.join(", "),
                    b.mass
                ));
            }
            if d.iter().any(|x| !x.is_finite()) {
                return Some(format!(
                    "body '{}': its acceleration is not finite (mass {:e} kg, inertia {:e}, {:e}, {:e} kg·m²): the hinge loads on it are too large for its mass or inertia",
                    b.name,
                    b.mass,
                    b.inertia_in_body[(0, 0)],
                    b.inertia_in_body[(1, 1)],
                    b.inertia_in_body[(2, 2)]
                ));
            }
        }
        None
    }

    /// The body with the largest acceleration at `y` (linear, m/s², or angular times its
    /// largest hinge lever, whichever is larger), with a description: where a step that
    /// overflowed was heading.
    pub fn fastest_body(&self, y: &[f64]) -> Option<String> {
        let model = self.model();
        let dydt = self.uncounted_rhs(y);
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let (i, a, alpha) = (0..model.bodies.len())
            .map(|i| {
                let d = &dydt[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
                (i, norm(&d[VEL..VEL + 3]), norm(&d[OMEGA..OMEGA + 3]))
            })
            .max_by(|x, y| (x.1 + x.2).total_cmp(&(y.1 + y.2)))?;
        Some(format!("body '{}' accelerates fastest ({a:.3e} m/s², {alpha:.3e} rad/s²)", model.bodies[i].name))
    }

    /// The right-hand side at `y`, left out of the evaluation counts (a diagnosis is not
    /// part of the run).
    fn uncounted_rhs(&self, y: &[f64]) -> Vec<f64> {
        let counts = (self.evaluations.get(), self.constrained_evaluations.get());
        let mut dydt = vec![0.0; y.len()];
        self.rhs(y, &mut dydt);
        self.evaluations.set(counts.0);
        self.constrained_evaluations.set(counts.1);
        dydt
    }
}

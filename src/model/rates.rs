//! How fast each hinge direction can move: its law's stiffness and damping bounds against
//! the mobility of the two bodies at the hinge. The run's step budget, and the messages of a
//! run that cannot go on, come from these.

use super::Model;
use crate::law::directional::DIRECTION_NAMES;

/// The fastest direction of one hinge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HingeRate {
    /// Hinge index.
    pub hinge: usize,
    /// Direction: 0..3 = x, y, z (δ, A0 components); 3..6 = rx, ry, rz.
    pub direction: usize,
    /// `max(√(k μ), c μ)`, 1/s: the direction's natural angular frequency, or its damping
    /// rate if larger. An upper bound: explicit methods need steps of about 3 / rate.
    pub rate: f64,
    /// The law's stiffness bound there, N/m or N·m/rad.
    pub stiffness: f64,
    /// The law's damping bound there, N·s/m or N·m·s/rad.
    pub damping: f64,
    /// Mobility of the two bodies in that direction at the hinge, 1/kg or 1/(kg·m²): for a
    /// translation `1/m + d²/I_min` of each body (d its CoM's distance from the hinge frame),
    /// for a rotation `1/I_min` of each, summed over the two.
    pub mobility: f64,
}

impl HingeRate {
    /// "hinge 'h2' direction x (stiffness 1e6 N/m on 0.5 kg: period 4.4e-3 s)".
    pub fn describe(&self, model: &Model) -> String {
        let rotational = self.direction >= 3;
        let (k, c, m) = if rotational { ("N·m/rad", "N·m·s/rad", "kg·m²") } else { ("N/m", "N·s/m", "kg") };
        let natural = (self.stiffness * self.mobility).sqrt();
        let what = if natural >= self.damping * self.mobility {
            format!(
                "stiffness {:.3e} {k} against an effective {:.3e} {m}: period {:.3e} s",
                self.stiffness,
                1.0 / self.mobility,
                2.0 * std::f64::consts::PI / natural
            )
        } else {
            format!(
                "damping {:.3e} {c} against an effective {:.3e} {m}: time constant {:.3e} s",
                self.damping,
                1.0 / self.mobility,
                1.0 / (self.damping * self.mobility)
            )
        };
        format!("hinge '{}' direction {} ({what})", model.hinges[self.hinge].name, DIRECTION_NAMES[self.direction])
    }
}

impl Model {
    /// Per hinge, its fastest direction (see [`HingeRate`]), in hinge order.
    pub fn hinge_rates(&self) -> Vec<HingeRate> {
        let smallest_inertia = |b: usize| {
            let e = self.bodies[b].inertia_in_body.symmetric_eigenvalues();
            e.min()
        };
        self.hinges
            .iter()
            .enumerate()
            .map(|(i, h)| {
                let (p, c) = (&self.bodies[h.parent], &self.bodies[h.child]);
                let (ip, ic) = (smallest_inertia(h.parent), smallest_inertia(h.child));
                let translation = 1.0 / p.mass
                    + h.r_a0_in_parent.norm_squared() / ip
                    + 1.0 / c.mass
                    + h.r_a_in_child.norm_squared() / ic;
                let rotation = 1.0 / ip + 1.0 / ic;
                h.law
                    .stiffness_bounds()
                    .iter()
                    .enumerate()
                    .map(|(d, b)| {
                        let mobility = if d < 3 { translation } else { rotation };
                        let rate = (b.stiffness * mobility).sqrt().max(b.damping * mobility);
                        HingeRate { hinge: i, direction: d, rate, stiffness: b.stiffness, damping: b.damping, mobility }
                    })
                    .max_by(|a, b| a.rate.total_cmp(&b.rate))
                    .expect("six directions")
            })
            .collect()
    }

    /// The fastest hinge direction of the structure, if it has hinges.
    pub fn fastest_hinge(&self) -> Option<HingeRate> {
        self.hinge_rates().into_iter().max_by(|a, b| a.rate.total_cmp(&b.rate))
    }
}

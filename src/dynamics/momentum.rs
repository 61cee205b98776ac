//! The structure's momenta, and their restoration after steps of integrators that conserve
//! them only to their tolerance.

use super::Dynamics;
use crate::math::{Mat3, Vec3};
use crate::state::{BODY_STATE_LEN, BodyMotion, OMEGA, POS, VEL};

impl Dynamics<'_> {
    /// Total linear momentum (kg·m/s) and angular momentum about N's origin (kg·m²/s), N
    /// components, of state `y`, the reaction wheels' spin momenta included.
    pub fn momenta(&self, y: &[f64]) -> (Vec3, Vec3) {
        let (p, h, _) = self.momenta_and_scales(y);
        (p, h)
    }

    /// [`Self::momenta`] and the scales the run report measures their drift against,
    /// `Σ m_i |Ṙ_i|` and `Σ (|R_i × m_i Ṙ_i| + |I_i ω_i|)` with the wheels' `|h|` (as
    /// `Observation::momentum_scale` and `angular_momentum_scale`), in one pass.
    fn momenta_and_scales(&self, y: &[f64]) -> (Vec3, Vec3, [f64; 2]) {
        let (mut p, mut h, mut scales) = (Vec3::zeros(), Vec3::zeros(), [0.0; 2]);
        for (i, b) in self.model.bodies.iter().enumerate() {
            let m = BodyMotion::from_state(y, i).momenta(b.mass, &b.inertia_in_body);
            p += m.linear;
            h += m.orbital + m.spin;
            scales[0] += m.linear.norm();
            scales[1] += m.orbital.norm() + m.spin.norm();
        }
        if let Some(c) = &self.model.control {
            let w = crate::state::wheel_index(self.model);
            let spin = BodyMotion::from_state(y, 0).dcm_n_b * c.wheel_momentum_in_hub(&y[w..w + c.wheels().len()]);
            h += spin;
            scales[1] += spin.norm();
        }
        (p, h, scales)
    }

    /// How far the momenta of `y` are from `(p0, h0)` (kg·m/s, kg·m²/s, N components, as
    /// [`Self::momenta`] gives them): `(|P − P0|, |H − H0|)`, with the scales the run report
    /// measures drift against at `y` (see `momenta_and_scales`).
    pub fn momentum_drift(&self, y: &[f64], p0: &Vec3, h0: &Vec3) -> ([f64; 2], [f64; 2]) {
        let (p, h, scales) = self.momenta_and_scales(y);
        ([(p - p0).norm(), (h - h0).norm()], scales)
    }

    /// Restores total linear and angular momentum to `(p0, h0)` by adding one rigid-body
    /// velocity field to every body (a uniform velocity and a rotation about the
    /// barycenter): the smallest mass-weighted correction, and one that leaves every hinge's
    /// relative velocities unchanged, so the internal motion is untouched. For integrators
    /// that conserve momentum only to their tolerance (the implicit path). Returns the size
    /// of the correction relative to the momenta's scale.
    pub fn restore_momentum(&self, y: &mut [f64], p0: &Vec3, h0: &Vec3) -> f64 {
        let model = self.model;
        let total: f64 = model.total_mass();
        let (p, _) = self.momenta(y);
        let dv = -(p - p0) / total;
        let mut c = Vec3::zeros();
        for (i, b) in model.bodies.iter().enumerate() {
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for k in 0..3 {
                s[VEL + k] += dv[k];
            }
            c += Vec3::new(s[POS], s[POS + 1], s[POS + 2]) * b.mass;
        }
        c /= total;
        let (_, h) = self.momenta(y);
        // Inertia of the whole structure about its barycenter, N components.
        let mut inertia = Mat3::zeros();
        for (i, b) in model.bodies.iter().enumerate() {
            let m = BodyMotion::from_state(y, i);
            let r = m.r_in_n - c;
            inertia += m.dcm_n_b * b.inertia_in_body * m.dcm_n_b.transpose()
                + (Mat3::identity() * r.norm_squared() - r * r.transpose()) * b.mass;
        }
        let Some(inv) = inertia.try_inverse() else { return 0.0 };
        let dw = -(inv * (h - h0));
        for i in 0..model.bodies.len() {
            let m = BodyMotion::from_state(y, i);
            let r = m.r_in_n - c;
            let dv_i = dw.cross(&r);
            let dw_b = m.dcm_n_b.transpose() * dw;
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for k in 0..3 {
                s[VEL + k] += dv_i[k];
                s[OMEGA + k] += dw_b[k];
            }
        }
        let scale = (p0.norm() + h0.norm()).max(1e-300);
        (dv.norm() * total + (inertia * dw).norm()) / scale
    }

    /// Angular momentum about the barycenter, kg·m²/s, N components: `H − R_c × P`.
    pub fn momentum_about_barycenter(&self, y: &[f64]) -> Vec3 {
        let (p, h) = self.momenta(y);
        let model = self.model;
        let rc =
            (0..model.bodies.len()).map(|i| BodyMotion::from_state(y, i).r_in_n * model.bodies[i].mass).sum::<Vec3>()
                / model.total_mass();
        h - rc.cross(&p)
    }
}

//! A rigid body's mass properties (docs/model.md §2).

use super::shape::Shape;
use crate::math::Mat3;

/// A rigid body (docs/model.md §2). Body 0 is the hub.
#[derive(Clone, Debug)]
pub struct Body {
    /// Unique name, used for output columns.
    pub name: String,
    /// Mass, kg (> 0).
    pub mass: f64,
    /// Inertia tensor about the CoM in the body frame, kg·m² (symmetric positive definite,
    /// triangle inequalities hold).
    pub inertia_in_body: Mat3,
    /// Inverse of `inertia_in_body`, 1/(kg·m²).
    pub(crate) inertia_inv_in_body: Mat3,
    /// Its geometry, if given (body frame; for display and contact: the dynamics use the
    /// mass and inertia alone).
    pub shape: Option<Shape>,
}

impl Body {
    /// Takes the reaction wheels' spin inertia `Σ J_s g gᵀ` (kg·m², body frame) out of this
    /// body's inertia (crate::loads::control: the wheels' spin momenta are states of their
    /// own). Fails, saying by how much, unless what is left is positive definite.
    pub fn remove_spin_inertia(&mut self, spin: &Mat3) -> Result<(), String> {
        let left = self.inertia_in_body - spin;
        let eig = left.symmetric_eigenvalues();
        let least = eig.min();
        match left.try_inverse() {
            Some(inv) if least > 1e-9 * self.inertia_in_body.abs().max() => {
                self.inertia_in_body = left;
                self.inertia_inv_in_body = inv;
                Ok(())
            }
            _ => Err(format!(
                "body '{}': its inertia less the wheels' spin inertias Σ J_s g gᵀ is not positive definite (least principal value {least:.6e} kg·m²): the hub's inertia must include its wheels, and each wheel's J_s be smaller than it",
                self.name
            )),
        }
    }

    /// A body, checked: mass > 0 and finite; inertia finite, symmetric (to 1e-12 relative),
    /// positive definite and satisfying the triangle inequalities of its principal values.
    pub fn new(name: &str, mass: f64, inertia_in_body: Mat3) -> Result<Self, String> {
        if !(mass.is_finite() && mass > 0.0) {
            return Err(format!(
                "body '{name}': mass must be a finite number > 0 kg, got {}",
                crate::math::short(mass)
            ));
        }
        if inertia_in_body.iter().any(|x| !x.is_finite()) {
            return Err(format!("body '{name}': inertia has a non-finite entry"));
        }
        let scale = inertia_in_body.abs().max();
        let asym = (inertia_in_body - inertia_in_body.transpose()).abs().max();
        if asym > 1e-12 * scale {
            return Err(format!(
                "body '{name}': inertia tensor is not symmetric (largest |I_ij − I_ji| = {asym:e} kg·m²)"
            ));
        }
        let sym = inertia_in_body * 0.5 + inertia_in_body.transpose() * 0.5;
        // Eigenvalues of the tensor scaled to unit size (entries near ±1e308 overflow the
        // solver to NaN, which no comparison refuses), scaled back.
        let eig = if scale > 0.0 { (sym / scale).symmetric_eigenvalues() * scale } else { sym.symmetric_eigenvalues() };
        let mut p = [eig[0], eig[1], eig[2]];
        p.sort_by(f64::total_cmp);
        if !(p.iter().all(|x| x.is_finite()) && p[0] > 0.0) {
            return Err(format!(
                "body '{name}': inertia must be positive definite; principal values are {:.6e}, {:.6e}, {:.6e} kg·m²",
                p[0], p[1], p[2]
            ));
        }
        // Triangle inequality: the largest principal value may not exceed the sum of the
        // other two (a thin plate reaches equality); allow rounding of the input.
        if p[2] > (p[0] + p[1]) * (1.0 + 1e-9) {
            return Err(format!(
                "body '{name}': principal inertias {:.6e}, {:.6e}, {:.6e} kg·m² violate the triangle inequality (the largest must not exceed the sum of the other two)",
                p[0], p[1], p[2]
            ));
        }
        let inertia_inv_in_body =
            sym.try_inverse().ok_or_else(|| format!("body '{name}': inertia tensor is singular"))?;
        Ok(Self { name: name.to_string(), mass, inertia_in_body: sym, inertia_inv_in_body, shape: None })
    }

    /// The body with its geometry (which its mass and inertia should match; the scenario
    /// reader checks that they do).
    pub fn with_shape(mut self, shape: Shape) -> Self {
        self.shape = Some(shape);
        self
    }
}

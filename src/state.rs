//! The integrated state: every body's pose and twist in maximal coordinates (docs/architecture.md).
//!
//! Layout per body, [`BODY_STATE_LEN`] numbers from `BODY_STATE_LEN · i`:
//! `R_i` (m, N components, 3), `q_n_i` (unit quaternion w, x, y, z mapping body to N
//! components, 4), `Ṙ_i` (m/s, N components, 3), `ω_{i/N}` (rad/s, body components, 3).

use crate::math::{Mat3, Real, Vec3, dcm_from_quat, mat_vec, quat_from_dcm};
use crate::model::Model;
use nalgebra::{Matrix3, Vector3};

/// Numbers per body in the state vector.
pub const BODY_STATE_LEN: usize = 13;
/// Offset of `R_i` within a body's block.
pub const POS: usize = 0;
/// Offset of the quaternion `q_n_i`.
pub const QUAT: usize = 3;
/// Offset of `Ṙ_i`.
pub const VEL: usize = 7;
/// Offset of `ω_{i/N}` in body components.
pub const OMEGA: usize = 10;

/// The flat state vector integrated in time.
pub type State = Vec<f64>;

/// Pose and twist of one body, everything resolved (f64, or dual numbers for the Jacobian).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMotion<T: nalgebra::Scalar = f64> {
    /// CoM position `R_i`, m, N components.
    pub r_in_n: Vector3<T>,
    /// `[N i]`.
    pub dcm_n_b: Matrix3<T>,
    /// CoM velocity `Ṙ_i`, m/s, N components.
    pub v_in_n: Vector3<T>,
    /// `ω_{i/N}`, rad/s, N components.
    pub omega_in_n: Vector3<T>,
}

impl Default for BodyMotion {
    fn default() -> Self {
        Self { r_in_n: Vec3::zeros(), dcm_n_b: Mat3::identity(), v_in_n: Vec3::zeros(), omega_in_n: Vec3::zeros() }
    }
}

impl BodyMotion {
    /// Reads body `i` from a state vector (the quaternion is normalized).
    #[inline]
    pub fn from_state(y: &[f64], i: usize) -> Self {
        Self::from_body_state(&y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)])
    }

    /// This body's momenta, N components, for a body of `mass` (kg) and central inertia
    /// `inertia_in_body` (kg·m², body components): the linear momentum `m Ṙ` (kg·m/s), its
    /// moment about N's origin `R × m Ṙ` and the spin `I ω` (kg·m²/s). The one place the
    /// momenta's terms are formed, for their totals and for the scales their drift is
    /// measured against.
    pub fn momenta(&self, mass: f64, inertia_in_body: &Mat3) -> BodyMomenta {
        let linear = self.v_in_n * mass;
        BodyMomenta {
            linear,
            orbital: self.r_in_n.cross(&linear),
            spin: self.dcm_n_b * (inertia_in_body * self.omega_in_body()),
        }
    }
}

/// One body's momenta, N components ([`BodyMotion::momenta`]).
#[derive(Clone, Copy, Debug)]
pub struct BodyMomenta {
    /// `m Ṙ`, kg·m/s.
    pub linear: Vec3,
    /// `R × m Ṙ`, about N's origin, kg·m²/s.
    pub orbital: Vec3,
    /// `I ω`, kg·m²/s.
    pub spin: Vec3,
}

impl<T: Real> BodyMotion<T> {
    /// From one body's [`BODY_STATE_LEN`] state numbers (the quaternion is normalized).
    #[inline]
    pub fn from_body_state(s: &[T]) -> Self {
        let dcm_n_b = dcm_from_quat(&s[QUAT..QUAT + 4]);
        let omega_in_b = Vector3::new(s[OMEGA], s[OMEGA + 1], s[OMEGA + 2]);
        Self {
            r_in_n: Vector3::new(s[POS], s[POS + 1], s[POS + 2]),
            dcm_n_b,
            v_in_n: Vector3::new(s[VEL], s[VEL + 1], s[VEL + 2]),
            omega_in_n: mat_vec(&dcm_n_b, &omega_in_b),
        }
    }

    /// `ω_{i/N}` in body components, rad/s.
    pub fn omega_in_body(&self) -> Vector3<T> {
        self.dcm_n_b.transpose() * self.omega_in_n
    }
}

/// Index in the state vector of the work W (then the other [`crate::model::LOAD_STATES`]),
/// if the model has it.
pub fn work_index(model: &Model) -> Option<usize> {
    model.work_offset().map(|o| BODY_STATE_LEN * model.bodies.len() + o)
}

/// Index in the state vector of the first reaction wheel's spin momentum (the others follow).
pub fn wheel_index(model: &Model) -> usize {
    BODY_STATE_LEN * model.bodies.len() + model.wheel_offset()
}

/// Builds the state vector from body motions (model order).
pub fn state_from_motions(model: &Model, motions: &[BodyMotion]) -> State {
    let mut y = vec![0.0; BODY_STATE_LEN * model.bodies.len()];
    for (i, m) in motions.iter().enumerate() {
        let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
        s[POS..POS + 3].copy_from_slice(m.r_in_n.as_slice());
        s[QUAT..QUAT + 4].copy_from_slice(&quat_from_dcm(&m.dcm_n_b));
        s[VEL..VEL + 3].copy_from_slice(m.v_in_n.as_slice());
        s[OMEGA..OMEGA + 3].copy_from_slice(m.omega_in_body().as_slice());
    }
    y
}

impl<T: Real> BodyMotion<T> {
    /// The body's pose and velocity as contact takes them ([`crate::contact::Frame`]).
    pub fn contact_frame(&self) -> crate::contact::Frame<T> {
        crate::contact::Frame {
            position_in_n: self.r_in_n,
            dcm_n_b: self.dcm_n_b,
            velocity_in_n: self.v_in_n,
            omega_in_n: self.omega_in_n,
        }
    }
}

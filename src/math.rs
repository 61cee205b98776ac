//! Rotation conventions of docs/model.md §1: elementary rotations, 3-2-1 Euler angles, their rate
//! matrix, and quaternion helpers.
//!
//! A direction cosine matrix `[XY]` (named `dcm_x_y` in code) maps Y-frame components to
//! X-frame components: `ˣv = [XY] ʸv`.

use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// 3-vector of f64, SI units; the frame is named by the variable.
pub type Vec3 = Vector3<f64>;
/// 3×3 matrix of f64; a DCM `[XY]` or an inertia tensor, as the name says.
pub type Mat3 = Matrix3<f64>;

/// The scalars the kinematics and the hinge laws are written for: `f64` on the right-hand
/// side, dual numbers (`num_dual`) when the implicit path forms its Jacobian.
pub trait Real: nalgebra::RealField + Copy {}
impl<T: nalgebra::RealField + Copy> Real for T {}

/// `x` as a [`Real`].
#[inline]
pub fn real<T: Real>(x: f64) -> T {
    nalgebra::convert(x)
}

/// The real part of a [`Real`] (the value itself for f64).
#[inline]
pub fn re<T: Real>(x: T) -> f64 {
    nalgebra::convert_unchecked::<T, f64>(x)
}

/// Four-quadrant arctangent of `y / x`, rad, whose derivative is right wherever
/// `(x, y) ≠ 0`: `d atan2 = (x dy − y dx) / (x² + y²)`.
///
/// `num_dual`'s own `atan2` differentiates `atan(y / x)`, which is 0/0 where `x` is exactly
/// zero: a hinge angle at exactly ±90° (yaw or roll) with an exactly zero DCM entry, as
/// quaternion products give for frames rolled by multiples of 45°, made every quaternion
/// column of the exact Jacobian NaN. The value is f64's `atan2` to the bit (for f64 the
/// derivative term is `y x − x y`, exactly zero).
#[inline]
pub fn atan2<T: Real>(y: T, x: T) -> T {
    // f64 needs no derivative: its own atan2 (the test below folds away when monomorphized).
    if let (Some(yf), Some(xf)) =
        ((&y as &dyn std::any::Any).downcast_ref::<f64>(), (&x as &dyn std::any::Any).downcast_ref::<f64>())
    {
        return real(yf.atan2(*xf));
    }
    let (yr, xr) = (re(y), re(x));
    let value = yr.atan2(xr);
    let r2 = xr * xr + yr * yr;
    if r2 == 0.0 {
        // Undefined at the origin; only the value is given.
        return real(value);
    }
    (y * real::<T>(xr) - x * real::<T>(yr)) * real::<T>(1.0 / r2) + real::<T>(value)
}

/// A matrix of f64 as a matrix of [`Real`]s.
#[inline]
pub fn lift<T: Real>(m: &Mat3) -> Matrix3<T> {
    m.map(real)
}

/// A number as messages print it: short (`1e300`, `2.5`, `-1e-12`), never the 300 digits
/// that `{}` gives a large `f64`.
pub fn short(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e15).contains(&x.abs()) { format!("{x:e}") } else { format!("{x}") }
}

/// Elementary rotation about axis 1 by `a` rad (docs/model.md §1).
pub fn m1(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c)
}

/// Elementary rotation about axis 2 by `a` rad (docs/model.md §1).
pub fn m2(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c)
}

/// Elementary rotation about axis 3 by `a` rad (docs/model.md §1).
pub fn m3(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0)
}

/// 3-2-1 Euler angles `(yaw θ1, pitch θ2, roll θ3)` in rad.
///
/// `[XY] = M1(θ3) · M2(θ2) · M3(θ1)` (docs/model.md §1).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Euler321<T = f64> {
    /// θ1, rotation about axis 3, rad.
    pub yaw: T,
    /// θ2, rotation about the new axis 2, rad.
    pub pitch: T,
    /// θ3, rotation about the newest axis 1, rad.
    pub roll: T,
}

impl<T: Real> Euler321<T> {
    /// Principal 3-2-1 angles of a DCM `[XY]`: yaw and roll in (−π, π], pitch in [−π/2, π/2]
    /// (docs/model.md §7).
    pub fn from_dcm(dcm: &Matrix3<T>) -> Self {
        let one = T::one();
        let s = dcm[(0, 2)];
        let s = if s > one {
            one
        } else if s < -one {
            -one
        } else {
            s
        };
        Self { yaw: atan2(dcm[(0, 1)], dcm[(0, 0)]), pitch: -s.asin(), roll: atan2(dcm[(1, 2)], dcm[(2, 2)]) }
    }

    /// These angles with yaw and roll moved by whole turns to lie nearest `reference`
    /// (continuous tracking of docs/model.md §7). Pitch is left as it is.
    pub fn unwrapped_near(self, reference: &Euler321) -> Self {
        let turns = |angle: T, reference: f64| real::<T>(2.0 * PI * ((reference - re(angle)) / (2.0 * PI)).round());
        Self {
            yaw: self.yaw + turns(self.yaw, reference.yaw),
            pitch: self.pitch,
            roll: self.roll + turns(self.roll, reference.roll),
        }
    }

    /// The paper's torque-ordered vector `φ = [θ3, θ2, θ1]` = (roll, pitch, yaw), rad
    /// (docs/model.md §4, paper eq. 15b).
    pub fn phi(self) -> Vector3<T> {
        Vector3::new(self.roll, self.pitch, self.yaw)
    }

    /// As a vector `[yaw, pitch, roll]` = `[θ1, θ2, θ3]`, rad.
    pub fn as_vector(self) -> Vector3<T> {
        Vector3::new(self.yaw, self.pitch, self.roll)
    }
}

impl Euler321 {
    /// 3-2-1 angles of an attitude DCM `[X N]` that are right at every attitude, for output.
    /// Pitch is `atan2(−C₀₂, √(C₀₀² + C₀₁²))` (exact near ±90°, where `asin` loses half its
    /// digits). At pitch ±90° (gimbal lock: `cos θ2` below 1e-8) yaw and roll are not
    /// separately defined, only `θ3 ∓ θ1` is: roll is taken as `roll_hint` (0, or the previous
    /// value for continuity) and yaw from the second row, where `C₁₀ = sin(θ3 − θ1)`,
    /// `C₁₁ = cos(θ3 − θ1)` at +90° and `C₁₀ = −sin(θ3 + θ1)`, `C₁₁ = cos(θ3 + θ1)` at −90°
    /// (Schaub & Junkins, *Analytical Mechanics of Space Systems*, §3.3, the 3-2-1 DCM).
    /// Away from the lock the angles are [`Euler321::from_dcm`]'s. The threshold balances the
    /// two errors: `ε/cos θ2` of the general formula and `cos θ2` of the lock formula, both
    /// about 1e-8 rad there.
    pub fn attitude_from_dcm(dcm: &Mat3, roll_hint: f64) -> Euler321 {
        let c2 = dcm[(0, 0)].hypot(dcm[(0, 1)]);
        let pitch = (-dcm[(0, 2)]).atan2(c2);
        if c2 >= 1e-8 {
            let e = Euler321::from_dcm(dcm);
            return Euler321 { pitch, ..e };
        }
        let (s, c) = (dcm[(1, 0)], dcm[(1, 1)]);
        let yaw = if pitch > 0.0 { roll_hint - s.atan2(c) } else { (-s).atan2(c) - roll_hint };
        Euler321 { yaw: unwrap_near(yaw, 0.0), pitch, roll: roll_hint }
    }

    /// Angles from yaw, pitch, roll in rad.
    pub fn new(yaw: f64, pitch: f64, roll: f64) -> Self {
        Self { yaw, pitch, roll }
    }

    /// The DCM `[XY]` of frame X relative to frame Y for these angles.
    pub fn to_dcm(self) -> Mat3 {
        // Closed form of M1(roll) M2(pitch) M3(yaw).
        let (s1, c1) = self.yaw.sin_cos();
        let (s2, c2) = self.pitch.sin_cos();
        let (s3, c3) = self.roll.sin_cos();
        Mat3::new(
            c2 * c1,
            c2 * s1,
            -s2,
            s3 * s2 * c1 - c3 * s1,
            s3 * s2 * s1 + c3 * c1,
            s3 * c2,
            c3 * s2 * c1 + s3 * s1,
            c3 * s2 * s1 - s3 * c1,
            c3 * c2,
        )
    }

    /// Sines and cosines of pitch and roll.
    pub fn trig(self) -> EulerTrig {
        EulerTrig::from_angles(&self)
    }

    /// Euler-rate matrix `B(θ)`: `ω = B(θ) θ̇`, ω of X relative to Y in X components
    /// (docs/model.md §1).
    pub fn rate_matrix(self) -> Mat3 {
        self.trig().rate_matrix()
    }

    /// Solves `B(θ)ᵀ τ = g` for τ in closed form (see [`EulerTrig::torque_from_generalized`]).
    pub fn torque_from_generalized(self, g: &Vec3) -> Vec3 {
        self.trig().torque_from_generalized(g)
    }

    /// Euler-angle rates `θ̇ = B(θ)⁻¹ ω` (see [`EulerTrig::rates_from_omega`]).
    pub fn rates_from_omega(self, omega: &Vec3) -> Vec3 {
        self.trig().rates_from_omega(omega)
    }

    /// Whether pitch is within `margin` rad of ±π/2, where every 3-2-1 law is singular.
    pub fn near_gimbal_lock(self, margin: f64) -> bool {
        self.pitch.abs() > PI / 2.0 - margin
    }
}

/// Sines and cosines of the 3-2-1 pitch θ2 and roll θ3: all that the Euler-rate matrix
/// `B(θ)` depends on. Read straight from the DCM when the angles come from one (no
/// trigonometric calls on the right-hand side's hot path).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerTrig<T = f64> {
    /// sin θ2.
    pub s2: T,
    /// cos θ2 (≥ 0: pitch lies in [−π/2, π/2]).
    pub c2: T,
    /// sin θ3.
    pub s3: T,
    /// cos θ3.
    pub c3: T,
}

impl Default for EulerTrig {
    fn default() -> Self {
        Self { s2: 0.0, c2: 1.0, s3: 0.0, c3: 1.0 }
    }
}

impl EulerTrig {
    /// From the angles.
    pub fn from_angles(theta: &Euler321) -> Self {
        let (s2, c2) = theta.pitch.sin_cos();
        let (s3, c3) = theta.roll.sin_cos();
        Self { s2, c2, s3, c3 }
    }
}

impl<T: Real> EulerTrig<T> {
    /// From the DCM `[XY] = M1(θ3) M2(θ2) M3(θ1)` whose angles [`Euler321::from_dcm`] gives
    /// (row 0 = (c2 c1, c2 s1, −s2), elements (1, 2) = s3 c2 and (2, 2) = c3 c2). Equal to
    /// [`Self::from_angles`] of those angles to round-off; roll's whole turns do not matter.
    pub fn from_dcm(dcm: &Matrix3<T>) -> Self {
        let one = T::one();
        let s = dcm[(0, 2)];
        let s2 = -(if s > one {
            one
        } else if s < -one {
            -one
        } else {
            s
        });
        // Elements of a DCM are at most 1 in size: no overflow to guard against (`hypot`
        // would cost as much as the sin_cos this replaces).
        let c2 = (dcm[(0, 0)] * dcm[(0, 0)] + dcm[(0, 1)] * dcm[(0, 1)]).sqrt();
        let r = (dcm[(1, 2)] * dcm[(1, 2)] + dcm[(2, 2)] * dcm[(2, 2)]).sqrt();
        if r > T::zero() {
            Self { s2, c2, s3: dcm[(1, 2)] / r, c3: dcm[(2, 2)] / r }
        } else {
            // Pitch ±π/2 exactly: roll is undefined, and so is every law there.
            Self { s2, c2, s3: T::zero(), c3: one }
        }
    }

    /// Euler-rate matrix `B(θ)`: `ω = B(θ) θ̇`, ω of X relative to Y in X components
    /// (docs/model.md §1).
    pub fn rate_matrix(&self) -> Matrix3<T> {
        let Self { s2, c2, s3, c3 } = *self;
        let (zero, one) = (T::zero(), T::one());
        Matrix3::new(-s2, zero, one, s3 * c2, c3, zero, c3 * c2, -s3, zero)
    }

    /// Solves `B(θ)ᵀ τ = g` for τ in closed form. `g` is a generalized force on `θ = [θ1, θ2,
    /// θ3]`; τ is the torque (X components) whose virtual work on ω equals `g · δθ`.
    /// Singular at pitch ±π/2, where the result is not finite.
    pub fn torque_from_generalized(&self, g: &Vector3<T>) -> Vector3<T> {
        let Self { s2, c2, s3, c3 } = *self;
        // Bᵀ = [[−s2, s3 c2, c3 c2], [0, c3, −s3], [1, 0, 0]].
        let t1 = g.z;
        let h = (g.x + s2 * g.z) / c2; // = s3 τ2 + c3 τ3
        let t2 = c3 * g.y + s3 * h;
        let t3 = -s3 * g.y + c3 * h;
        Vector3::new(t1, t2, t3)
    }

    /// Euler-angle rates `θ̇ = B(θ)⁻¹ ω` for ω of X relative to Y in X components, rad/s
    /// (docs/model.md §1). Singular at pitch ±π/2.
    pub fn rates_from_omega(&self, omega: &Vector3<T>) -> Vector3<T> {
        let Self { s2, c2, s3, c3 } = *self;
        let yaw_rate = (s3 * omega.y + c3 * omega.z) / c2;
        Vector3::new(yaw_rate, c3 * omega.y - s3 * omega.z, omega.x + s2 * yaw_rate)
    }
}

/// Rotation vector `r` (axis × angle, rad, |r| ≤ π) of the DCM `[X Y]`: frame X is frame Y
/// turned by |r| about r, so `[Y X] = exp([r×])`; r has the same components in X and Y.
pub fn rotation_vector<T: Real>(dcm_x_y: &Matrix3<T>) -> Vector3<T> {
    let rot = nalgebra::Rotation3::from_matrix_unchecked(dcm_x_y.transpose());
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(&rot);
    let (w, v) = (q.w, q.imag());
    let (w, v) = if w < T::zero() { (-w, -v) } else { (w, v) };
    let sin_half = v.norm();
    let two: T = real(2.0);
    if sin_half < real(1e-12) {
        // angle/sin(angle/2) → 2 as the angle → 0.
        return v * two;
    }
    let angle = two * atan2(sin_half, w);
    v * (angle / sin_half)
}

/// Inverse of the right Jacobian of SO(3) at r: `ṙ = J_r(r)⁻¹ ω`, with ω the angular velocity
/// of X relative to Y in X components for `[Y X] = exp([r×])`. Finite for |r| < 2π; its
/// transpose maps a generalized force on r to the torque that does the same virtual work.
pub fn rotation_vector_rate_matrix_inverse<T: Real>(r: &Vector3<T>) -> Matrix3<T> {
    // |r|² rather than |r| near 0, so that dual numbers differentiate through r = 0.
    let angle2 = r.norm_squared();
    let k = skew(r);
    let one = T::one();
    let c = if angle2 < real(1e-8) {
        // 1/θ² − (1 + cos θ)/(2θ sin θ) = 1/12 + θ²/720 + …
        real::<T>(1.0 / 12.0) + angle2 / real(720.0)
    } else {
        let angle = angle2.sqrt();
        one / angle2 - (one + angle.cos()) / (real::<T>(2.0) * angle * angle.sin())
    };
    Matrix3::identity() + k * real::<T>(0.5) + k * k * c
}

/// `angle + 2πk` for the integer k that brings it nearest `reference`, rad.
pub fn unwrap_near(angle: f64, reference: f64) -> f64 {
    let turns = ((reference - angle) / (2.0 * PI)).round();
    angle + 2.0 * PI * turns
}

/// A body's moment of inertia about a line, kg·m²: mass `mass` (kg), inertia about its centre
/// of mass `inertia_in_body` (kg·m², body frame), centre `centre` (m, N) and attitude
/// `dcm_n_b`; the line through `point` (m, N) along the unit vector `axis` (N):
/// `aᵀ [N b] I [b N] a + m d²`, d the centre's distance from the line (parallel axes).
pub fn inertia_about_line(
    mass: f64,
    inertia_in_body: &Mat3,
    (centre, dcm_n_b): (&Vec3, &Mat3),
    point: &Vec3,
    axis: &Vec3,
) -> f64 {
    let d = centre - point;
    let perp = d - axis * d.dot(axis);
    let a_in_body = dcm_n_b.transpose() * axis;
    mass * perp.norm_squared() + a_in_body.dot(&(inertia_in_body * a_in_body))
}

/// Skew-symmetric cross-product matrix `[v×]`.
pub fn skew<T: Real>(v: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -v.z, v.y, v.z, z, -v.x, -v.y, v.x, z)
}

/// The attitude of frame B relative to a reference frame R from their quaternions relative
/// to N, `(w, x, y, z)`, scalar first (Hamilton, as stored in the state: `[N b] =
/// dcm_from_quat(q)`): `β_{B/R} = β_{R/N}* ⊗ β_{B/N}`, since `[N B] = [N R][R B]`
/// (Schaub & Junkins §3.5, in Hamilton's product order). `q_b` need not be unit.
pub fn quat_relative<T: Real>(q_b: &[T], q_r: &[f64; 4]) -> [T; 4] {
    let n = (q_b[0] * q_b[0] + q_b[1] * q_b[1] + q_b[2] * q_b[2] + q_b[3] * q_b[3]).sqrt();
    let b = [q_b[0] / n, q_b[1] / n, q_b[2] / n, q_b[3] / n];
    let a = [real::<T>(q_r[0]), real::<T>(-q_r[1]), real::<T>(-q_r[2]), real::<T>(-q_r[3])];
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// Modified Rodrigues parameters `σ = q_v / (1 + q_w)` of a unit quaternion, the short way
/// round (the shadow set `−q` when `q_w < 0`), so `|σ| ≤ 1` (Schaub & Junkins §3.7).
pub fn mrp_from_quat<T: Real>(q: &[T; 4]) -> Vector3<T> {
    let s = if q[0] < T::zero() { -T::one() } else { T::one() };
    Vector3::new(q[1], q[2], q[3]) * (s / (T::one() + s * q[0]))
}

/// The rotation angle of a unit quaternion, the short way round, rad in [0, π]:
/// `2 atan2(|q_v|, |q_w|)`.
pub fn quat_angle(q: &[f64; 4]) -> f64 {
    2.0 * (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt().atan2(q[0].abs())
}

/// Unit quaternion `(w, x, y, z)` (Hamilton) of a rotation, as stored in the state vector.
///
/// The body state stores `q_n_b`, which maps body components to N components:
/// `[N b] = dcm_from_quat(q_n_b)`.
pub fn quat_from_dcm(dcm_n_b: &Mat3) -> [f64; 4] {
    let rot = nalgebra::Rotation3::from_matrix_unchecked(*dcm_n_b);
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(&rot);
    [q.w, q.i, q.j, q.k]
}

/// DCM `[N b]` of a quaternion `(w, x, y, z)` that need not be exactly unit: it is
/// normalized first, so the integrator's drift of |q| never reaches the physics.
pub fn dcm_from_quat<T: Real>(q: &[T]) -> Matrix3<T> {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let (w, x, y, z) = (q[0] / n, q[1] / n, q[2] / n, q[3] / n);
    let (one, two) = (T::one(), real::<T>(2.0));
    Matrix3::new(
        one - two * (y * y + z * z),
        two * (x * y - w * z),
        two * (x * z + w * y),
        two * (x * y + w * z),
        one - two * (x * x + z * z),
        two * (y * z - w * x),
        two * (x * z - w * y),
        two * (y * z + w * x),
        one - two * (x * x + y * y),
    )
}

/// Quaternion rate `q̇ = ½ q ⊗ (0, ω)` for `q = q_n_b` and ω in body components, rad/s.
pub fn quat_rate(q: &[f64], omega_in_body: &Vec3) -> [f64; 4] {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    let (p, r, s) = (omega_in_body.x, omega_in_body.y, omega_in_body.z);
    [
        0.5 * (-x * p - y * r - z * s),
        0.5 * (w * p + y * s - z * r),
        0.5 * (w * r + z * p - x * s),
        0.5 * (w * s + x * r - y * p),
    ]
}

// Small products written out. nalgebra's `*` on 3×3 matrices goes through its general
// gemm/gemv, which for a non-f64 scalar clones every operand and multiplies by α = 1 and adds
// β·y with β = 0: for the 26-lane dual numbers of the exact Jacobian that was 40 % of the
// flasher example's run in copies alone (perf, `cargo bench --bench flasher`). These sum in
// nalgebra's order (column k of `a` times `b[k]`, k = 0, 1, 2, left to right), so f64 results
// are the same to the bit.

/// `a b`.
#[inline]
pub fn mat_mul<T: Real>(a: &Matrix3<T>, b: &Matrix3<T>) -> Matrix3<T> {
    Matrix3::from_fn(|i, j| a[(i, 0)] * b[(0, j)] + a[(i, 1)] * b[(1, j)] + a[(i, 2)] * b[(2, j)])
}

/// `aᵀ b`, without forming `aᵀ`.
#[inline]
pub fn mat_tr_mul<T: Real>(a: &Matrix3<T>, b: &Matrix3<T>) -> Matrix3<T> {
    Matrix3::from_fn(|i, j| a[(0, i)] * b[(0, j)] + a[(1, i)] * b[(1, j)] + a[(2, i)] * b[(2, j)])
}

/// `a b` with `b` a constant (f64) matrix.
#[inline]
pub fn mat_mul_const<T: Real>(a: &Matrix3<T>, b: &Mat3) -> Matrix3<T> {
    Matrix3::from_fn(|i, j| dot_const([a[(i, 0)], a[(i, 1)], a[(i, 2)]], [b[(0, j)], b[(1, j)], b[(2, j)]]))
}

/// `x · c` with `c` constant, leaving out the terms whose constant is exactly zero (frames at
/// right angles, diagonal gains: for dual numbers each term is a product over every lane).
/// Left to right as nalgebra sums; the value differs from the full sum at most in the sign of
/// a zero.
#[inline]
fn dot_const<T: Real>(x: [T; 3], c: [f64; 3]) -> T {
    // f64 sums every term: the test for zero costs more than a product (this folds away when
    // monomorphized).
    if std::any::TypeId::of::<T>() == std::any::TypeId::of::<f64>() {
        return x[0] * real::<T>(c[0]) + x[1] * real::<T>(c[1]) + x[2] * real::<T>(c[2]);
    }
    let mut sum: Option<T> = None;
    for (x, c) in x.into_iter().zip(c) {
        if c != 0.0 {
            let term = x * real::<T>(c);
            sum = Some(sum.map_or(term, |s| s + term));
        }
    }
    sum.unwrap_or_else(T::zero)
}

/// `a v`.
#[inline]
pub fn mat_vec<T: Real>(a: &Matrix3<T>, v: &Vector3<T>) -> Vector3<T> {
    Vector3::from_fn(|i, _| a[(i, 0)] * v[0] + a[(i, 1)] * v[1] + a[(i, 2)] * v[2])
}

/// `aᵀ v`, without forming `aᵀ`.
#[inline]
pub fn mat_tr_vec<T: Real>(a: &Matrix3<T>, v: &Vector3<T>) -> Vector3<T> {
    Vector3::from_fn(|i, _| a[(0, i)] * v[0] + a[(1, i)] * v[1] + a[(2, i)] * v[2])
}

/// `a v` with `v` a constant (f64) vector.
#[inline]
pub fn mat_vec_const<T: Real>(a: &Matrix3<T>, v: &Vec3) -> Vector3<T> {
    Vector3::from_fn(|i, _| dot_const([a[(i, 0)], a[(i, 1)], a[(i, 2)]], [v[0], v[1], v[2]]))
}

/// `a v` with `a` a constant (f64) matrix.
#[inline]
pub fn const_mat_vec<T: Real>(a: &Mat3, v: &Vector3<T>) -> Vector3<T> {
    Vector3::from_fn(|i, _| dot_const([v[0], v[1], v[2]], [a[(i, 0)], a[(i, 1)], a[(i, 2)]]))
}

/// `a × b`, in nalgebra's order of operations.
#[inline]
pub fn cross<T: Real>(a: &Vector3<T>, b: &Vector3<T>) -> Vector3<T> {
    Vector3::new(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The trigonometric values read from a DCM equal those of its angles (round-off), for
    /// rolls beyond ±π (whole turns do not matter) and pitch near ±π/2.
    #[test]
    fn trig_from_dcm_matches_angles() {
        for e in [Euler321::new(0.3, -0.7, 2.1), Euler321::new(-2.9, 1.5, -3.1), Euler321::new(1.0, -1.57, 0.4)] {
            let a = EulerTrig::from_angles(&e);
            let b = EulerTrig::from_dcm(&e.to_dcm());
            let d = [a.s2 - b.s2, a.c2 - b.c2, a.s3 - b.s3, a.c3 - b.c3];
            assert!(d.iter().all(|x| x.abs() < 1e-12), "{e:?}: {d:?}");
            let wound = Euler321::new(e.yaw, e.pitch, e.roll + 4.0 * PI);
            assert!((EulerTrig::from_dcm(&wound.to_dcm()).s3 - a.s3).abs() < 1e-12);
        }
    }

    #[test]
    fn dcm_matches_elementary_product() {
        let e = Euler321::new(0.3, -0.7, 2.1);
        let direct = m1(e.roll) * m2(e.pitch) * m3(e.yaw);
        assert!((e.to_dcm() - direct).abs().max() < 1e-15);
        let back = Euler321::from_dcm(&direct);
        assert!((back.as_vector() - e.as_vector()).abs().max() < 1e-14);
    }

    #[test]
    fn rate_matrix_matches_numerical_derivative() {
        // ω = B θ̇ with [ω×] = −[XY]̇ [XY]ᵀ for ω of X relative to Y in X components.
        let e = Euler321::new(0.4, 0.2, -1.0);
        let rate = Vec3::new(0.3, -0.5, 0.7);
        let h = 1e-6;
        let ep = Euler321::new(e.yaw + h * rate.x, e.pitch + h * rate.y, e.roll + h * rate.z);
        let em = Euler321::new(e.yaw - h * rate.x, e.pitch - h * rate.y, e.roll - h * rate.z);
        let cdot = (ep.to_dcm() - em.to_dcm()) / (2.0 * h);
        let w = -cdot * e.to_dcm().transpose();
        let omega = Vec3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
        assert!((omega - e.rate_matrix() * rate).abs().max() < 1e-9);
    }

    #[test]
    fn torque_from_generalized_inverts_rate_matrix_transpose() {
        let e = Euler321::new(-2.0, 0.9, 0.4);
        let g = Vec3::new(1.0, -2.0, 3.0);
        let tau = e.torque_from_generalized(&g);
        assert!((e.rate_matrix().transpose() * tau - g).abs().max() < 1e-13);
    }

    #[test]
    fn euler_rates_invert_rate_matrix() {
        let e = Euler321::new(0.3, -1.1, 2.0);
        let w = Vec3::new(0.4, -0.2, 0.9);
        assert!((e.rate_matrix() * e.rates_from_omega(&w) - w).abs().max() < 1e-14);
    }

    /// ω = J_r ṙ: check J_r⁻¹ against a numerical derivative of exp, and the log map.
    #[test]
    fn rotation_vector_kinematics() {
        let r = Vec3::new(0.9, -1.4, 1.7); // |r| ≈ 2.4 rad, beyond Euler-friendly folds
        let rdot = Vec3::new(0.3, 0.1, -0.5);
        let exp = |v: &Vec3| nalgebra::Rotation3::new(*v).into_inner(); // [Y X]
        assert!((rotation_vector(&exp(&r).transpose()) - r).abs().max() < 1e-12);
        let h = 1e-6;
        let rdot_dcm = (exp(&(r + rdot * h)) - exp(&(r - rdot * h))) / (2.0 * h);
        // [ω×] = [Y X]ᵀ d[Y X]/dt (ω in X components)
        let w = exp(&r).transpose() * rdot_dcm;
        let omega = Vec3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
        assert!((rotation_vector_rate_matrix_inverse(&r) * omega - rdot).abs().max() < 1e-8);
    }

    #[test]
    fn quaternion_round_trip() {
        let dcm = Euler321::new(1.0, 0.5, -2.5).to_dcm().transpose();
        let q = quat_from_dcm(&dcm);
        assert!((dcm_from_quat(&q) - dcm).abs().max() < 1e-14);
    }

    /// Attitude angles give back their DCM at every pitch, ±90° (gimbal lock) and its
    /// neighbourhood included, to 1e-8 (the lock branch's error is cos θ2 ≤ 1e-8; elsewhere
    /// round-off); at the lock roll is the hint given.
    #[test]
    fn attitude_angles_are_right_at_every_pitch() {
        let half = std::f64::consts::FRAC_PI_2;
        let mut worst = 0.0f64;
        for &pitch in &[0.3, -1.2, half, -half, half - 1e-9, -half + 1e-9, half - 1e-6, half - 1e-10] {
            for &(yaw, roll) in &[(0.4, -2.0), (-3.0, 1.0), (2.5, 2.5), (0.0, 0.0)] {
                let dcm = Euler321::new(yaw, pitch, roll).to_dcm();
                for hint in [0.0, 0.7] {
                    let e = Euler321::attitude_from_dcm(&dcm, hint);
                    worst = worst.max((e.to_dcm() - dcm).abs().max());
                    if (e.pitch.abs() - half).abs() < 1e-12 {
                        assert_eq!(e.roll, hint);
                    }
                }
            }
        }
        assert!(worst < 1e-8, "{worst:e}");
    }

    /// The derivative of [`atan2`] is `(x dy − y dx) / (x² + y²)` on the axes too (where
    /// num-dual's own is 0/0), and its value is f64's `atan2` to the bit.
    #[test]
    fn atan2_differentiates_on_the_axes() {
        use num_dual::Dual64;
        for (y, x) in [(1.0, 0.0), (-2.0, 0.0), (0.0, -3.0), (0.0, 0.5), (0.3, -0.4)] {
            let (dy, dx) = (0.7, -1.3);
            let a = atan2(Dual64::new(y, dy), Dual64::new(x, dx));
            assert_eq!(a.re, f64::atan2(y, x));
            let expected = (x * dy - y * dx) / (x * x + y * y);
            assert!((a.eps - expected).abs() < 1e-15, "({y}, {x}): {} vs {expected}", a.eps);
            assert_eq!(atan2(y, x).to_bits(), f64::atan2(y, x).to_bits());
        }
    }

    #[test]
    fn unwrap_chooses_nearest_turn() {
        assert!((unwrap_near(-3.1, 3.1) - (2.0 * PI - 3.1)).abs() < 1e-15);
        assert!((unwrap_near(0.1, 12.0) - (0.1 + 4.0 * PI)).abs() < 1e-14);
    }

    /// `β_{B/R}` composes back to `β_{B/N}` (`[N B] = [N R][R B]`), and the MRPs of a rotation
    /// by φ about an axis are `tan(φ/4)` along it, the short way round past π.
    #[test]
    fn relative_quaternion_and_mrps() {
        let q_of = |axis: Vec3, angle: f64| {
            let a = axis.normalize() * (0.5 * angle).sin();
            [(0.5 * angle).cos(), a.x, a.y, a.z]
        };
        let q_b = q_of(Vec3::new(1.0, -2.0, 0.5), 1.3);
        let q_r = q_of(Vec3::new(0.2, 1.0, -1.0), -0.7);
        let q_br = quat_relative(&q_b, &q_r);
        let composed = dcm_from_quat(&q_r) * dcm_from_quat(&q_br);
        assert!((composed - dcm_from_quat(&q_b)).norm() < 1e-15);
        for phi in [0.3, 2.0, 4.0] {
            let sigma = mrp_from_quat(&q_of(Vec3::z(), phi));
            let short = if phi > PI { phi - 2.0 * PI } else { phi };
            assert!((sigma - Vec3::z() * (short / 4.0).tan()).norm() < 1e-15, "{phi}");
            assert!((quat_angle(&q_of(Vec3::x(), phi)) - short.abs()).abs() < 1e-14);
        }
    }
}

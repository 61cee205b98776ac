//! A lock's constraint row: the locked coordinate's rate as a linear form in the two bodies'
//! twists, `J V`, with its velocity-product term γ (`J V̇ + γ = 0`), derived exactly from the
//! hinge kinematics (docs/model.md §2, 3-2-1 angle rates for rotations).

use crate::kinematics::{HingeKinematics, hinge_kinematics};
use crate::math::{Euler321, EulerTrig, Real, real};
use crate::model::{Hinge, Model};
use crate::state::BodyMotion;
use nalgebra::Vector3;

/// One locked direction of one hinge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lock {
    /// Hinge index.
    pub hinge: usize,
    /// Direction: 0..3 = δ x, y, z; 3, 4, 5 = rx (roll θ3), ry (pitch θ2), rz (yaw θ1).
    pub direction: usize,
    /// Value held, m or rad (the initial value).
    pub target: f64,
}

/// A constraint row at one state (in f64, or in dual numbers for the Jacobian).
#[derive(Clone, Copy, Debug)]
pub struct Row<T: nalgebra::Scalar = f64> {
    pub(crate) parent: usize,
    pub(crate) child: usize,
    /// Coefficients of the parent's (v, ω) and the child's (v, ω), N components.
    pub(crate) lin_p: Vector3<T>,
    pub(crate) ang_p: Vector3<T>,
    pub(crate) lin_c: Vector3<T>,
    pub(crate) ang_c: Vector3<T>,
    /// Velocity-product term γ (the coordinate's acceleration at zero body accelerations).
    pub(crate) gamma: T,
    /// Coordinate minus target.
    pub(super) error: T,
    /// Coordinate rate `J V`.
    pub(super) rate: T,
}

/// Euler-angle index (in (yaw, pitch, roll)) of rotational direction 3, 4, 5.
pub fn euler_index(direction: usize) -> usize {
    match direction {
        3 => 2, // rx = roll θ3
        4 => 1, // ry = pitch θ2
        _ => 0, // rz = yaw θ1
    }
}

/// Rows of `B(θ)⁻¹` (so `θ̇ = B⁻¹ ω`) and `Ḃ θ̇` for the rates `theta_rate`.
fn euler_rows<T: Real>(trig: &EulerTrig<T>, theta_rate: &Vector3<T>) -> ([Vector3<T>; 3], Vector3<T>) {
    let EulerTrig { s2, c2, s3, c3 } = *trig;
    let (zero, one) = (real::<T>(0.0), real::<T>(1.0));
    let b_inv = [
        Vector3::new(zero, s3 / c2, c3 / c2),
        Vector3::new(zero, c3, -s3),
        Vector3::new(one, s2 * s3 / c2, s2 * c3 / c2),
    ];
    // B = [[−s2, 0, 1], [s3 c2, c3, 0], [c3 c2, −s3, 0]], so with θ̇ = (r1, r2, r3),
    // Ḃ θ̇ = r2 ∂B/∂θ2 θ̇ + r3 ∂B/∂θ3 θ̇ with ∂B/∂θ2 = [[−c2, 0, 0], [−s3 s2, 0, 0],
    // [−c3 s2, 0, 0]] and ∂B/∂θ3 = [[0, 0, 0], [c3 c2, −s3, 0], [−s3 c2, −c3, 0]].
    let (r1, r2, r3) = (theta_rate.x, theta_rate.y, theta_rate.z);
    let r12 = r1 * r2;
    let b_dot_rate = Vector3::new(
        -c2 * r12,
        -s3 * s2 * r12 + r3 * (c3 * c2 * r1 - s3 * r2),
        -c3 * s2 * r12 - r3 * (s3 * c2 * r1 + c3 * r2),
    );
    (b_inv, b_dot_rate)
}

/// Constraint rows of every lock at body motions `motions`, with the hinges' continuous
/// angle references `refs`. `locks` are grouped by hinge (as [`crate::dynamics::Dynamics`]
/// keeps them).
pub fn rows(model: &Model, locks: &[Lock], motions: &[BodyMotion], refs: &[Euler321]) -> Vec<Row> {
    let mut out = Vec::with_capacity(locks.len());
    for group in locks.chunk_by(|a, b| a.hinge == b.hinge) {
        let i = group[0].hinge;
        let h = &model.hinges[i];
        let (p, c) = (&motions[h.parent], &motions[h.child]);
        hinge_rows(h, group, p, c, &hinge_kinematics(h, p, c, &refs[i]), &mut out);
    }
    out
}

/// Appends to `out` the rows of `locks`, all of hinge `h`, from the hinge's kinematics `k`
/// and its parent's and child's motions `p`, `c`.
#[inline]
pub fn hinge_rows<T: Real>(
    h: &Hinge,
    locks: &[Lock],
    p: &BodyMotion<T>,
    c: &BodyMotion<T>,
    k: &HingeKinematics<T>,
    out: &mut Vec<Row<T>>,
) {
    let (a_p, a_c) = (k.arm_parent_in_n, k.arm_child_in_n);
    let (w_p, w_c) = (p.omega_in_n, c.omega_in_n);
    // The Euler-rate data shared by the hinge's rotational locks, and the velocity-product
    // acceleration of A relative to the parent shared by its translational ones (γ = u · g),
    // each computed once.
    // (rows of B⁻¹, θ̇, and the velocity-product part −ω_c^A × ω_rel − Ḃ θ̇ that every
    // rotational row dots with its row of B⁻¹)
    type EulerRates<T> = ([Vector3<T>; 3], Vector3<T>, Vector3<T>);
    let mut euler: Option<EulerRates<T>> = None;
    let mut relative: Option<Vector3<T>> = None;
    for lock in locks {
        let zero = real::<T>(0.0);
        // Filled in place: building the row and pushing it costs a copy of it.
        out.push(Row {
            parent: h.parent,
            child: h.child,
            lin_p: Vector3::zeros(),
            ang_p: Vector3::zeros(),
            lin_c: Vector3::zeros(),
            ang_c: Vector3::zeros(),
            gamma: zero,
            error: zero,
            rate: zero,
        });
        let row = out.last_mut().expect("just pushed");
        if lock.direction < 3 {
            // δ̇ = [A0 N] w, w = v_A − v_p − ω_p × a_p, v_A = v_c + ω_c × a_c.
            let u = k.dcm_n_a0.column(lock.direction).into_owned();
            row.lin_c = u;
            row.ang_c = a_c.cross(&u);
            row.lin_p = -u;
            row.ang_p = -a_p.cross(&u);
            let g = *relative.get_or_insert_with(|| {
                let v_a = c.v_in_n + w_c.cross(&a_c);
                let w = v_a - p.v_in_n - w_p.cross(&a_p);
                w_c.cross(&w_c.cross(&a_c)) - w_p.cross(&(v_a - p.v_in_n)) - w_p.cross(&w)
            });
            row.gamma = u.dot(&g);
            row.error = k.state.delta_in_a0[lock.direction] - real::<T>(lock.target);
            row.rate = k.state.delta_rate_in_a0[lock.direction];
        } else {
            // θ̇_j = b_j · ω_rel, ω_rel = [A N](ω_c − ω_p);
            // θ̈_j = b_j · ([A N](α_c − α_p) − ω_c^A × ω_rel − Ḃ θ̇).
            let j = euler_index(lock.direction);
            let theta = k.state.theta;
            let w_rel = k.state.omega_rel_in_a;
            let (b_inv, theta_rate, product) = *euler.get_or_insert_with(|| {
                let tr = k.state.trig.rates_from_omega(&w_rel);
                let (b, bd) = euler_rows(&k.state.trig, &tr);
                let w_c_in_a = k.dcm_n_a.tr_mul(&w_c);
                (b, tr, -w_c_in_a.cross(&w_rel) - bd)
            });
            let n = k.dcm_n_a * b_inv[j];
            row.ang_c = n;
            row.ang_p = -n;
            row.gamma = b_inv[j].dot(&product);
            row.error = theta.as_vector()[j] - real::<T>(lock.target);
            row.rate = theta_rate[j];
        }
    }
}

//! Locked hinge directions: holonomic constraints between two bodies, held exactly.
//!
//! A locked direction keeps one relative coordinate of a hinge at its initial value: a
//! component of δ (A0 components), or one 3-2-1 Euler angle of `[A A0]`. In maximal
//! coordinates each lock is a constraint row `J V = 0` on the two bodies' twists
//! (`V = (v, ω)`, N components), with the acceleration-level form `J V̇ + γ = 0`, `γ` the
//! velocity-product terms, derived exactly below. Each right-hand-side evaluation solves
//! `(J M⁻¹ Jᵀ) λ = −(J a_free + γ)` for the constraint multipliers: ideal (workless) wrench
//! pairs, equal and opposite at a common point, so energy and momentum are conserved. After
//! every accepted step the state is projected back onto the constraint manifold (positions,
//! then velocities, mass-weighted), which holds the locked coordinates to round-off.
//!
//! The solve is dense in the number of locked directions: fine for tens of hinges; large
//! locked structures need the sparse factorization the stiff-hinge issue brings.

use crate::dynamics::{HingeKinematics, hinge_kinematics};
use crate::math::{Euler321, Mat3, Vec3};
use crate::model::Model;
use crate::state::{BODY_STATE_LEN, BodyMotion, OMEGA, POS, QUAT, VEL};
use nalgebra::{DMatrix, DVector};

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

/// A constraint row at one state.
#[derive(Clone, Copy, Debug)]
pub struct Row {
    parent: usize,
    child: usize,
    /// Coefficients of the parent's (v, ω) and the child's (v, ω), N components.
    lin_p: Vec3,
    ang_p: Vec3,
    lin_c: Vec3,
    ang_c: Vec3,
    /// Velocity-product term γ (the coordinate's acceleration at zero body accelerations).
    gamma: f64,
    /// Coordinate minus target.
    error: f64,
    /// Coordinate rate `J V`.
    rate: f64,
}

/// Euler-angle index (in (yaw, pitch, roll)) of rotational direction 3, 4, 5.
pub(crate) fn euler_index(direction: usize) -> usize {
    match direction {
        3 => 2, // rx = roll θ3
        4 => 1, // ry = pitch θ2
        _ => 0, // rz = yaw θ1
    }
}

/// Rows of `B(θ)⁻¹` (so `θ̇ = B⁻¹ ω`) and `Ḃ θ̇` for the rates `theta_rate`.
fn euler_rows(theta: &Euler321, theta_rate: &Vec3) -> ([Vec3; 3], Vec3) {
    let (s2, c2) = theta.pitch.sin_cos();
    let (s3, c3) = theta.roll.sin_cos();
    let b_inv = [Vec3::new(0.0, s3 / c2, c3 / c2), Vec3::new(0.0, c3, -s3), Vec3::new(1.0, s2 * s3 / c2, s2 * c3 / c2)];
    // B = [[−s2, 0, 1], [s3 c2, c3, 0], [c3 c2, −s3, 0]]
    let db_d2 = Mat3::new(-c2, 0.0, 0.0, -s3 * s2, 0.0, 0.0, -c3 * s2, 0.0, 0.0);
    let db_d3 = Mat3::new(0.0, 0.0, 0.0, c3 * c2, -s3, 0.0, -s3 * c2, -c3, 0.0);
    let b_dot = db_d2 * theta_rate.y + db_d3 * theta_rate.z;
    (b_inv, b_dot * theta_rate)
}

/// Constraint rows of every lock at body motions `motions`, with the hinges' continuous
/// angle references `refs`.
pub fn rows(model: &Model, locks: &[Lock], motions: &[BodyMotion], refs: &[Euler321]) -> Vec<Row> {
    let mut kin: Vec<Option<HingeKinematics>> = vec![None; model.hinges.len()];
    for lock in locks {
        let h = &model.hinges[lock.hinge];
        kin[lock.hinge]
            .get_or_insert_with(|| hinge_kinematics(h, &motions[h.parent], &motions[h.child], &refs[lock.hinge]));
    }
    let mut out = Vec::with_capacity(locks.len());
    rows_from(model, locks, motions, |h| kin[h].as_ref().expect("computed above"), &mut out);
    out
}

/// Constraint rows from the hinges' kinematics (`kinematics(h)` for hinge h), into `out`.
pub fn rows_from<'k>(
    model: &Model,
    locks: &[Lock],
    motions: &[BodyMotion],
    kinematics: impl Fn(usize) -> &'k HingeKinematics,
    out: &mut Vec<Row>,
) {
    out.clear();
    // Per hinge, the Euler-rate data shared by its rotational locks (computed once).
    let mut euler_cache: Option<(usize, [Vec3; 3], Vec3, Vec3)> = None;
    for lock in locks {
        let h = &model.hinges[lock.hinge];
        let (p, c) = (&motions[h.parent], &motions[h.child]);
        let k = kinematics(lock.hinge);
        let (a_p, a_c) = (k.arm_parent_in_n, k.arm_child_in_n);
        let (w_p, w_c) = (p.omega_in_n, c.omega_in_n);
        let mut row = Row {
            parent: h.parent,
            child: h.child,
            lin_p: Vec3::zeros(),
            ang_p: Vec3::zeros(),
            lin_c: Vec3::zeros(),
            ang_c: Vec3::zeros(),
            gamma: 0.0,
            error: 0.0,
            rate: 0.0,
        };
        if lock.direction < 3 {
            // δ̇ = [A0 N] w, w = v_A − v_p − ω_p × a_p, v_A = v_c + ω_c × a_c.
            let u = k.dcm_n_a0.column(lock.direction).into_owned();
            row.lin_c = u;
            row.ang_c = a_c.cross(&u);
            row.lin_p = -u;
            row.ang_p = -a_p.cross(&u);
            let v_a = c.v_in_n + w_c.cross(&a_c);
            let w = v_a - p.v_in_n - w_p.cross(&a_p);
            let g = w_c.cross(&w_c.cross(&a_c)) - w_p.cross(&(v_a - p.v_in_n)) - w_p.cross(&w);
            row.gamma = u.dot(&g);
            row.error = k.state.delta_in_a0[lock.direction] - lock.target;
            row.rate = k.state.delta_rate_in_a0[lock.direction];
        } else {
            // θ̇_j = b_j · ω_rel, ω_rel = [A N](ω_c − ω_p);
            // θ̈_j = b_j · ([A N](α_c − α_p) − ω_c^A × ω_rel − Ḃ θ̇).
            let j = euler_index(lock.direction);
            let theta = k.state.theta;
            let w_rel = k.state.omega_rel_in_a;
            let (b_inv, b_dot_rate, theta_rate) = match euler_cache {
                Some((hinge, b, bd, tr)) if hinge == lock.hinge => (b, bd, tr),
                _ => {
                    let tr = theta.rates_from_omega(&w_rel);
                    let (b, bd) = euler_rows(&theta, &tr);
                    euler_cache = Some((lock.hinge, b, bd, tr));
                    (b, bd, tr)
                }
            };
            let n = k.dcm_n_a * b_inv[j];
            row.ang_c = n;
            row.ang_p = -n;
            let w_c_in_a = k.dcm_n_a.transpose() * w_c;
            row.gamma = b_inv[j].dot(&(-w_c_in_a.cross(&w_rel) - b_dot_rate));
            row.error = theta.as_vector()[j] - lock.target;
            row.rate = theta_rate[j];
        }
        out.push(row);
    }
}

/// `J M⁻¹ Jᵀ` for the rows (dense).
fn effective_mass(model: &Model, rows: &[Row], inertia_inv_in_n: &[Mat3]) -> DMatrix<f64> {
    let m = rows.len();
    DMatrix::from_fn(m, m, |r, s| coupling(model, &rows[r], &rows[s], inertia_inv_in_n))
}

/// `M⁻¹ Jᵀ λ` added to per-body (linear, angular) quantities.
fn apply(
    model: &Model,
    rows: &[Row],
    lambda: &DVector<f64>,
    inertia_inv_in_n: &[Mat3],
    lin: &mut [Vec3],
    ang: &mut [Vec3],
) {
    for (row, &l) in rows.iter().zip(lambda.iter()) {
        for (b, lv, wv) in [(row.parent, row.lin_p, row.ang_p), (row.child, row.lin_c, row.ang_c)] {
            lin[b] += lv * (l / model.bodies[b].mass);
            ang[b] += inertia_inv_in_n[b] * wv * l;
        }
    }
}

fn inertia_inverses(model: &Model, motions: &[BodyMotion]) -> Vec<Mat3> {
    model.bodies.iter().zip(motions).map(|(b, m)| m.dcm_n_b * b.inertia_inv_in_body * m.dcm_n_b.transpose()).collect()
}

/// Work space for [`constrain_accelerations`], reused across evaluations.
#[derive(Debug, Default)]
pub struct Workspace {
    /// Per row: `M⁻¹ Jᵀ` on the parent (linear, angular) and the child.
    scaled: Vec<[Vec3; 4]>,
    /// `J M⁻¹ Jᵀ`, row-major, then its Cholesky factor in place.
    matrix: Vec<f64>,
    lambda: Vec<f64>,
}

/// In-place Cholesky factorization of the row-major SPD matrix `a` (n×n), lower triangle.
fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut v = a[i * n + j];
            for k in 0..j {
                v -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = v / d;
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place for the factor from [`cholesky_in_place`].
fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut v = b[i];
        for k in 0..i {
            v -= l[i * n + k] * b[k];
        }
        b[i] = v / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut v = b[i];
        for k in i + 1..n {
            v -= l[k * n + i] * b[k];
        }
        b[i] = v / l[i * n + i];
    }
}

/// Corrects free accelerations (`accel` linear, `alpha` angular, N components, per body) so
/// that every locked coordinate has zero acceleration, given the locks' `rows` at this
/// state. Returns false if `J M⁻¹ Jᵀ` is singular (redundant locks).
pub fn constrain_accelerations(
    model: &Model,
    rows: &[Row],
    motions: &[BodyMotion],
    accel: &mut [Vec3],
    alpha: &mut [Vec3],
    work: &mut Workspace,
) -> bool {
    let n = rows.len();
    // M⁻¹ Jᵀ per row; the angular part as [N b] I⁻¹ [b N] w, without forming I_N⁻¹.
    let inv_ang = |b: usize, w: &Vec3| {
        let r = &motions[b].dcm_n_b;
        r * (model.bodies[b].inertia_inv_in_body * (r.transpose() * w))
    };
    work.scaled.clear();
    for r in rows {
        work.scaled.push([
            r.lin_p / model.bodies[r.parent].mass,
            inv_ang(r.parent, &r.ang_p),
            r.lin_c / model.bodies[r.child].mass,
            inv_ang(r.child, &r.ang_c),
        ]);
    }
    work.matrix.clear();
    work.matrix.resize(n * n, 0.0);
    for (r, ra) in rows.iter().enumerate() {
        for (s, rb) in rows.iter().enumerate().take(r + 1) {
            let m = &work.scaled[s];
            let mut v = 0.0;
            if ra.parent == rb.parent {
                v += ra.lin_p.dot(&m[0]) + ra.ang_p.dot(&m[1]);
            }
            if ra.parent == rb.child {
                v += ra.lin_p.dot(&m[2]) + ra.ang_p.dot(&m[3]);
            }
            if ra.child == rb.parent {
                v += ra.lin_c.dot(&m[0]) + ra.ang_c.dot(&m[1]);
            }
            if ra.child == rb.child {
                v += ra.lin_c.dot(&m[2]) + ra.ang_c.dot(&m[3]);
            }
            work.matrix[r * n + s] = v;
            work.matrix[s * n + r] = v;
        }
    }
    work.lambda.clear();
    work.lambda.extend(rows.iter().map(|r| {
        -(r.gamma
            + r.lin_p.dot(&accel[r.parent])
            + r.ang_p.dot(&alpha[r.parent])
            + r.lin_c.dot(&accel[r.child])
            + r.ang_c.dot(&alpha[r.child]))
    }));
    if !cholesky_in_place(&mut work.matrix, n) {
        return false;
    }
    cholesky_solve(&work.matrix, n, &mut work.lambda);
    for ((row, m), &l) in rows.iter().zip(&work.scaled).zip(&work.lambda) {
        accel[row.parent] += m[0] * l;
        alpha[row.parent] += m[1] * l;
        accel[row.child] += m[2] * l;
        alpha[row.child] += m[3] * l;
    }
    true
}

/// Entry of `J M⁻¹ Jᵀ` for two rows.
fn coupling(model: &Model, ra: &Row, rb: &Row, inv: &[Mat3]) -> f64 {
    let mut v = 0.0;
    for (ba, la, wa) in [(ra.parent, ra.lin_p, ra.ang_p), (ra.child, ra.lin_c, ra.ang_c)] {
        for (bb, lb, wb) in [(rb.parent, rb.lin_p, rb.ang_p), (rb.child, rb.lin_c, rb.ang_c)] {
            if ba == bb {
                v += la.dot(&lb) / model.bodies[ba].mass + wa.dot(&(inv[ba] * wb));
            }
        }
    }
    v
}

/// Whether the locks are independent here (`J M⁻¹ Jᵀ` positive definite); redundant locks,
/// such as a closed loop of fully locked hinges, are not.
pub fn independent(model: &Model, locks: &[Lock], motions: &[BodyMotion], refs: &[Euler321]) -> bool {
    let rows = rows(model, locks, motions, refs);
    effective_mass(model, &rows, &inertia_inverses(model, motions)).cholesky().is_some()
}

/// Drift of a locked coordinate (m or rad) or of its rate (m/s or rad/s) beyond which
/// [`project`] corrects the state. Well below the 1e-9 the locks promise, and rarely reached
/// at tight tolerances, so the integration is seldom restarted.
pub const DRIFT_LIMIT: f64 = 1e-11;

/// Projects the state onto the constraint manifold if a locked coordinate or its rate has
/// drifted beyond [`DRIFT_LIMIT`] (or always, with `force`): two mass-weighted Newton
/// corrections of the poses, then one of the velocities. Returns whether `y` changed.
pub fn project(model: &Model, locks: &[Lock], refs: &[Euler321], y: &mut [f64], force: bool) -> bool {
    let nb = model.bodies.len();
    let motions = |y: &[f64]| (0..nb).map(|i| BodyMotion::from_state(y, i)).collect::<Vec<_>>();
    if !force {
        let r = rows(model, locks, &motions(y), refs);
        if r.iter().all(|r| r.error.abs() <= DRIFT_LIMIT && r.rate.abs() <= DRIFT_LIMIT) {
            return false;
        }
    }
    for _ in 0..2 {
        let m = motions(y);
        let rows = rows(model, locks, &m, refs);
        let inv = inertia_inverses(model, &m);
        let Some(chol) = effective_mass(model, &rows, &inv).cholesky() else { return true };
        let lambda = chol.solve(&DVector::from_iterator(rows.len(), rows.iter().map(|r| -r.error)));
        let mut dp = vec![Vec3::zeros(); nb];
        let mut dphi = vec![Vec3::zeros(); nb];
        apply(model, &rows, &lambda, &inv, &mut dp, &mut dphi);
        for i in 0..nb {
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for k in 0..3 {
                s[POS + k] += dp[i][k];
            }
            // q ← exp(δφ/2) ⊗ q with δφ in N components (a left rotation).
            let angle = dphi[i].norm();
            if angle > 0.0 {
                let axis = dphi[i] / angle;
                let (sh, ch) = (0.5 * angle).sin_cos();
                let dq = nalgebra::Quaternion::new(ch, sh * axis.x, sh * axis.y, sh * axis.z);
                let q = nalgebra::Quaternion::new(s[QUAT], s[QUAT + 1], s[QUAT + 2], s[QUAT + 3]);
                let r = dq * q;
                s[QUAT..QUAT + 4].copy_from_slice(&[r.w, r.i, r.j, r.k]);
            }
        }
    }
    // Velocities: remove J V.
    let m = motions(y);
    let rows = rows(model, locks, &m, refs);
    let inv = inertia_inverses(model, &m);
    if let Some(chol) = effective_mass(model, &rows, &inv).cholesky() {
        let lambda = chol.solve(&DVector::from_iterator(rows.len(), rows.iter().map(|r| -r.rate)));
        let mut dv = vec![Vec3::zeros(); nb];
        let mut dw = vec![Vec3::zeros(); nb];
        apply(model, &rows, &lambda, &inv, &mut dv, &mut dw);
        for i in 0..nb {
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            let w_b = m[i].dcm_n_b.transpose() * dw[i];
            for k in 0..3 {
                s[VEL + k] += dv[i][k];
                s[OMEGA + k] += w_b[k];
            }
        }
    }
    true
}

//! Natural modes of a structure at a static state (docs/linear.md): the free-free modes with
//! the six rigid-body ones set apart, and the modes with the hub held fixed, with their
//! effective masses and inertias about the hub (what a flexible appendage shows a controller).
//!
//! Both from the undamped problem `K φ = ω² M φ` with `K` the symmetric part of the
//! stiffness (law 1's is not symmetric: docs/linear.md says what that means), solved as the
//! symmetric eigenproblem of `M^{-1/2} K M^{-1/2}` (nalgebra's `SymmetricEigen`, dense).
//! Shapes are mass-normalised (`φᵀ M φ = 1`). Damping ratios are modal, `ζ = φᵀ C φ / 2ω`
//! (C's symmetric part): exact for damping proportional to the modes, a first-order
//! estimate otherwise.

use super::Linearization;
use crate::math::{Mat3, Vec3};
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// One mode.
#[derive(Clone, Debug)]
pub struct Mode {
    /// Natural frequency ω, rad/s (NaN for an unstable mode, `ω² < 0`).
    pub omega: f64,
    /// `ω²`, 1/s² (negative: the state is unstable along this shape).
    pub eigenvalue: f64,
    /// Modal damping ratio `φᵀ C φ / 2ω` (NaN for ω = 0).
    pub damping_ratio: f64,
    /// The shape, mass-normalised, in the positions' coordinates of the model (6 per body, or
    /// per body but the hub for hub-fixed modes).
    pub shape: DVector<f64>,
    /// A rigid-body mode of the free structure.
    pub rigid: bool,
    /// Hub-fixed modes: the effective masses (kg, along the hub's x, y, z) and inertias
    /// (kg·m², about the hub's axes through its centre of mass); zero for free modes.
    pub effective: [f64; 6],
}

impl Mode {
    /// Natural frequency, Hz.
    pub fn frequency_hz(&self) -> f64 {
        self.omega / (2.0 * std::f64::consts::PI)
    }
}

/// A structure's modes at a static state.
#[derive(Clone, Debug)]
pub struct Modes {
    /// The free-free modes, ω ascending (the six rigid-body modes first, flagged).
    pub free: Vec<Mode>,
    /// The modes with the hub held fixed, ω ascending, with their effective masses.
    pub hub_fixed: Vec<Mode>,
    /// The appendages' total mass (kg) and inertia about the hub (kg·m²) in the hub's axes:
    /// what the hub-fixed modes' effective masses add up to.
    pub appendage_total: [f64; 6],
    /// `‖K − Kᵀ‖ / ‖K‖` (Frobenius): how far the stiffness is from symmetric.
    pub asymmetry: f64,
    /// T, 6(n − 1) × 6: the other bodies' coordinates when the hub moves rigidly by its six
    /// (translations along, rotations about its axes), the structure moving with it.
    pub hub_rigid_influence: DMatrix<f64>,
}

/// `M^{-1/2}` of a block-diagonal mass matrix given per body (mass, inertia).
fn inverse_root(mass: &[(f64, Mat3)]) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(6 * mass.len(), 6 * mass.len());
    for (i, (m, inertia)) in mass.iter().enumerate() {
        for k in 0..3 {
            out[(6 * i + k, 6 * i + k)] = 1.0 / m.sqrt();
        }
        let e = SymmetricEigen::new(*inertia);
        let root =
            e.eigenvectors * Mat3::from_diagonal(&e.eigenvalues.map(|l| 1.0 / l.sqrt())) * e.eigenvectors.transpose();
        out.view_mut((6 * i + 3, 6 * i + 3), (3, 3)).copy_from(&root);
    }
    out
}

/// Eigen-solution of `K φ = λ M φ` (K symmetric) with `M^{-1/2}` given: λ ascending, shapes
/// mass-normalised as columns.
fn solve(k: &DMatrix<f64>, m_inv_root: &DMatrix<f64>) -> (Vec<f64>, DMatrix<f64>) {
    let s = m_inv_root * k * m_inv_root;
    let s = (&s + s.transpose()) * 0.5;
    let e = SymmetricEigen::new(s);
    let mut order: Vec<usize> = (0..e.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    let shapes = m_inv_root * e.eigenvectors.select_columns(order.iter());
    (order.iter().map(|&i| e.eigenvalues[i]).collect(), shapes)
}

/// A mode from its eigenvalue (ω², 1/s²), shape and `damping = φᵀ C φ` (1/s).
fn mode(lambda: f64, shape: DVector<f64>, damping: f64) -> Mode {
    let omega = if lambda >= 0.0 { lambda.sqrt() } else { f64::NAN };
    Mode {
        omega,
        eigenvalue: lambda,
        damping_ratio: if omega > 0.0 { damping / (2.0 * omega) } else { f64::NAN },
        shape,
        rigid: false,
        effective: [0.0; 6],
    }
}

/// The hub-fixed modes of eigenvalues `lambda` and shapes (columns), with their effective
/// masses `Γ_a²`, `Γ = φᵀ M T` (`mt` = M T of [`hub_influence`]); `damping(φ)` is `φᵀ C φ`.
fn hub_fixed_modes(
    lambda: &[f64],
    shapes: &DMatrix<f64>,
    mt: &DMatrix<f64>,
    damping: impl Fn(&DVector<f64>) -> f64,
) -> Vec<Mode> {
    lambda
        .iter()
        .enumerate()
        .map(|(j, l)| {
            let shape = shapes.column(j).into_owned();
            let gamma = shape.transpose() * mt;
            let d = damping(&shape);
            let mut m = mode(*l, shape, d);
            m.effective = std::array::from_fn(|a| gamma[a] * gamma[a]);
            m
        })
        .collect()
}

impl Modes {
    /// The modes of the linear model `lin` of a static state (every body at rest), whose
    /// bodies sit at `positions` (m, N) with attitudes `dcm_n_b`; at least two bodies.
    /// The rates of a moving state are left out: the modes are those of its configuration
    /// (the caller says so when the state moves).
    pub fn of(lin: &Linearization, positions: &[Vec3], dcm_n_b: &[Mat3]) -> Result<Self, String> {
        if lin.frame_rate.norm() > 0.0 {
            return Err("the modes are those of a structure at rest in N: for one spinning steadily, use the state matrix's eigenvalues".into());
        }
        let n = lin.bodies;
        if n < 2 {
            return Err("a structure of one body has no modes but its rigid motion".into());
        }
        let (k, c) = lin.stiffness_and_damping();
        let asymmetry = (&k - k.transpose()).norm() / k.norm().max(f64::MIN_POSITIVE);
        let k = (&k + k.transpose()) * 0.5;
        let c = (&c + c.transpose()) * 0.5;
        // Free-free.
        let (lambda, shapes) = solve(&k, &inverse_root(&lin.mass));
        let mut free: Vec<Mode> = lambda
            .iter()
            .enumerate()
            .map(|(j, l)| {
                let shape = shapes.column(j).into_owned();
                let d = shape.dot(&(&c * &shape));
                mode(*l, shape, d)
            })
            .collect();
        // The six lowest are the rigid-body modes: zero frequency by definition (their ω², at
        // round-off at an equilibrium, stays in `eigenvalue`).
        for m in free.iter_mut().take(6) {
            m.rigid = true;
            m.omega = 0.0;
            m.damping_ratio = f64::NAN;
        }
        // Hub fixed: the hub's six coordinates removed.
        let keep: Vec<usize> = (6..6 * n).collect();
        let kc = k.select_rows(keep.iter()).select_columns(keep.iter());
        let cc = c.select_rows(keep.iter()).select_columns(keep.iter());
        let (lambda_c, shapes_c) = solve(&kc, &inverse_root(&lin.mass[1..]));
        let (t, mt, total) = hub_influence(lin, positions, dcm_n_b);
        let hub_fixed = hub_fixed_modes(&lambda_c, &shapes_c, &mt, |x| x.dot(&(&cc * x)));
        Ok(Self {
            free,
            hub_fixed,
            appendage_total: std::array::from_fn(|a| total[(a, a)]),
            asymmetry,
            hub_rigid_influence: t,
        })
    }

    /// The six rigid-body modes and the `count` lowest flexible ones free-free, and the
    /// `count` lowest hub-fixed modes with their effective masses, by shift-invert Lanczos on
    /// the block-sparse K and M ([`super::lanczos`]): for large structures, where the dense
    /// [`Modes::of`] takes O(n³). The appendages' totals are exact; the hub-fixed effective
    /// masses add up to the part of them these modes carry. `asymmetry` is not computed (NaN).
    pub fn lowest(lin: &Linearization, positions: &[Vec3], dcm_n_b: &[Mat3], count: usize) -> Result<Self, String> {
        if lin.frame_rate.norm() > 0.0 {
            return Err("the modes are those of a structure at rest in N".into());
        }
        if lin.bodies < 2 {
            return Err("a structure of one body has no modes but its rigid motion".into());
        }
        if lin.bodies <= DENSE_FOR_LOWEST {
            // A small structure: every mode by the dense solver, the lowest kept (Lanczos's
            // basis would be as large as the problem, and fail to separate its modes).
            let mut all = Self::of(lin, positions, dcm_n_b)?;
            let rigid = all.free.iter().filter(|m| m.rigid).count();
            all.free.truncate(rigid + count);
            all.hub_fixed.truncate(count);
            return Ok(all);
        }
        let (k, c, m) = lin.blocks_kcm();
        let ratios: Vec<f64> = (0..lin.bodies)
            .flat_map(|i| (0..6).map(move |a| (i, a)))
            .map(|(i, a)| k.rows[i].get(&i).map_or(0.0, |b| b[(a, a)]) / m.rows[i][&i][(a, a)])
            .collect();
        let softest = ratios.iter().copied().filter(|r| *r > 0.0).fold(f64::INFINITY, f64::min);
        let stiffest = ratios.iter().copied().fold(0.0, f64::max);
        if !softest.is_finite() {
            return Err("the structure has no stiffness: every mode is rigid".into());
        }
        let make = |l: f64, shape: DVector<f64>| {
            let d = shape.dot(&c.mul(&shape));
            mode(l, shape, d)
        };
        // Free-free: the six rigid-body motions (translations along, rotations about, N's
        // axes) deflated, their modes the eigenpairs of K in their span (ω² zero to round-off
        // at an equilibrium, as the dense solver's).
        let rigid: Vec<DVector<f64>> = (0..6)
            .map(|a| {
                let axis = Vec3::ith(a % 3, 1.0);
                DVector::from_fn(6 * lin.bodies, |r, _| {
                    let (i, c) = (r / 6, r % 6);
                    let v = match (a < 3, c < 3) {
                        (true, true) => axis,
                        (true, false) => Vec3::zeros(),
                        (false, true) => axis.cross(&positions[i]),
                        (false, false) => dcm_n_b[i].transpose() * axis,
                    };
                    v[c % 3]
                })
            })
            .collect();
        let free_problem = super::lanczos::Problem::new(&k, &m, stiffest).deflating(&rigid);
        let basis = free_problem.deflated();
        let projected = DMatrix::from_fn(basis.len(), basis.len(), |i, j| basis[i].dot(&k.mul(&basis[j])));
        let e = SymmetricEigen::new((&projected + projected.transpose()) * 0.5);
        let mut free: Vec<Mode> = (0..basis.len())
            .map(|j| {
                let shape = basis
                    .iter()
                    .enumerate()
                    .fold(DVector::zeros(6 * lin.bodies), |acc, (i, b)| acc + b * e.eigenvectors[(i, j)]);
                Mode { omega: 0.0, damping_ratio: f64::NAN, rigid: true, ..make(e.eigenvalues[j], shape) }
            })
            .collect();
        free.sort_by(|x, y| x.eigenvalue.total_cmp(&y.eigenvalue));
        let (lambda, shapes) = free_problem.lowest(count)?;
        free.extend(lambda.iter().enumerate().map(|(j, l)| make(*l, shapes.column(j).into_owned())));
        // Hub fixed: no rigid motion left.
        let (kc, cc, mc) = (k.without(0), c.without(0), m.without(0));
        let fixed_problem = super::lanczos::Problem::new(&kc, &mc, stiffest);
        let (lambda_c, shapes_c) = fixed_problem.lowest(count)?;
        let (t, mt, total) = hub_influence(lin, positions, dcm_n_b);
        let hub_fixed = hub_fixed_modes(&lambda_c, &shapes_c, &mt, |x| x.dot(&cc.mul(x)));
        Ok(Self {
            free,
            hub_fixed,
            appendage_total: std::array::from_fn(|a| total[(a, a)]),
            asymmetry: f64::NAN,
            hub_rigid_influence: t,
        })
    }
}

/// Bodies up to which [`Modes::lowest`] takes every mode densely and keeps the lowest (a
/// dense eigenproblem of 360 coordinates takes milliseconds).
pub const DENSE_FOR_LOWEST: usize = 60;

/// The rigid motion the hub's unit motions give the other bodies (translations along, and
/// rotations about, the hub's axes through its centre of mass), `T`, 6(n − 1) × 6: returns
/// `M T` (the other bodies' mass times it) and `Tᵀ M T` (their mass and inertia about the hub).
fn hub_influence(
    lin: &Linearization,
    positions: &[Vec3],
    dcm_n_b: &[Mat3],
) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let n = lin.bodies;
    let hub_axes = dcm_n_b[0];
    let mut t = DMatrix::zeros(6 * (n - 1), 6);
    let mut mt = DMatrix::zeros(6 * (n - 1), 6);
    for i in 1..n {
        let arm = positions[i] - positions[0];
        let (mass, inertia) = lin.mass[i];
        for a in 0..3 {
            let axis = hub_axes.column(a).into_owned();
            let turn = dcm_n_b[i].transpose() * axis;
            t.view_mut((6 * (i - 1), a), (3, 1)).copy_from(&axis);
            t.view_mut((6 * (i - 1), 3 + a), (3, 1)).copy_from(&axis.cross(&arm));
            t.view_mut((6 * (i - 1) + 3, 3 + a), (3, 1)).copy_from(&turn);
            mt.view_mut((6 * (i - 1), a), (3, 1)).copy_from(&(axis * mass));
            mt.view_mut((6 * (i - 1), 3 + a), (3, 1)).copy_from(&(axis.cross(&arm) * mass));
            mt.view_mut((6 * (i - 1) + 3, 3 + a), (3, 1)).copy_from(&(inertia * turn));
        }
    }
    let total = t.transpose() * &mt;
    (t, mt, total)
}

/// The state `y` (crate::state's layout) displaced along a mode `shape` (6 coordinates per
/// body, or per body but the hub for a hub-fixed mode: `hub_fixed`), scaled so that its
/// largest motion is `size` (m: a translation, or a rotation times `arm`, m, a body's size):
/// positions by `δR`, attitudes by `q ⊗ (cos(|δφ|/2), sin(|δφ|/2) δφ/|δφ|)`; rates untouched.
/// What the viewer draws to show a mode.
pub fn displaced(y: &[f64], shape: &DVector<f64>, hub_fixed: bool, size: f64, arm: f64) -> Vec<f64> {
    use crate::state::{BODY_STATE_LEN as B, POS, QUAT};
    let first = usize::from(hub_fixed);
    let largest = (0..shape.len() / 6)
        .flat_map(|i| (0..6).map(move |c| (i, c)))
        .map(|(i, c)| shape[6 * i + c].abs() * if c < 3 { 1.0 } else { arm })
        .fold(0.0, f64::max);
    let scale = if largest > 0.0 { size / largest } else { 0.0 };
    let mut z = y.to_vec();
    for k in 0..shape.len() / 6 {
        let i = k + first;
        for c in 0..3 {
            z[B * i + POS + c] += scale * shape[6 * k + c];
        }
        let turn = Vec3::new(shape[6 * k + 3], shape[6 * k + 4], shape[6 * k + 5]) * scale;
        let angle = turn.norm();
        if angle > 0.0 {
            let (c, s) = ((angle / 2.0).cos(), (angle / 2.0).sin() / angle);
            let r = [c, s * turn.x, s * turn.y, s * turn.z];
            let q = [z[B * i + QUAT], z[B * i + QUAT + 1], z[B * i + QUAT + 2], z[B * i + QUAT + 3]];
            // q ⊗ r (scalar first).
            let p = [
                q[0] * r[0] - q[1] * r[1] - q[2] * r[2] - q[3] * r[3],
                q[0] * r[1] + q[1] * r[0] + q[2] * r[3] - q[3] * r[2],
                q[0] * r[2] - q[1] * r[3] + q[2] * r[0] + q[3] * r[1],
                q[0] * r[3] + q[1] * r[2] - q[2] * r[1] + q[3] * r[0],
            ];
            z[B * i + QUAT..B * i + QUAT + 4].copy_from_slice(&p);
        }
    }
    z
}

/// One mode of a structure spinning steadily: from a complex pair `λ = −ζω ± iω√(1 − ζ²)` of
/// the state matrix in the frame turning with it.
#[derive(Clone, Copy, Debug)]
pub struct SpinningMode {
    /// `|λ|`, rad/s.
    pub omega: f64,
    /// The damped frequency `Im λ`, rad/s (what the turning frame sees oscillate).
    pub damped: f64,
    /// `−Re λ / |λ|` (negative: the mode grows).
    pub damping_ratio: f64,
}

/// The modes of a structure spinning steadily at `spin` (rad/s, N) about its hub's centre of
/// mass, at the relative equilibrium `y` ([`super::equilibrium::Equilibrium::spinning`]):
/// the complex eigenvalues of the state matrix in the turning frame (dense), one per pair,
/// by `Im λ` ascending; eigenvalues with `|λ|` below `1e-6` of the largest (the rigid
/// motions, which the spin couples) and real ones are left out. Gyroscopic coupling and
/// centrifugal stiffening are in; docs/linear.md.
pub fn spinning(dynamics: &crate::dynamics::Dynamics<'_>, y: &[f64], spin: Vec3) -> Result<Vec<SpinningMode>, String> {
    let lin = Linearization::at(dynamics, y, spin)?;
    let eigen = lin.state_matrix().complex_eigenvalues();
    if eigen.iter().any(|e| !(e.re.is_finite() && e.im.is_finite())) {
        return Err(format!(
            "the state matrix spinning at {:e} rad/s has eigenvalues that are not finite in f64: give a spin rate the structure can bear",
            spin.amax()
        ));
    }
    let largest = eigen.iter().map(|e| e.norm()).fold(0.0, f64::max);
    let mut out: Vec<SpinningMode> = eigen
        .iter()
        .filter(|e| e.im > 0.0 && e.norm() > 1e-6 * largest)
        .map(|e| SpinningMode { omega: e.norm(), damped: e.im, damping_ratio: -e.re / e.norm() })
        .collect();
    out.sort_by(|a, b| a.damped.total_cmp(&b.damped));
    if out.is_empty() {
        return Err(format!(
            "no oscillating mode spinning at {:e} rad/s: every eigenvalue of the state matrix is real or negligible",
            spin.amax()
        ));
    }
    Ok(out)
}

//! Static equilibrium of a structure (docs/linear.md): the configuration where every body's
//! hinge (and contact) wrenches balance, the hub held where it is (with no external load the
//! internal wrenches sum to zero, so the hub's own balance follows: only the internal balance
//! is solved for, the rigid-body motions are removed by holding the hub).
//!
//! Newton's method on the exact Jacobian in minimal coordinates ([`super::Linearization`]):
//! with `F` the other bodies' forces and torques at rest (N, N·m; `m R̈`, `I ω̇`) and
//! `K = −M J_x` their stiffness, `K Δ = F` moves the bodies by `Δ` (positions in N, attitudes
//! by `q ⊗ (1, Δφ/2)` normalised), halving the step while the largest force grows.

use super::Linearization;
use super::sparse::Block;
use crate::dynamics::Dynamics;
use crate::kinematics::hinge_kinematics;
use crate::math::{Euler321, Vec3, skew};
use crate::state::{BODY_STATE_LEN as B, BodyMotion, OMEGA, POS, QUAT, VEL};
use nalgebra::{DMatrix, DVector};
use std::fmt::Write as _;

/// The largest turn of a body in one Newton iteration, rad (about 11°).
const MAX_TURN: f64 = 0.2;
/// The smallest damping of a Newton step before the search gives up.
const MIN_DAMPING: f64 = 1e-6;

/// The error when the forces at the start are not finite.
fn non_finite(spin: &Vec3) -> String {
    // The largest component: the norm of a spin of 1e160 rad/s overflows.
    if spin.amax() > 0.0 {
        format!(
            "the forces of a spin at {:e} rad/s are not finite in f64: give a spin rate the structure can bear",
            spin.amax()
        )
    } else {
        "the forces at the initial state are not finite".into()
    }
}

/// A static equilibrium found.
#[derive(Clone, Debug)]
pub struct Equilibrium {
    /// The state there (every body at rest).
    pub y: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// The largest force (N) or torque (N·m) left on a body.
    pub residual: f64,
    /// The largest force or torque at the start.
    pub start_residual: f64,
    /// The largest distance a body's centre of mass moved, m.
    pub moved: f64,
    /// Per hinge: δ (m, A0) and the 3-2-1 angles (rad) there.
    pub hinges: Vec<(Vec3, Euler321)>,
}

/// The forces and torques on every body but the hub (N; N·m, body frame), as one vector of
/// 6(n − 1): `m (R̈ − a)` and `I ω̇`, with `a = Ω × (Ω × (R − R_hub))` the centripetal
/// acceleration of a steady spin at `spin` (rad/s, N; zero: at rest).
fn imbalance(dynamics: &Dynamics<'_>, y: &[f64], spin: &Vec3) -> DVector<f64> {
    let model = dynamics.model();
    let mut dydt = vec![0.0; y.len()];
    dynamics.rhs(y, &mut dydt);
    let n = model.bodies.len();
    let hub = BodyMotion::from_state(y, 0).r_in_n;
    DVector::from_fn(6 * (n - 1), |k, _| {
        let (i, r) = (1 + k / 6, k % 6);
        let b = &model.bodies[i];
        if r < 3 {
            let arm = BodyMotion::from_state(y, i).r_in_n - hub;
            b.mass * (dydt[B * i + VEL + r] - spin.cross(&spin.cross(&arm))[r])
        } else {
            let alpha = Vec3::from_column_slice(&dydt[B * i + OMEGA..B * i + OMEGA + 3]);
            (b.inertia_in_body * alpha)[r - 3]
        }
    })
}

/// The rates of a steady spin at `spin` (rad/s, N) about the hub's centre of mass: every
/// body's `ω = spin` (body components) and `Ṙ = spin × (R − R_hub)`, the hub's velocity zero.
fn spin_rates(y: &mut [f64], n: usize, spin: &Vec3) {
    let hub = BodyMotion::from_state(y, 0).r_in_n;
    for i in 0..n {
        let m = BodyMotion::from_state(y, i);
        let (v, w) = (spin.cross(&(m.r_in_n - hub)), m.dcm_n_b.transpose() * spin);
        for c in 0..3 {
            y[B * i + VEL + c] = v[c];
            y[B * i + OMEGA + c] = w[c];
        }
    }
}

/// Moves every body but the hub of the `n` by `step` (6 per body: ΔR in N, Δφ in body
/// components); the state's numbers after the bodies' (hinge histories, work) are kept.
fn moved(y: &[f64], n: usize, step: &DVector<f64>, scale: f64) -> Vec<f64> {
    let mut z = y.to_vec();
    for i in 1..n {
        let d = |c: usize| scale * step[6 * (i - 1) + c];
        for c in 0..3 {
            z[B * i + POS + c] += d(c);
        }
        let q = [z[B * i + QUAT], z[B * i + QUAT + 1], z[B * i + QUAT + 2], z[B * i + QUAT + 3]];
        let (x, yy, w) = (d(3) / 2.0, d(4) / 2.0, d(5) / 2.0);
        // q ⊗ (1, Δφ/2), then normalised (the exact exponential to second order).
        let r = [
            q[0] - q[1] * x - q[2] * yy - q[3] * w,
            q[1] + q[0] * x + q[2] * w - q[3] * yy,
            q[2] + q[0] * yy - q[1] * w + q[3] * x,
            q[3] + q[0] * w + q[1] * yy - q[2] * x,
        ];
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        for (k, v) in r.iter().enumerate() {
            z[B * i + QUAT + k] = v / norm;
        }
    }
    z
}

/// Per tree hinge (model.tree's order): `[δ (m, A0), yaw, pitch, roll (rad)]` at `y`, the
/// angles unwrapped near `refs`.
fn tree_coordinates(model: &crate::model::Model, y: &[f64], refs: &[Euler321]) -> Vec<[f64; 6]> {
    model
        .tree
        .iter()
        .map(|e| {
            let h = &model.hinges[e.hinge];
            let k = hinge_kinematics(
                h,
                &BodyMotion::from_state(y, h.parent),
                &BodyMotion::from_state(y, h.child),
                &refs[e.hinge],
            );
            let (d, t) = (k.state.delta_in_a0, k.state.theta);
            [d.x, d.y, d.z, t.yaw, t.pitch, t.roll]
        })
        .collect()
}

/// The state with every tree hinge at `coordinates` (as [`tree_coordinates`]), the bodies
/// placed along the tree from the hub as `y` has it (rates zero; the numbers after the
/// bodies' kept).
fn placed(model: &crate::model::Model, y: &[f64], coordinates: &[[f64; 6]]) -> Vec<f64> {
    use crate::kinematics::{RelativeTwist, place_motion};
    let n = model.bodies.len();
    let mut motions = vec![BodyMotion::from_state(y, 0); n];
    for (e, c) in model.tree.iter().zip(coordinates) {
        let rel = RelativeTwist { delta_in_a0: Vec3::new(c[0], c[1], c[2]), ..Default::default() };
        motions[e.to] =
            place_motion(&model.hinges[e.hinge], e.reversed, &motions[e.from], Euler321::new(c[3], c[4], c[5]), &rel);
    }
    let mut z = y.to_vec();
    let bodies = crate::state::state_from_motions(model, &motions);
    z[..bodies.len()].copy_from_slice(&bodies);
    z
}

/// Newton's step `step` (maximal coordinates, as [`moved`] takes it) in the tree hinges'
/// coordinates: their derivative along it, by central differences of [`tree_coordinates`]
/// (the step is linear, its second-order part is what this leaves out).
fn step_in_tree(
    model: &crate::model::Model,
    y: &[f64],
    n: usize,
    step: &DVector<f64>,
    refs: &[Euler321],
) -> Vec<[f64; 6]> {
    let largest = step.amax().max(f64::MIN_POSITIVE);
    let eps = 1e-6 / largest;
    let plus = tree_coordinates(model, &moved(y, n, step, eps), refs);
    let minus = tree_coordinates(model, &moved(y, n, step, -eps), refs);
    plus.iter().zip(&minus).map(|(p, m)| std::array::from_fn(|k| (p[k] - m[k]) / (2.0 * eps))).collect()
}

/// `K_Ω = −M (J_x + J_v S − [Ω×]²)` (6n × 6n): the stiffness of a steady spin at `spin`
/// (rad/s, N), the rates slaved to the positions by S (per body `δṘ = Ω × δR` and
/// `δω = [ω×] δφ`, ω its rate in body components: `δ(Cᵀ Ω) = [CᵀΩ ×] δφ` for `C → C(I + [δφ×])`);
/// at rest `K = −M J_x`.
fn spinning_stiffness(lin: &Linearization, y: &[f64], spin: &Vec3) -> DMatrix<f64> {
    // By blocks: S is block diagonal, so (J_v S)_ij = J_v,ij S_j; the centripetal term sits
    // on the diagonal.
    let n = lin.bodies;
    let turn = skew(spin);
    let slaved: Vec<Block> = (0..n)
        .map(|j| {
            let omega_body = BodyMotion::from_state(y, j).dcm_n_b.transpose() * spin;
            let mut b = Block::zeros();
            b.fixed_view_mut::<3, 3>(0, 0).copy_from(&turn);
            b.fixed_view_mut::<3, 3>(3, 3).copy_from(&skew(&omega_body));
            b
        })
        .collect();
    let mut k = DMatrix::zeros(6 * n, 6 * n);
    for (i, row) in lin.blocks.iter().enumerate() {
        let mb = lin.mass_block(i);
        for (&j, (bx, bv)) in row {
            let mut a = bx + bv * slaved[j];
            if i == j {
                let mut centripetal = a.fixed_view_mut::<3, 3>(0, 0);
                centripetal -= turn * turn;
            }
            k.view_mut((6 * i, 6 * j), (6, 6)).copy_from(&(-(mb * a)));
        }
    }
    k
}

impl Equilibrium {
    /// The static equilibrium nearest `y0` (rates set to zero), the hub held: Newton until the
    /// largest force or torque on a body is below `tolerance` (N, N·m), at most
    /// `max_iterations`. Fails for a structure with loads or control (no static balance
    /// without them), locks, or when Newton stalls.
    pub fn near(dynamics: &Dynamics<'_>, y0: &[f64], tolerance: f64, max_iterations: usize) -> Result<Self, String> {
        Self::spinning(dynamics, y0, Vec3::zeros(), tolerance, max_iterations)
    }

    /// The relative equilibrium nearest `y0` of the structure spinning steadily at `spin`
    /// (rad/s, N components) about an axis through the hub's centre of mass, the hub held
    /// (with `spin` zero: the static equilibrium, as [`Self::near`]): the configuration where
    /// every body's hinge wrenches give it the centripetal acceleration `Ω × (Ω × r)` and no
    /// angular acceleration (centrifugal stiffening and the stretch of every hinge by it).
    /// Newton on `K_Ω = −M (J_x + J_v S − [Ω×]²)`, S the rates' dependence on the positions
    /// (`δṘ = Ω × δR`, `δω = [ω×] δφ`): the exact Jacobian with the rates slaved to the spin.
    pub fn spinning(
        dynamics: &Dynamics<'_>,
        y0: &[f64],
        spin: Vec3,
        tolerance: f64,
        max_iterations: usize,
    ) -> Result<Self, String> {
        // On failure the dynamics' angle branches and memories are as they were (the search
        // accepted its iterates).
        let history = (dynamics.theta_refs().clone(), dynamics.memories().clone());
        let found = Self::search(dynamics, y0, spin, tolerance, max_iterations);
        if found.is_err() {
            dynamics.restore_history(history.0, history.1);
        }
        found
    }

    fn search(
        dynamics: &Dynamics<'_>,
        y0: &[f64],
        spin: Vec3,
        tolerance: f64,
        max_iterations: usize,
    ) -> Result<Self, String> {
        let model = dynamics.model();
        if model.has_work() {
            return Err("an equilibrium of a structure with loads, motors or control: remove them (the structure's own balance is what is solved for)".into());
        }
        let n = model.bodies.len();
        if n < 2 {
            return Err("a structure of one body is in equilibrium anywhere".into());
        }
        let mut y = y0.to_vec();
        spin_rates(&mut y, n, &spin);
        dynamics.accept(0.0, &y)?;
        let mut f = imbalance(dynamics, &y, &spin);
        let start_residual = f.amax();
        if !start_residual.is_finite() {
            return Err(non_finite(&spin));
        }
        // Rotations weigh in the step's norm by each body's radius of gyration (m), so that
        // a turn and a shift that move the body's material alike count alike.
        let gyration: Vec<f64> =
            model.bodies.iter().map(|b| (b.inertia_in_body.trace() / (2.0 * b.mass)).sqrt().max(1e-6)).collect();
        let norm = |d: &DVector<f64>| {
            (0..6 * (n - 1))
                .map(|k| {
                    let w = if k % 6 < 3 { 1.0 } else { gyration[1 + k / 6] };
                    (w * d[k]).powi(2)
                })
                .sum::<f64>()
                .sqrt()
        };
        let mut iterations = 0;
        while f.amax() > tolerance || !f.iter().all(|x| x.is_finite()) {
            if !f.iter().all(|x| x.is_finite()) {
                return Err(non_finite(&spin));
            }
            if iterations == max_iterations {
                return Err(format!(
                    "no equilibrium after {max_iterations} Newton iterations: the largest force or torque left is {:.3e} (from {start_residual:.3e}); the structure may have none near its initial state (a mechanism, or a buckling load)",
                    f.amax()
                ));
            }
            iterations += 1;
            let lin = Linearization::at(dynamics, &y, Vec3::zeros())?;
            let k = spinning_stiffness(&lin, &y, &spin);
            let keep: Vec<usize> = (6..6 * n).collect();
            let kc: DMatrix<f64> = k.select_rows(keep.iter()).select_columns(keep.iter());
            let lu = kc.lu();
            let singular = "the stiffness with the hub held is singular: the structure is a mechanism (a direction with no stiffness) and has no isolated equilibrium";
            let step = lu.solve(&f).ok_or(singular)?;
            let step_norm = norm(&step);
            // Globalised Newton (Deuflhard's natural monotonicity test, *Newton Methods for
            // Nonlinear Problems*, 2004, §3.3 and NLEQ-ERR): a damped step λ is taken when the
            // simplified correction K⁻¹ F(x + λΔ) (the old factorization) shrinks below
            // (1 − λ/4) |Δ|. The test is affine invariant: a stiff direction whose force
            // jumps with the curvature of a turn (a hinge's 1e6 N/m stretch as a soft fold
            // closes) counts by the displacement that force means, not by the force, so the
            // full step passes where the largest force alone would halve it away. No body
            // turns more than MAX_TURN in one iteration, so no iterate jumps across a hinge's
            // pitch ±90°.
            let largest_turn = (1..n)
                .map(|i| Vec3::new(step[6 * (i - 1) + 3], step[6 * (i - 1) + 4], step[6 * (i - 1) + 5]).norm())
                .fold(0.0, f64::max);
            let mut scale = (MAX_TURN / largest_turn).min(1.0);
            // The step is taken in the tree hinges' coordinates: each body placed from its
            // parent by the hinge's exact kinematics, so a turn about a soft fold does not
            // stretch the stiff directions by its curvature (a step in the bodies' own
            // coordinates would, by ½ |Δφ|² times the arm).
            let refs = dynamics.theta_refs().clone();
            let from = tree_coordinates(model, &y, &refs);
            let along = step_in_tree(model, &y, n, &step, &refs);
            loop {
                let to: Vec<[f64; 6]> =
                    from.iter().zip(&along).map(|(c, d)| std::array::from_fn(|k| c[k] + scale * d[k])).collect();
                let mut z = placed(model, &y, &to);
                spin_rates(&mut z, n, &spin);
                let trial = dynamics.accept(0.0, &z).map(|()| imbalance(dynamics, &z, &spin));
                let passed = match &trial {
                    Ok(g) if g.iter().all(|x| x.is_finite()) => {
                        lu.solve(g).is_some_and(|simplified| norm(&simplified) <= (1.0 - scale / 4.0) * step_norm)
                            || g.amax() <= tolerance
                    }
                    _ => false,
                };
                if passed {
                    y = z;
                    f = trial.expect("passed");
                    break;
                }
                // Back to the iterate's own angle branches and memories.
                dynamics.accept(0.0, &y)?;
                scale *= 0.5;
                if scale < MIN_DAMPING {
                    let why = match trial {
                        // An iterate has no time: the dynamics' "at t = 0" would read as
                        // the start of a run.
                        Err(m) => format!(
                            " (the last iterate tried: {})",
                            m.replace(" at t = 0.000000 s", "").replace(" before t = 0.000000 s", "")
                        ),
                        Ok(g) if !g.iter().all(|x| x.is_finite()) => " (a trial step's forces are not finite)".into(),
                        Ok(_) => String::new(),
                    };
                    return Err(format!(
                        "no equilibrium found: after {iterations} Newton iterations no step along Newton's direction brings the structure nearer to balance{why}; the largest force or torque left is {:.3e} (from {start_residual:.3e}). The structure may have none near its initial state (a mechanism, a buckling load, or a stowed state far from any balance): start from a state nearer the equilibrium",
                        f.amax()
                    ));
                }
            }
        }
        let refs = dynamics.theta_refs().clone();
        let hinges = model
            .hinges
            .iter()
            .enumerate()
            .map(|(i, h)| {
                let k = hinge_kinematics(
                    h,
                    &BodyMotion::from_state(&y, h.parent),
                    &BodyMotion::from_state(&y, h.child),
                    &refs[i],
                );
                (k.state.delta_in_a0, k.state.theta)
            })
            .collect();
        let moved = (0..n)
            .map(|i| (BodyMotion::from_state(&y, i).r_in_n - BodyMotion::from_state(y0, i).r_in_n).norm())
            .fold(0.0, f64::max);
        Ok(Self { y, iterations, residual: f.amax(), start_residual, moved, hinges })
    }

    /// The equilibrium as `[initial]` tables a scenario takes (docs/scenario.md): the hub as
    /// `hub` gives it (position in N, m; attitude, rad) with its rate at the equilibrium
    /// (rad/s, hub components: the spin, or zero), every tree hinge's δ and angles, and every
    /// loop hinge's angles (which pick its branch at ±180°).
    pub fn initial_tables(&self, model: &crate::model::Model, hub: (Vec3, Euler321)) -> String {
        let mut s = String::new();
        let (r, a) = hub;
        let w = BodyMotion::from_state(&self.y, 0);
        let w = w.dcm_n_b.transpose() * w.omega_in_n;
        let _ = writeln!(
            s,
            "[initial.hub]\nposition = [{:?}, {:?}, {:?}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\nomega = [{:?}, {:?}, {:?}]\n",
            r.x, r.y, r.z, a.yaw, a.pitch, a.roll, w.x, w.y, w.z
        );
        for (i, h) in model.hinges.iter().enumerate() {
            let (d, t) = self.hinges[i];
            if model.is_tree_hinge[i] {
                let _ = writeln!(
                    s,
                    "[initial.hinge.{}]\ndelta = [{:?}, {:?}, {:?}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\n",
                    h.name, d.x, d.y, d.z, t.yaw, t.pitch, t.roll
                );
            } else {
                let _ = writeln!(
                    s,
                    "[initial.loop.{}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\n",
                    h.name, t.yaw, t.pitch, t.roll
                );
            }
        }
        s
    }
}

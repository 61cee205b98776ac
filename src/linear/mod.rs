//! Linear models of a structure about a state (docs/linear.md): the state matrix in minimal
//! coordinates, from the exact Jacobian of the accelerations (crate::dynamics::jacobian), and
//! its second-order form `M q̈ + C q̇ + K q = 0` for the modes ([`modes`]).
//!
//! **Coordinates.** Per body i, the position perturbation `δR_i` (m, N components) and the
//! attitude perturbation `δφ_i` (rad, body components: `q_i = q_i0 ⊗ (1, δφ_i/2)`), then the
//! velocity perturbations `δv_i` (m/s, N) and `δω_i` (rad/s, body). The state is
//! `x = [δR_0, δφ_0, …, δR_{n−1}, δφ_{n−1}, δv_0, δω_0, …]`: positions first, 12 numbers per
//! body, no redundant quaternion part. Its equations (the variational equations of the
//! bodies' kinematics and of Newton–Euler):
//!
//! `δṘ = δv − Ω × δR`, `δφ̇ = δω − ω_0 × δφ`, `δv̇ = J_x x_pos + J_v x_vel − Ω × δv`,
//! `δω̇ = J_x x_pos + J_v x_vel`,
//!
//! with `ω_0` each body's rate at the state (body components), `J_x`, `J_v` the exact
//! Jacobians of the accelerations, and `Ω` the rate of the frame the positions are taken in:
//! zero (N) for a state of a run, the spin for a structure spinning steadily as one body (a
//! relative equilibrium: in the frame that turns with it the linear system is constant).
//!
//! Locked directions are not supported yet (their constraints would remove coordinates).
//! Reaction wheels' momenta are held at their values at the state here (the bodies' part);
//! [`statespace`] adds them as states.

pub mod equilibrium;
pub mod lanczos;
pub mod modes;
pub mod reduced;
pub mod sparse;
pub mod statespace;

use crate::dynamics::Dynamics;
use crate::dynamics::jacobian::{ExactJacobian, PoseBlock, TwistBlock};
use crate::kinematics::{HingeInitial, InitialConditions};
use crate::math::{Mat3, Vec3, skew};
use crate::model::Model;
use crate::simulate::{RunSettings, Stepper};
use crate::state::{BODY_STATE_LEN as B, BodyMotion, OMEGA, QUAT};
use nalgebra::{DMatrix, SMatrix};
use sparse::{Block, BlockMatrix};
use std::collections::BTreeMap;

/// A structure's linear model about one state.
#[derive(Clone, Debug)]
pub struct Linearization {
    /// Number of bodies n.
    pub bodies: usize,
    /// Per body i, per body j coupled to it: the 6 × 6 blocks of `∂(R̈_i, ω̇_i)/∂(δR_j, δφ_j)`
    /// (rows: R̈ in N, 1/s²; ω̇ in body, rad/s²) and of `∂(R̈_i, ω̇_i)/∂(δv_j, δω_j)` (1/s):
    /// the Jacobians `J_x`, `J_v` by block, as sparse as the hinge graph.
    pub blocks: Vec<BTreeMap<usize, (Block, Block)>>,
    /// Per body: its rate at the state, rad/s, body components.
    pub omega_in_body: Vec<Vec3>,
    /// The frame's rate Ω, rad/s, N components (zero: N itself).
    pub frame_rate: Vec3,
    /// Per body: mass (kg) and inertia about its centre of mass (kg·m², body frame).
    pub mass: Vec<(f64, Mat3)>,
    /// The largest acceleration at the state that the linear model leaves out (zero at an
    /// equilibrium, or at a relative equilibrium less its centripetal part), m/s² or rad/s².
    pub residual: f64,
}

/// `∂q/∂δφ` for `q ⊗ (1, δφ/2)`: `½ [−q_vᵀ; q_w I + [q_v×]]`, 4 × 3.
fn quaternion_tangent(q: &[f64]) -> SMatrix<f64, 4, 3> {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    SMatrix::<f64, 4, 3>::new(-x, -y, -z, w, -z, y, z, w, -x, -y, x, w) * 0.5
}

impl Linearization {
    /// The linear model of `dynamics` at state `y` (time as last set), positions taken in a
    /// frame turning at `frame_rate` (rad/s, N components; zero for N). Fails for models with
    /// locked directions, or a law without an exact Jacobian. Reaction wheels' momenta are
    /// held (their own coordinates are [`statespace`]'s).
    pub fn at(dynamics: &Dynamics<'_>, y: &[f64], frame_rate: Vec3) -> Result<Self, String> {
        let model = dynamics.model();
        if dynamics.has_locks() {
            return Err("linearisation does not take locked directions yet: give the hinge stiff springs instead (docs/linear.md)".into());
        }
        let n = model.bodies.len();
        // Unit quaternions: the tangent map below is for them (the dynamics normalise too).
        let mut y = y.to_vec();
        for i in 0..n {
            let q = &mut y[B * i + QUAT..B * i + QUAT + 4];
            let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            q.iter_mut().for_each(|v| *v /= norm);
        }
        let mut blocks: Vec<BTreeMap<usize, (Block, Block)>> = vec![BTreeMap::new(); n];
        let tangents: Vec<SMatrix<f64, 4, 3>> =
            (0..n).map(|i| quaternion_tangent(&y[B * i + QUAT..B * i + QUAT + 4])).collect();
        let ok = dynamics.acceleration_jacobian(&y, &mut |i, j, dx: &PoseBlock, dv: &TwistBlock| {
            let attitude = dx.fixed_columns::<4>(3) * tangents[j];
            let (bx, bv) = blocks[i].entry(j).or_insert((Block::zeros(), Block::zeros()));
            let mut position = bx.fixed_columns_mut::<3>(0);
            position += dx.fixed_columns::<3>(0);
            let mut turn = bx.fixed_columns_mut::<3>(3);
            turn += attitude;
            *bv += dv;
        });
        if !ok {
            return Err("a hinge law has no exact Jacobian (dual form): the linear model needs one".into());
        }
        let mut dydt = vec![0.0; y.len()];
        dynamics.rhs(&y, &mut dydt);
        let mut residual: f64 = 0.0;
        let mut omega_in_body = Vec::with_capacity(n);
        for i in 0..n {
            let m = BodyMotion::from_state(&y, i);
            // At a relative equilibrium each body's acceleration is the frame's centripetal
            // one, Ω × (Ω × R): what is left over the linear model ignores.
            let centripetal = frame_rate.cross(&frame_rate.cross(&m.r_in_n));
            let a = Vec3::from_column_slice(&dydt[B * i + crate::state::VEL..B * i + crate::state::VEL + 3]);
            let alpha = Vec3::from_column_slice(&dydt[B * i + OMEGA..B * i + OMEGA + 3]);
            residual = residual.max((a - centripetal).amax()).max(alpha.amax());
            omega_in_body.push(m.omega_in_body());
        }
        Ok(Self {
            bodies: n,
            blocks,
            omega_in_body,
            frame_rate,
            mass: model.bodies.iter().map(|b| (b.mass, b.inertia_in_body)).collect(),
            residual,
        })
    }

    /// `J_x` (0) or `J_v` (1) as a dense 6n × 6n matrix.
    fn dense(&self, which: usize) -> DMatrix<f64> {
        let mut out = DMatrix::zeros(6 * self.bodies, 6 * self.bodies);
        for (i, row) in self.blocks.iter().enumerate() {
            for (&j, b) in row {
                out.view_mut((6 * i, 6 * j), (6, 6)).copy_from(if which == 0 { &b.0 } else { &b.1 });
            }
        }
        out
    }

    /// `∂(R̈, ω̇)/∂(δR, δφ)`, dense 6n × 6n.
    pub fn jx(&self) -> DMatrix<f64> {
        self.dense(0)
    }

    /// `∂(R̈, ω̇)/∂(δv, δω)`, dense 6n × 6n.
    pub fn jv(&self) -> DMatrix<f64> {
        self.dense(1)
    }

    /// By blocks: the symmetric parts of `K = −M J_x` and `C = −M J_v`, and M (per body
    /// `m I₃` and its inertia).
    pub fn blocks_kcm(&self) -> (BlockMatrix, BlockMatrix, BlockMatrix) {
        let n = self.bodies;
        let (mut k, mut c, mut m) = (BlockMatrix::new(n), BlockMatrix::new(n), BlockMatrix::new(n));
        for i in 0..n {
            let mb = self.mass_block(i);
            m.add(i, i, &mb);
            for (&j, (bx, bv)) in &self.blocks[i] {
                let (kb, cb) = (-(mb * bx) * 0.5, -(mb * bv) * 0.5);
                k.add(i, j, &kb);
                k.add(j, i, &kb.transpose());
                c.add(i, j, &cb);
                c.add(j, i, &cb.transpose());
            }
        }
        (k, c, m)
    }

    /// Body `i`'s mass block: `m I₃` (kg) and its inertia (kg·m², body frame).
    pub fn mass_block(&self, i: usize) -> Block {
        let (mass, inertia) = &self.mass[i];
        let mut mb = Block::zeros();
        for a in 0..3 {
            mb[(a, a)] = *mass;
        }
        mb.fixed_view_mut::<3, 3>(3, 3).copy_from(inertia);
        mb
    }

    /// The state matrix A (12n × 12n) in the coordinates of the module documentation.
    pub fn state_matrix(&self) -> DMatrix<f64> {
        let n6 = 6 * self.bodies;
        let mut a = DMatrix::zeros(2 * n6, 2 * n6);
        let spin = skew(&self.frame_rate);
        for i in 0..self.bodies {
            let w = skew(&self.omega_in_body[i]);
            for r in 0..3 {
                for c in 0..3 {
                    a[(6 * i + r, 6 * i + c)] = -spin[(r, c)];
                    a[(6 * i + 3 + r, 6 * i + 3 + c)] = -w[(r, c)];
                    a[(n6 + 6 * i + r, n6 + 6 * i + c)] -= spin[(r, c)];
                }
            }
        }
        for k in 0..n6 {
            a[(k, n6 + k)] += 1.0;
        }
        a.view_mut((n6, 0), (n6, n6)).copy_from(&self.jx());
        let mut lower_right = a.view_mut((n6, n6), (n6, n6));
        lower_right += &self.jv();
        a
    }

    /// The mass matrix M (6n × 6n): per body `m I₃` and its inertia (body frame).
    pub fn mass_matrix(&self) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(6 * self.bodies, 6 * self.bodies);
        for (i, (mass, inertia)) in self.mass.iter().enumerate() {
            for k in 0..3 {
                m[(6 * i + k, 6 * i + k)] = *mass;
            }
            m.view_mut((6 * i + 3, 6 * i + 3), (3, 3)).copy_from(inertia);
        }
        m
    }

    /// Stiffness and damping matrices `K = −M J_x`, `C = −M J_v` (6n × 6n): the second-order
    /// form `M q̈ + C q̇ + K q = 0` of a static state (no rates). K is symmetric for laws with a
    /// potential, not for law 1 (docs/linear.md).
    pub fn stiffness_and_damping(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let m = self.mass_matrix();
        (-(&m * self.jx()), -(&m * self.jv()))
    }
}

/// The design state of `model` as initial conditions: every tree hinge's δ and angles zero,
/// every body at rest, the hub placed as `ic` places it. For a generated structure this is
/// the deployed design, stress-free where its laws rest at zero (the generators' laws do): an
/// equilibrium then (`Linearization::residual` says how far from one it is).
pub fn design_state(model: &Model, ic: &InitialConditions) -> InitialConditions {
    InitialConditions {
        hub_position_in_n: ic.hub_position_in_n,
        hub_attitude: ic.hub_attitude,
        hinges: model.is_tree_hinge.iter().map(|&t| t.then(HingeInitial::default)).collect(),
        ..InitialConditions::default()
    }
}

/// Where a linear analysis takes `model`'s state: the run from `ic` to time `at` (s), or the
/// design state with `deployed` ([`design_state`]; `at` must then be 0). Returns the initial
/// conditions to run from; fails, naming what is valid, for a time outside the run.
pub fn start_for(
    model: &Model,
    ic: &InitialConditions,
    settings: &mut RunSettings,
    at: f64,
    deployed: bool,
) -> Result<InitialConditions, String> {
    if !(at >= 0.0 && at <= settings.duration) {
        return Err(format!("{at} s: the time must lie between 0 and run.duration = {} s", settings.duration));
    }
    if deployed && at > 0.0 {
        return Err(format!("{at} s: the design state is taken as it is, not at a time of a run"));
    }
    if deployed {
        // The design state is free of the launch restraint, which holds the stowed package.
        settings.release_at = None;
    }
    if let Some(release) = settings.release_at
        && at < release
    {
        return Err(format!(
            "{at} s: the launch restraint holds every tree hinge until run.release_at = {release} s, so the structure has no motion of its own there; give a time at or after the release (--at {release}) or the design state (--deployed)"
        ));
    }
    Ok(if deployed { design_state(model, ic) } else { ic.clone() })
}

/// A structure's state where it is linearised: its time and how far it is from rest.
#[derive(Clone, Debug)]
pub struct Where {
    /// Time, s.
    pub t: f64,
    /// Per body: centre of mass, m, N components.
    pub positions: Vec<Vec3>,
    /// Per body: `[N b]`.
    pub dcm_n_b: Vec<Mat3>,
    /// The largest body rate, rad/s, and velocity, m/s, there.
    pub largest_rates: (f64, f64),
    /// When the state asked for was at rest but out of balance: the static equilibrium
    /// nearest it was found and taken instead, with this many Newton iterations, the bodies
    /// moved up to this far (m), and this largest acceleration at the state asked for
    /// (m/s² or rad/s²).
    pub balanced: Option<(usize, f64, f64)>,
    /// When the state asked for was at rest, out of balance, and no equilibrium was found
    /// near it: why (the state is then taken as it is).
    pub unbalanced: Option<String>,
    /// The state itself (as [`crate::state`] lays it out): the one the model is of.
    pub state: Vec<f64>,
}

/// Whether `lin`'s residual acceleration is out of balance: above 1e-8 of the largest
/// stiffness (the diagonal of J_x, 1/s²) times the structure's size (m), with a floor of
/// 1e-12 m/s². The round-off of the hinge forces is ~1e-16 of that.
fn out_of_balance(lin: &Linearization, positions: &[Vec3]) -> bool {
    let stiffest = lin
        .blocks
        .iter()
        .enumerate()
        .filter_map(|(i, row)| row.get(&i))
        .map(|(bx, _)| (0..6).map(|k| bx[(k, k)].abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    let size = positions.iter().map(|r| (r - positions[0]).norm()).fold(1e-3, f64::max);
    lin.residual > (1e-8 * stiffest * size).max(1e-12)
}

/// The linear model of `model` at time `at` (s) of its run from `ic` with `settings` (at its
/// initial state for `at = 0`), positions in N, and where that is.
pub fn linearize_at(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    at: f64,
) -> Result<(Linearization, Where), String> {
    let mut stepper = Stepper::start(model, ic, settings).map_err(|e| e.to_string())?;
    if at > 0.0 {
        stepper.advance(at).map_err(|e| e.to_string())?;
    }
    let mut y = stepper.state().to_vec();
    let mut lin = Linearization::at(stepper.dynamics(), &y, Vec3::zeros())?;
    let positions =
        |y: &[f64]| (0..model.bodies.len()).map(|i| BodyMotion::from_state(y, i).r_in_n).collect::<Vec<_>>();
    let at_rest = (0..model.bodies.len()).all(|i| {
        let m = BodyMotion::from_state(&y, i);
        m.omega_in_n.norm() == 0.0 && m.v_in_n.norm() == 0.0
    });
    let (mut balanced, mut unbalanced) = (None, None);
    if at_rest && out_of_balance(&lin, &positions(&y)) {
        // Modes about a state out of balance are no modes (its stiffness is not that of a
        // vibration about it: negative ω², NaN frequencies): the equilibrium nearest it.
        let d = stepper.dynamics();
        // Balanced to 1e-9 m/s² times the heaviest body's mass or inertia (N, N·m): above
        // the round-off of stiff hinges' forces (1e-16 of 1e6 N/m times a metre).
        let force_scale = model.bodies.iter().map(|b| b.mass.max(b.inertia_in_body.amax())).fold(0.0, f64::max);
        match equilibrium::Equilibrium::near(d, &y, 1e-9 * force_scale, 50) {
            Ok(found) => {
                d.accept(stepper.time(), &found.y)?;
                balanced = Some((found.iterations, found.moved, lin.residual));
                y = found.y;
                lin = Linearization::at(d, &y, Vec3::zeros())?;
            }
            Err(e) => {
                // The state as it is: the modes of its configuration, with the reason.
                d.accept(stepper.time(), &y)?;
                unbalanced = Some(format!(
                    "the state at t = {} s is at rest but out of balance (largest acceleration {:.3e} m/s² or rad/s²), and the search for the equilibrium nearest it failed: {e}",
                    stepper.time(),
                    lin.residual
                ));
            }
        }
    }
    let motions: Vec<BodyMotion> = (0..model.bodies.len()).map(|i| BodyMotion::from_state(&y, i)).collect();
    let largest_rates =
        motions.iter().fold((0.0f64, 0.0f64), |(w, v), m| (w.max(m.omega_in_n.norm()), v.max(m.v_in_n.norm())));
    Ok((
        lin,
        Where {
            t: stepper.time(),
            positions: motions.iter().map(|m| m.r_in_n).collect(),
            dcm_n_b: motions.iter().map(|m| m.dcm_n_b).collect(),
            largest_rates,
            balanced,
            unbalanced,
            state: y,
        },
    ))
}

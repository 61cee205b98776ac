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
use crate::dynamics::Dynamics;
use crate::kinematics::hinge_kinematics;
use crate::math::{Euler321, Vec3};
use crate::state::{BODY_STATE_LEN as B, BodyMotion, OMEGA, POS, QUAT, VEL};
use nalgebra::{DMatrix, DVector};
use std::fmt::Write as _;

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

/// The forces and torques on every body but the hub at rest (N; N·m, body frame), as one
/// vector of 6(n − 1).
fn imbalance(dynamics: &Dynamics<'_>, y: &[f64]) -> DVector<f64> {
    let model = dynamics.model();
    let mut dydt = vec![0.0; y.len()];
    dynamics.rhs(y, &mut dydt);
    let n = model.bodies.len();
    DVector::from_fn(6 * (n - 1), |k, _| {
        let (i, r) = (1 + k / 6, k % 6);
        let b = &model.bodies[i];
        if r < 3 {
            b.mass * dydt[B * i + VEL + r]
        } else {
            let alpha = Vec3::from_column_slice(&dydt[B * i + OMEGA..B * i + OMEGA + 3]);
            (b.inertia_in_body * alpha)[r - 3]
        }
    })
}

/// Moves every body but the hub by `step` (6 per body: ΔR in N, Δφ in body components).
fn moved(y: &[f64], step: &DVector<f64>, scale: f64) -> Vec<f64> {
    let mut z = y.to_vec();
    for i in 1..y.len() / B {
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

impl Equilibrium {
    /// The static equilibrium nearest `y0` (rates set to zero), the hub held: Newton until the
    /// largest force or torque on a body is below `tolerance` (N, N·m), at most
    /// `max_iterations`. Fails for a structure with loads or control (no static balance
    /// without them), locks, or when Newton stalls.
    pub fn near(dynamics: &Dynamics<'_>, y0: &[f64], tolerance: f64, max_iterations: usize) -> Result<Self, String> {
        let model = dynamics.model();
        if model.has_work() {
            return Err("an equilibrium of a structure with loads, motors or control: remove them (the structure's own balance is what is solved for)".into());
        }
        let n = model.bodies.len();
        if n < 2 {
            return Err("a structure of one body is in equilibrium anywhere".into());
        }
        let mut y = y0.to_vec();
        for i in 0..n {
            for c in 0..3 {
                y[B * i + VEL + c] = 0.0;
                y[B * i + OMEGA + c] = 0.0;
            }
        }
        dynamics.accept(0.0, &y)?;
        let mut f = imbalance(dynamics, &y);
        let start_residual = f.amax();
        let mut iterations = 0;
        while f.amax() > tolerance {
            if iterations == max_iterations {
                return Err(format!(
                    "no equilibrium after {max_iterations} Newton iterations: the largest force or torque left is {:.3e} (from {start_residual:.3e}); the structure may have none near its initial state (a mechanism, or a buckling load)",
                    f.amax()
                ));
            }
            iterations += 1;
            let lin = Linearization::at(dynamics, &y, Vec3::zeros())?;
            let (k, _) = lin.stiffness_and_damping();
            let keep: Vec<usize> = (6..6 * n).collect();
            let kc: DMatrix<f64> = k.select_rows(keep.iter()).select_columns(keep.iter());
            let step = kc.lu().solve(&f).ok_or("the stiffness with the hub held is singular: the structure is a mechanism (a direction with no stiffness) and has no isolated equilibrium")?;
            // Halve the step while the imbalance does not shrink.
            let mut scale = 1.0;
            loop {
                let z = moved(&y, &step, scale);
                dynamics.accept(0.0, &z)?;
                let g = imbalance(dynamics, &z);
                if g.amax() < f.amax() || scale < 1e-6 {
                    y = z;
                    f = g;
                    break;
                }
                scale *= 0.5;
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
    /// `hub` gives it (position in N, m; attitude, rad), every tree hinge's δ and angles, and
    /// every loop hinge's angles (which pick its branch at ±180°).
    pub fn initial_tables(&self, model: &crate::model::Model, hub: (Vec3, Euler321)) -> String {
        let mut s = String::new();
        let (r, a) = hub;
        let _ = writeln!(
            s,
            "[initial.hub]\nposition = [{:?}, {:?}, {:?}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\n",
            r.x, r.y, r.z, a.yaw, a.pitch, a.roll
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

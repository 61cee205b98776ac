//! The exact Jacobian of the bodies' accelerations, by dual numbers, for the implicit path.
//!
//! A hinge's wrench depends on the 13 state numbers of its parent and the 13 of its child
//! only. Seeding one body's 13 as dual directions ([`crate::law::JacobianDual`]), the other's
//! held at their values, and evaluating the same kinematics and law code the right-hand side
//! runs (generic over [`crate::math::Real`]) gives the hinge's contribution to the two
//! bodies' accelerations and its exact derivatives in that body's state; a second pass does
//! the other body. (One pass in 26 lanes gives the same numbers, lane for lane, but a
//! 26-lane dual is too large to copy in registers: its copies were a quarter of the
//! 228-panel starshade's run, calls to `memmove`; in two 13-lane passes the held side's
//! numbers carry no derivative at all.) Per body, the rotation of the total torque into body
//! components and the gyroscopic term `ω × Iω` depend on the body's own attitude and rate;
//! one more pass per body differentiates those. The cost is linear in bodies plus hinges,
//! with no differencing step to choose.
//!
//! Laws differentiate through [`crate::law::HingeLaw::wrench_dual`] with their memory
//! (hysteresis branch, stop contact) held, as the piecewise-smooth response is between
//! events. With locked directions this is the Jacobian of the accelerations before the
//! constraint forces; the Newton matrix adds the constraints themselves as rows
//! ([`ExactJacobian::constraint_jacobian`], see [`super::newton`]). A law without a dual form
//! makes the caller fall back to finite differences.

use super::Dynamics;
use super::contact_pair::PairSum;
use super::lanes::{D13, D26 as D, seeded13};
use super::locks::{Lock, hinge_rows};
use crate::kinematics::{ChildSide, ParentSide, hinge_kinematics, kinematics_of_sides};
use crate::math::{const_mat_vec, cross, lift, mat_tr_vec, mat_vec, re, real};
use crate::state::{BODY_STATE_LEN as B, BodyMotion, OMEGA, VEL};
use nalgebra::{Const, SMatrix, U1, Vector3};

/// Derivatives of a body's 6 accelerations (R̈ in N components, ω̇ in body components) with
/// respect to another body's pose (R, q): 6×7.
pub type PoseBlock = SMatrix<f64, 6, 7>;
/// The same with respect to its twist (Ṙ, ω): 6×6.
pub type TwistBlock = SMatrix<f64, 6, 6>;

/// Receives Jacobian blocks: `(row body i, column body j, ∂a_i/∂x_j, ∂a_i/∂v_j)`, to be
/// added (a pair of bodies can receive several).
pub type BlockSink<'s> = dyn FnMut(usize, usize, &PoseBlock, &TwistBlock) + 's;

/// A system that can give the exact Jacobian of its accelerations in body blocks.
pub trait ExactJacobian {
    /// Sends every block of `∂(R̈, ω̇)/∂(x, v)` at state `y` to `add`. Returns false when it
    /// cannot (a hinge law without a dual form), having sent the blocks of the hinges before
    /// that one: the caller discards what it received and differences (the Newton matrix
    /// overwrites every block it differences). With locked directions these are the
    /// accelerations before the constraint forces (see [`Self::constraint_jacobian`]).
    fn acceleration_jacobian(&self, y: &[f64], add: &mut BlockSink<'_>) -> bool;

    /// The hinges with locked directions, as (parent body, child body, number of locked
    /// directions), in hinge order. Empty when nothing is locked.
    fn locked_hinges(&self) -> Vec<(usize, usize, usize)> {
        Vec::new()
    }

    /// Body pairs whose accelerations are coupled at `y` besides the hinges' (bodies in
    /// contact): the Newton matrix makes room for their blocks before asking for them.
    fn coupled_pairs(&self, _y: &[f64]) -> Vec<(usize, usize)> {
        Vec::new()
    }

    /// The contact's part of [`Self::acceleration_jacobian`] at `y` alone: the blocks that
    /// the forces of the points in contact add, with their torques' share of each body's
    /// attitude derivative (linear in the torque: the rest's share is the rest's). The full
    /// Jacobian is the rest's blocks plus these, so that a Newton matrix can bring its
    /// contact part up to date at a new state and keep the rest (see
    /// [`crate::integrate::NewtonMatrix::refresh_contact`]). False when there is no such
    /// split (no contact), sending nothing.
    fn contact_jacobian(&self, _y: &[f64], _add: &mut BlockSink<'_>) -> bool {
        false
    }

    /// The rest of [`Self::acceleration_jacobian`] at `y`, all but [`Self::contact_jacobian`]'s
    /// blocks; false (having sent what it sent, as `acceleration_jacobian`) when there is no
    /// such split or a law has no dual form.
    fn rest_jacobian(&self, _y: &[f64], _add: &mut BlockSink<'_>) -> bool {
        false
    }

    /// The locks at `y`, for a Newton matrix that carries them as rows: sends to `add` the
    /// blocks of the constraint wrenches' derivatives with the multipliers held
    /// (`∂(M⁻¹ Jᵀ λ)/∂(x, v)`), and returns the engaged locks' rows (see
    /// [`crate::dynamics::Dynamics::disengage_locks`]). Returns no rows (and sends nothing)
    /// when every lock is idle there: the free accelerations satisfy the locks to round-off
    /// and the multipliers are zero (see [`crate::dynamics::locks::constrain_accelerations`]).
    fn constraint_jacobian(&self, _y: &[f64], _add: &mut BlockSink<'_>) -> LockRows {
        LockRows::default()
    }
}

/// The locks a Newton matrix carries at a state.
#[derive(Clone, Debug, Default)]
pub struct LockRows {
    /// The hinges carried, in hinge order, as (parent body, child body, number of rows).
    pub groups: Vec<(usize, usize, usize)>,
    /// Their rows, grouped by hinge in that order.
    pub rows: Vec<ConstraintRow>,
}

/// One lock's row for the Newton matrix, per side (0: the hinge's parent, 1: its child), in
/// the body's twist components (linear: N, angular: body).
#[derive(Clone, Copy, Debug, Default)]
pub struct ConstraintRow {
    /// `J`: the locked coordinate's acceleration is `J a + γ`.
    pub j: [[f64; 6]; 2],
    /// `M⁻¹ Jᵀ`.
    pub m_inv_j: [[f64; 6]; 2],
    /// `∂(J a + γ)/∂x` (pose: R, q) with the accelerations a held at their constrained
    /// values.
    pub d_pose: [[f64; 7]; 2],
    /// `∂(J a + γ)/∂v` (twist), likewise.
    pub d_twist: [[f64; 6]; 2],
}

/// The 26 derivatives of a dual number.
fn lanes(x: &D) -> SMatrix<f64, 26, 1> {
    x.eps.unwrap_generic(Const::<26>, U1)
}

/// One body's 13 state numbers as dual numbers seeded at lanes `first..first + 13`.
fn seeded(s: &[f64], first: usize) -> [D; B] {
    std::array::from_fn(|k| D::from_re(s[k]).derivative(first + k))
}

/// A body's six acceleration rows (R̈ in N, ω̇ in body components) from a force and torque in N
/// components: `R̈ = F / m`, `ω̇ = I⁻¹ [b N] τ` with `[b N]` held at `dcm_n_b` (its attitude
/// derivative is taken per body, on the total torque).
fn accel_rows<T: crate::math::Real + std::ops::Mul<f64, Output = T>>(
    bd: &crate::model::Body,
    dcm_n_b: &nalgebra::Matrix3<f64>,
    force: &Vector3<T>,
    torque: &Vector3<T>,
) -> [T; 6] {
    let inv_m = 1.0 / bd.mass;
    let alpha = const_mat_vec(&(bd.inertia_inv_in_body * dcm_n_b.transpose()), torque);
    [force.x * inv_m, force.y * inv_m, force.z * inv_m, alpha.x, alpha.y, alpha.z]
}

/// The blocks of a body's six acceleration rows (R̈ then ω̇) in the 13 lanes of the body
/// seeded.
fn block(rows: &[D13; 6]) -> (PoseBlock, TwistBlock) {
    let mut out = (PoseBlock::zeros(), TwistBlock::zeros());
    for (r, x) in rows.iter().enumerate() {
        let Some(g) = &x.eps.0 else { continue };
        for k in 0..7 {
            out.0[(r, k)] = g[k];
        }
        for k in 0..6 {
            out.1[(r, k)] = g[7 + k];
        }
    }
    out
}

/// Splits the lanes of a body's six acceleration rows (R̈ then ω̇) into the blocks of the
/// body seeded at lanes 0..13 and of the body seeded at 13..26.
fn split(rows: &[D; 6]) -> [(PoseBlock, TwistBlock); 2] {
    let mut out = [(PoseBlock::zeros(), TwistBlock::zeros()); 2];
    for (r, x) in rows.iter().enumerate() {
        let g = lanes(x);
        for (side, (dx, dv)) in out.iter_mut().enumerate() {
            for k in 0..7 {
                dx[(r, k)] = g[13 * side + k];
            }
            for k in 0..6 {
                dv[(r, k)] = g[13 * side + 7 + k];
            }
        }
    }
    out
}

/// Which parts of the Jacobian [`Dynamics::jacobian_parts`] sends.
#[derive(Clone, Copy)]
struct Parts {
    /// The hinges, motors, loads, control and the bodies' gyroscopic terms.
    rest: bool,
    /// The contact points.
    contact: bool,
}

impl Dynamics<'_> {
    /// The blocks of `parts` of the accelerations' Jacobian at `y` (see
    /// [`ExactJacobian::acceleration_jacobian`]; the two parts add up to the whole).
    fn jacobian_parts(&self, y: &[f64], add: &mut BlockSink<'_>, parts: Parts) -> bool {
        let model = self.model();
        let refs = self.theta_refs();
        let memories = self.memories();
        let nb = model.bodies.len();
        let body = |i: usize| &y[B * i..B * (i + 1)];
        let motions: Vec<BodyMotion> = (0..nb).map(|i| BodyMotion::from_state(y, i)).collect();
        // Per body: total hinge torque, N components (for the rotation into body components).
        let mut torque_in_n = vec![Vector3::<f64>::zeros(); nb];
        let t = self.time.get();
        // Each body's motion in its own 13 lanes, once; each hinge's one-body quantities in
        // those lanes too, and the hinge evaluated twice: with the parent's lanes and the
        // child's values held, then the other way round (see the module documentation).
        let own: Vec<BodyMotion<D13>> =
            (0..nb).map(|i| BodyMotion::<D13>::from_body_state(&seeded13(body(i)))).collect();
        let held = |x: D13| D13::from_re(x.re);
        for (i, h) in model.hinges.iter().enumerate().filter(|_| parts.rest) {
            let p = ParentSide::new(h, &own[h.parent]);
            let c = ChildSide::new(h, &own[h.child]);
            for (pass, (column, p, c)) in
                [(h.parent, p, c.map(held)), (h.child, p.map(held), c)].into_iter().enumerate()
            {
                let k = kinematics_of_sides(&p, &c, &refs[i]);
                let Some(mut w) = h.law.wrench_dual(&k.state, &memories[i]) else { return false };
                if let Some((motor, _)) = self.motor_wrench(i, &k.state, t) {
                    w.force_in_a0 += motor.force_in_a0;
                    w.torque_in_a += motor.torque_in_a;
                }
                let f_n = mat_vec(&k.dcm_n_a0, &w.force_in_a0);
                let tau_n = mat_vec(&k.dcm_n_a, &w.torque_in_a);
                let on_parent = (f_n, cross(&k.arm_parent_in_n, &f_n) + tau_n);
                let on_child = (-f_n, -(cross(&k.arm_child_in_n, &f_n) + tau_n));
                for (b, (force, torque)) in [(h.parent, on_parent), (h.child, on_child)] {
                    if pass == 0 {
                        torque_in_n[b] += torque.map(re);
                    }
                    // R̈ = F / m; ω̇ = I⁻¹ ([b N] τ − ω × Iω), here the τ part with [b N]
                    // held (its attitude derivative is taken per body below, on the total
                    // torque).
                    let rows = accel_rows(&model.bodies[b], &motions[b].dcm_n_b, &force, &torque);
                    let (dx, dv) = block(&rows);
                    add(b, column, &dx, &dv);
                }
            }
        }
        // Contact points: the same code as the right-hand side's, in dual numbers, each
        // point's impact speed held (crate::contact::ContactSet::point_force).
        if parts.contact
            && let Some(set) = &model.contact
        {
            let memory = self.contact_memory();
            // The points come grouped by pair: the two seeded motions once per pair, and the
            // pair's force and its moment about each body's centre summed over its points
            // before the accelerations are formed (once per pair, not per point).
            let mut pair: Option<PairSum> = None;
            let flush = |sum: PairSum, add: &mut BlockSink<'_>, torque_in_n: &mut Vec<Vector3<f64>>| {
                let (a, b) = sum.bodies;
                let (force_in_b, moment_about_a_in_b, moment_about_b_in_b) = sum.force_and_moments();
                let force_in_n = sum.dcm_n_b * force_in_b;
                let on_a = (force_in_n, sum.dcm_n_b * moment_about_a_in_b);
                let on_b = (-force_in_n, -(sum.dcm_n_b * moment_about_b_in_b));
                for (body_index, (force, torque)) in [(a, on_a), (b, on_b)] {
                    torque_in_n[body_index] += torque.map(re);
                    let rows = accel_rows(&model.bodies[body_index], &motions[body_index].dcm_n_b, &force, &torque);
                    let [(ax, av), (bx, bv)] = split(&rows);
                    add(body_index, a, &ax, &av);
                    add(body_index, b, &bx, &bv);
                }
            };
            // The points `coupled_pairs` found at this state, else found now.
            let cached = self.jacobian_points.borrow_mut().take();
            let points = match cached {
                Some((at, points)) if at == y => points,
                _ => self.contact_points(y),
            };
            for p in points {
                let (a, b) = (p.key.body as usize, p.key.other as usize);
                let Some((sample, solid)) = set.sample_and_solid(&p.key) else { continue };
                if pair.as_ref().is_none_or(|s| s.bodies != (a, b)) {
                    if let Some(done) = pair.take() {
                        flush(done, add, &mut torque_in_n);
                    }
                    pair = Some(PairSum::new((a, b), &own[a], &own[b]));
                }
                if let Some(sum) = pair.as_mut() {
                    sum.add(set, sample, solid, memory.get(&p.key).copied());
                }
            }
            if let Some(done) = pair.take() {
                flush(done, add, &mut torque_in_n);
            }
        }
        // External loads (crate::loads): one fixed in its body's frame, or acting off the
        // centre of mass, turns with the body, so its wrench depends on the attitude. The
        // hub's control depends on the hub's attitude and rate (the wheel momenta held).
        let mut self_block = |b: usize, force: Vector3<D13>, torque: Vector3<D13>| {
            torque_in_n[b] += torque.map(re);
            let rows = accel_rows(&model.bodies[b], &motions[b].dcm_n_b, &force, &torque);
            let (dx, dv) = block(&rows);
            add(b, b, &dx, &dv);
        };
        if parts.rest {
            for load in model.loads.iter().chain(self.commanded.borrow().iter()) {
                let (force, torque) = load.wrench(t, &own[load.body].dcm_n_b);
                self_block(load.body, force, torque);
            }
            let wi = crate::state::wheel_index(model);
            let hub = seeded13(body(0));
            if let Some(tau_b) = self.control_torque(&hub, &y[wi..wi + model.wheel_count()]) {
                self_block(0, Vector3::zeros(), own[0].dcm_n_b * tau_b);
            }
        }
        // Per body: ω̇ = I⁻¹ ([b N](q) τ_total − ω × Iω) in its own attitude and rate; linear in
        // τ, so that each part takes its own torques' share (the gyroscopic term the rest's).
        for (i, bd) in model.bodies.iter().enumerate() {
            let s = seeded13(body(i));
            let omega_b = Vector3::new(s[OMEGA], s[OMEGA + 1], s[OMEGA + 2]);
            let tau_b = mat_tr_vec(&own[i].dcm_n_b, &torque_in_n[i].map(real::<D13>));
            let i_omega = const_mat_vec(&bd.inertia_in_body, &omega_b);
            let gyroscopic = if parts.rest { cross(&omega_b, &i_omega) } else { Vector3::zeros() };
            let alpha = const_mat_vec(&bd.inertia_inv_in_body, &(tau_b - gyroscopic));
            let (dx, dv) = block(&[D13::from_re(0.0), D13::from_re(0.0), D13::from_re(0.0), alpha.x, alpha.y, alpha.z]);
            add(i, i, &dx, &dv);
        }
        true
    }
}

impl ExactJacobian for Dynamics<'_> {
    fn acceleration_jacobian(&self, y: &[f64], add: &mut BlockSink<'_>) -> bool {
        self.jacobian_parts(y, add, Parts { rest: true, contact: true })
    }

    fn contact_jacobian(&self, y: &[f64], add: &mut BlockSink<'_>) -> bool {
        self.model().contact.is_some() && self.jacobian_parts(y, add, Parts { rest: false, contact: true })
    }

    fn rest_jacobian(&self, y: &[f64], add: &mut BlockSink<'_>) -> bool {
        self.model().contact.is_some() && self.jacobian_parts(y, add, Parts { rest: true, contact: false })
    }

    fn coupled_pairs(&self, y: &[f64]) -> Vec<(usize, usize)> {
        let points = self.contact_points(y);
        let mut pairs: Vec<(usize, usize)> = points
            .iter()
            .map(|p| {
                let (a, b) = (p.key.body as usize, p.key.other as usize);
                (a.min(b), a.max(b))
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        if !points.is_empty() {
            *self.jacobian_points.borrow_mut() = Some((y.to_vec(), points));
        }
        pairs
    }

    fn locked_hinges(&self) -> Vec<(usize, usize, usize)> {
        let model = self.model();
        self.locks()
            .chunk_by(|a, b| a.hinge == b.hinge)
            .map(|g| (model.hinges[g[0].hinge].parent, model.hinges[g[0].hinge].child, g.len()))
            .collect()
    }

    fn constraint_jacobian(&self, y: &[f64], add: &mut BlockSink<'_>) -> LockRows {
        let model = self.model();
        // Disengaged locks have zero multipliers, as has a failed multiplier solve (locks
        // momentarily redundant): the wrench derivatives are then left out (Newton still
        // converges, more slowly).
        let (dydt, lambda) = self.rhs_and_multipliers(y);
        let locks = self.locks();
        if lambda.iter().all(|l| *l == 0.0) {
            return LockRows::default();
        }
        let refs = self.theta_refs();
        // The engaged locks, with their multipliers, grouped by hinge.
        let engaged: Vec<(Lock, f64)> = locks
            .iter()
            .zip(self.engaged_locks().iter())
            .zip(&lambda)
            .filter(|((_, e), _)| **e)
            .map(|((l, _), m)| (*l, *m))
            .collect();
        let body = |i: usize| &y[B * i..B * (i + 1)];
        let accel = |i: usize| -> [f64; 6] {
            let o = B * i;
            [
                dydt[o + VEL],
                dydt[o + VEL + 1],
                dydt[o + VEL + 2],
                dydt[o + OMEGA],
                dydt[o + OMEGA + 1],
                dydt[o + OMEGA + 2],
            ]
        };
        let mut out = LockRows::default();
        for engaged_group in engaged.chunk_by(|a, b| a.0.hinge == b.0.hinge) {
            let group: Vec<Lock> = engaged_group.iter().map(|(l, _)| *l).collect();
            let lam: Vec<f64> = engaged_group.iter().map(|(_, m)| *m).collect();
            let hinge = group[0].hinge;
            let h = &model.hinges[hinge];
            let p = BodyMotion::<D>::from_body_state(&seeded(body(h.parent), 0));
            let c = BodyMotion::<D>::from_body_state(&seeded(body(h.child), B));
            let k = hinge_kinematics(h, &p, &c, &refs[hinge]);
            let mut rows = Vec::with_capacity(group.len());
            hinge_rows(h, &group, &p, &c, &k, &mut rows);
            out.groups.push((h.parent, h.child, group.len()));
            // The constraint wrench Jᵀλ with λ held, as accelerations (ω̇ in the body's own,
            // seeded, attitude).
            let mut wrench = [(Vector3::<D>::zeros(), Vector3::<D>::zeros()); 2];
            for (r, &l) in rows.iter().zip(&lam) {
                let l = D::from_re(l);
                wrench[0].0 += r.lin_p * l;
                wrench[0].1 += r.ang_p * l;
                wrench[1].0 += r.lin_c * l;
                wrench[1].1 += r.ang_c * l;
            }
            for (b, m, (force, torque)) in [(h.parent, &p, wrench[0]), (h.child, &c, wrench[1])] {
                let bd = &model.bodies[b];
                let acc = force / real::<D>(bd.mass);
                let alpha = lift::<D>(&bd.inertia_inv_in_body) * (m.dcm_n_b.transpose() * torque);
                let [(px, pv), (cx, cv)] = split(&[acc.x, acc.y, acc.z, alpha.x, alpha.y, alpha.z]);
                add(b, h.parent, &px, &pv);
                add(b, h.child, &cx, &cv);
            }
            // Each row, and the derivatives of J a + γ with a held.
            for r in &rows {
                let mut row = ConstraintRow::default();
                let mut value = r.gamma;
                for (side, (b, m, lin, ang)) in
                    [(h.parent, &p, r.lin_p, r.ang_p), (h.child, &c, r.lin_c, r.ang_c)].into_iter().enumerate()
                {
                    let bd = &model.bodies[b];
                    let ang_b = m.dcm_n_b.transpose() * ang;
                    let coeffs = [lin.x, lin.y, lin.z, ang_b.x, ang_b.y, ang_b.z];
                    for (x, a) in coeffs.iter().zip(accel(b)) {
                        value += *x * D::from_re(a);
                    }
                    row.j[side] = coeffs.map(|x| x.re);
                    let m_ang = bd.inertia_inv_in_body * ang_b.map(re);
                    let lin = lin.map(re) / bd.mass;
                    row.m_inv_j[side] = [lin.x, lin.y, lin.z, m_ang.x, m_ang.y, m_ang.z];
                }
                let g = lanes(&value);
                for side in 0..2 {
                    for k in 0..7 {
                        row.d_pose[side][k] = g[13 * side + k];
                    }
                    for k in 0..6 {
                        row.d_twist[side][k] = g[13 * side + 7 + k];
                    }
                }
                out.rows.push(row);
            }
        }
        out
    }
}

//! The loads that locked directions carry: the constraint forces of the lock solve
//! (`Δ = M⁻¹ Jᵀ λ`, so the generalized force on the bodies is `Jᵀ λ`) written as a hinge
//! wrench in the law's convention (force `F` in A0 components at A's origin, torque `τ` in A
//! components; the child receives −F and −τ, the parent +F and +τ), so that the `_F_` and
//! `_M_` columns give what a structures engineer sizes a latched or locked hinge for.
//!
//! A lock's row is the rate of its coordinate as a linear form in the two bodies' twists; the
//! child's part of `Jᵀ λ` is a force `Σ λ lin_c` and a torque about its centre of mass
//! `Σ λ ang_c` (N components). Moved to A's origin, the torque loses `arm × force`; what is
//! left is the couple. Reactions do no work on the hinge (each acts along a direction whose
//! coordinate does not move), so adding them keeps the power check of the columns exact.

use super::Dynamics;
use crate::kinematics::hinge_kinematics;
use crate::math::Vec3;

/// One hinge's lock reaction: hinge index, force `F` (N, A0 components) and torque `τ` (N·m,
/// A components), in the law's sign convention.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reaction {
    /// Hinge index.
    pub hinge: usize,
    /// Force in A0 components, N (the child receives −F at A's origin).
    pub force_in_a0: Vec3,
    /// Torque in A components, N·m (the child receives −τ).
    pub torque_in_a: Vec3,
}

impl Dynamics<'_> {
    /// The reactions of the locks at state `y` (hinges with none are left out): every lock
    /// in force, engaged or not (a run engages a lock only once it drifts, so at the first
    /// row none is; a lock that carries no load gets a multiplier of zero to round-off), the
    /// restraint's until it lets go. It evaluates the right-hand side once with them, which
    /// the run's counts of evaluations do not include, and leaves the engaged set as it was.
    pub fn lock_reactions(&self, y: &[f64]) -> Vec<Reaction> {
        if self.locks.borrow().is_empty() {
            return Vec::new();
        }
        let engaged = self.engaged.borrow().clone();
        let released = self.released.get();
        let in_force: Vec<bool> = self.restraint.borrow().iter().map(|&r| !(r && released)).collect();
        if !in_force.iter().any(|&f| f) {
            return Vec::new();
        }
        self.set_engaged(in_force);
        let (evaluations, constrained) = (self.evaluations.get(), self.constrained_evaluations.get());
        let mut dydt = vec![0.0; self.state_len()];
        self.rhs(y, &mut dydt);
        self.evaluations.set(evaluations);
        self.constrained_evaluations.set(constrained);
        let out = self.reactions_of_last_solve();
        self.set_engaged(engaged);
        out
    }

    /// The reactions from the multipliers of the last right-hand side's lock solve.
    fn reactions_of_last_solve(&self) -> Vec<Reaction> {
        let model = self.model;
        let scratch = self.scratch.borrow();
        let refs = self.theta_refs.borrow();
        let (locks, _) = &*self.active.borrow();
        let lambda = scratch.work.multipliers();
        let mut out: Vec<Reaction> = Vec::new();
        // Rows are made per hinge, in the order of the engaged locks.
        let mut k = 0;
        for group in locks.chunk_by(|a, b| a.hinge == b.hinge) {
            let i = group[0].hinge;
            let (mut force_n, mut torque_n) = (Vec3::zeros(), Vec3::zeros());
            for row in &scratch.rows[k..k + group.len()] {
                let l = lambda.get(k).copied().unwrap_or(0.0);
                force_n += row.lin_c * l;
                torque_n += row.ang_c * l;
                k += 1;
            }
            let h = &model.hinges[i];
            let motions = &scratch.motions;
            let kin = hinge_kinematics(h, &motions[h.parent], &motions[h.child], &refs[i]);
            let couple_n = torque_n - kin.arm_child_in_n.cross(&force_n);
            out.push(Reaction {
                hinge: i,
                force_in_a0: -(kin.dcm_n_a0.transpose() * force_n),
                torque_in_a: -(kin.dcm_n_a.transpose() * couple_n),
            });
        }
        out
    }
}

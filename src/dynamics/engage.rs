//! Which locks are solved for: a run engages a lock once it carries load (drifts while
//! free), projects the state onto the engaged locks, and reads their multipliers.

use super::Dynamics;
use super::locks::{Lock, drift_mask, drifted, independent, project};
use crate::state::BodyMotion;

impl Dynamics<'_> {
    /// Sets which locks are engaged, and the list of engaged locks from it.
    pub(super) fn set_engaged(&self, engaged: Vec<bool>) {
        let locks = self.locks.borrow();
        let mut active = self.active.borrow_mut();
        let (list, ranges) = &mut *active;
        list.clear();
        ranges.iter_mut().for_each(|r| *r = 0..0);
        for group in locks.chunk_by(|a, b| a.hinge == b.hinge) {
            let first = list.len();
            let offset = self.lock_ranges.borrow()[group[0].hinge].start;
            list.extend(group.iter().enumerate().filter(|(k, _)| engaged[offset + k]).map(|(_, l)| *l));
            ranges[group[0].hinge] = first..list.len();
        }
        *self.engaged.borrow_mut() = engaged;
    }

    /// Disengages every lock: the right-hand side then leaves the locked directions free
    /// (they have no law) until [`Self::engage_drifted_locks`] engages them. A direction that
    /// carries no load keeps its value without a constraint force, so a run that starts with
    /// its locks disengaged and engages each once it drifts follows the locks at the cost of
    /// a drift check per step.
    pub fn disengage_locks(&self) {
        // The restraint's locks hold the stowed state from the start: they carry its load.
        let engaged = self.restraint.borrow().iter().map(|&r| r && !self.released.get()).collect();
        self.set_engaged(engaged);
    }

    /// Holds the state `y` (the stowed configuration) with a restraint: every tree hinge's
    /// directions that its law does not lock already are locked at their values in `y`, so
    /// the structure turns as one rigid body (loop hinges follow, unloaded) until
    /// [`Self::release_restraint`]. Call after [`Self::initialize_memory`].
    pub fn restrain_tree_hinges(&self, y: &[f64]) {
        let model = self.model;
        let old = self.locks.borrow().clone();
        let refs = self.theta_refs.borrow().clone();
        let mut locks = Vec::with_capacity(old.len() + 6 * model.tree.len());
        let mut restraint = Vec::with_capacity(locks.capacity());
        let mut ranges = vec![0..0; model.hinges.len()];
        for (i, h) in model.hinges.iter().enumerate() {
            let first = locks.len();
            let own: Vec<Lock> = old.iter().filter(|l| l.hinge == i).copied().collect();
            let restrained = model.is_tree_hinge[i];
            let k = restrained.then(|| {
                crate::kinematics::hinge_kinematics(
                    h,
                    &BodyMotion::from_state(y, h.parent),
                    &BodyMotion::from_state(y, h.child),
                    &refs[i],
                )
            });
            for d in 0..6 {
                if let Some(l) = own.iter().find(|l| l.direction == d) {
                    locks.push(*l);
                    restraint.push(false);
                } else if let Some(k) = &k {
                    let target = if d < 3 {
                        k.state.delta_in_a0[d]
                    } else {
                        k.state.theta.as_vector()[super::locks::euler_index(d)]
                    };
                    locks.push(Lock { hinge: i, direction: d, target });
                    restraint.push(true);
                }
            }
            ranges[i] = first..locks.len();
        }
        let n = locks.len();
        *self.locks.borrow_mut() = locks;
        *self.lock_ranges.borrow_mut() = ranges;
        *self.restraint.borrow_mut() = restraint;
        self.released.set(false);
        self.set_engaged(vec![true; n]);
    }

    /// Lets the restraint go: its locks disengage and never engage again; the laws' own
    /// locks stay as they are.
    pub fn release_restraint(&self) {
        self.released.set(true);
        let engaged =
            self.engaged.borrow().iter().zip(self.restraint.borrow().iter()).map(|(&e, &r)| e && !r).collect();
        self.set_engaged(engaged);
    }

    /// Per lock (as in [`Self::locks`]): whether it is the restraint's.
    pub fn restraint_locks(&self) -> std::cell::Ref<'_, Vec<bool>> {
        self.restraint.borrow()
    }

    /// Engages every disengaged lock whose coordinate or rate has drifted beyond
    /// [`crate::dynamics::locks::DRIFT_LIMIT`] at `y`. Returns those locks (indices into
    /// [`Self::locks`]).
    pub fn engage_drifted_locks(&self, y: &[f64]) -> Vec<usize> {
        let mut out = Vec::new();
        if self.active.borrow().0.len() == self.locks.borrow().len() {
            // Every lock engaged, or none locked (this runs after every step).
            return out;
        }
        {
            let locks = self.locks.borrow();
            let ranges = self.lock_ranges.borrow();
            let refs = self.theta_refs.borrow();
            let engaged = self.engaged.borrow();
            let restraint = self.restraint.borrow();
            // A released restraint's locks never engage again.
            let idle = |k: usize| !(engaged[k] || restraint[k] && self.released.get());
            for range in ranges.iter().filter(|r| (*r).clone().any(&idle)) {
                let moved = drift_mask(self.model, &locks[range.clone()], &refs, y);
                out.extend(range.clone().filter(|&k| idle(k) && moved & (1 << (k - range.start)) != 0));
            }
        }
        if !out.is_empty() {
            let mut engaged = self.engaged.borrow().clone();
            out.iter().for_each(|&k| engaged[k] = true);
            self.set_engaged(engaged);
        }
        out
    }

    /// Per lock (as in [`Self::locks`]): whether it is engaged (see
    /// [`Self::disengage_locks`]).
    pub fn engaged_locks(&self) -> std::cell::Ref<'_, Vec<bool>> {
        self.engaged.borrow()
    }

    /// Checks that the locked directions are independent at `y`. Fails with the hinge whose
    /// locks are at fault (index and message): one whose locks are degenerate on their own
    /// (a lever arm or inertia out of range), or the first, in hinge order, whose locks
    /// repeat constraints the locks before it already impose (a closed loop of locked
    /// hinges), with the other locked hinges on its bodies.
    pub fn check_locks(&self, y: &[f64]) -> Result<(), (usize, String)> {
        let locks = self.locks.borrow();
        if locks.is_empty() {
            return Ok(());
        }
        let motions: Vec<BodyMotion> = (0..self.model.bodies.len()).map(|i| BodyMotion::from_state(y, i)).collect();
        let refs = self.theta_refs.borrow();
        if independent(self.model, &locks, &motions, &refs) {
            return Ok(());
        }
        // Only on failure: find the hinge at fault, group by group (quadratic, but rare).
        let groups: Vec<&[Lock]> = locks.chunk_by(|a, b| a.hinge == b.hinge).collect();
        let name = |h: usize| self.model.hinges[h].name.as_str();
        for g in &groups {
            if !independent(self.model, g, &motions, &refs) {
                let h = &self.model.hinges[g[0].hinge];
                return Err((
                    g[0].hinge,
                    format!(
                        "hinge '{}': its locked directions are degenerate on their own (A0 {:.3e} m from the parent's centre of mass, A {:.3e} m from the child's): lever arms or inertias out of range make the constraint singular",
                        h.name,
                        h.r_a0_in_parent.norm(),
                        h.r_a_in_child.norm()
                    ),
                ));
            }
        }
        for k in 1..groups.len() {
            let upto: Vec<Lock> = groups[..=k].iter().flat_map(|g| g.iter().copied()).collect();
            if !independent(self.model, &upto, &motions, &refs) {
                let i = groups[k][0].hinge;
                let h = &self.model.hinges[i];
                let others: Vec<&str> = groups[..k]
                    .iter()
                    .map(|g| g[0].hinge)
                    .filter(|&j| {
                        let o = &self.model.hinges[j];
                        [o.parent, o.child].iter().any(|b| *b == h.parent || *b == h.child)
                    })
                    .map(name)
                    .collect();
                return Err((
                    i,
                    format!(
                        "hinge '{}': its locked directions repeat constraints that other locked hinges already impose (a closed loop of locked hinges; locked hinges on its bodies: {}): unlock one direction of the loop",
                        h.name,
                        if others.is_empty() { "none directly".to_string() } else { others.join(", ") }
                    ),
                ));
            }
        }
        Err((groups[0][0].hinge, "the locked hinge directions are redundant: unlock one direction of the loop".into()))
    }

    /// The locked directions, grouped by hinge.
    pub fn locks(&self) -> std::cell::Ref<'_, Vec<Lock>> {
        self.locks.borrow()
    }

    /// Whether any direction is locked.
    pub fn has_locks(&self) -> bool {
        !self.locks.borrow().is_empty()
    }

    /// Projects `y` onto the engaged locks' constraints (positions, then velocities) if one
    /// has drifted (see [`crate::dynamics::locks::project()`]), or onto every lock's with `force`.
    /// Disengaged locks are left alone: a drift of theirs engages them instead
    /// ([`Self::engage_drifted_locks`], after every step). Returns whether `y` changed.
    pub fn project(&self, y: &mut [f64], force: bool) -> bool {
        let refs = self.theta_refs.borrow();
        let (all, active) = (self.locks.borrow(), self.active.borrow());
        let locks = if force { &*all } else { &active.0 };
        if locks.is_empty() || !(force || drifted(self.model, locks, &refs, y)) {
            return false;
        }
        project(self.model, locks, &refs, y);
        true
    }

    /// The state derivative at `y` and the locks' multipliers there (one per lock, in the
    /// order of [`Self::locks`]; the constraint wrench is `Jᵀ λ`; zero for disengaged locks).
    pub fn rhs_and_multipliers(&self, y: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut dydt = vec![0.0; y.len()];
        self.rhs(y, &mut dydt);
        let engaged = self.engaged.borrow();
        let scratch = self.scratch.borrow();
        // The solve's multipliers are the engaged locks', in order (none when no lock is
        // engaged: then they are left from an earlier evaluation; and none after a failed
        // solve).
        let mut solved = scratch.work.multipliers().iter();
        let any = engaged.iter().any(|e| *e);
        let lambda =
            engaged.iter().map(|&e| if e && any { solved.next().copied().unwrap_or(0.0) } else { 0.0 }).collect();
        (dydt, lambda)
    }
}

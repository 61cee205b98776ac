//! Equations of motion: Newton–Euler for every body, hinges as wrench pairs (DESIGN.md §1).
//!
//! One right-hand-side evaluation walks the bodies once and the hinges once: O(bodies +
//! hinges). The hinge wrench of MODEL.md §4 (paper eq. 14) is applied exactly: with
//! `F_N = [N A0] F` and `τ_N = [N A] τ`, the child receives `−F_N` at A's origin and `−τ_N`,
//! the parent `+F_N` at the same point and `+τ_N`. This follows from the virtual work of
//! eq. 14 and conserves linear and angular momentum for any law.

use crate::constraints::{
    Lock, Row, Workspace, constrain_accelerations, drift_mask, drifted, euler_index, hinge_rows, independent, project,
};
use crate::law::{EventKind, HingeState, HingeWrench, LawMemory};
use crate::math::{Euler321, EulerTrig, Mat3, Real, Vec3, lift, quat_rate, real};
use crate::model::{Hinge, Model};
use crate::state::{BODY_STATE_LEN, BodyMotion, OMEGA, POS, QUAT, VEL};
use nalgebra::{Matrix3, Vector3};
use std::cell::{Cell, RefCell};

/// Kinematics of one hinge at one instant, with the frames the wrench needs (f64, or dual
/// numbers for the Jacobian).
#[derive(Clone, Copy, Debug)]
pub struct HingeKinematics<T: nalgebra::Scalar = f64> {
    /// The relative state handed to the law.
    pub state: HingeState<T>,
    /// `[N A0]`.
    pub dcm_n_a0: Matrix3<T>,
    /// `[N A]`.
    pub dcm_n_a: Matrix3<T>,
    /// A's origin from the parent CoM, m, N components.
    pub arm_parent_in_n: Vector3<T>,
    /// A's origin from the child CoM, m, N components.
    pub arm_child_in_n: Vector3<T>,
}

/// The translational part of a hinge's kinematics (see [`HingeKinematics`]).
#[derive(Clone, Copy, Debug)]
pub struct HingeTranslation<T: nalgebra::Scalar = f64> {
    /// `[N A0]`.
    pub dcm_n_a0: Matrix3<T>,
    /// A's origin from the parent CoM, m, N components.
    pub arm_parent_in_n: Vector3<T>,
    /// A's origin from the child CoM, m, N components.
    pub arm_child_in_n: Vector3<T>,
    /// δ: A's origin from A0's, m, A0 components.
    pub delta_in_a0: Vector3<T>,
    /// The rate of δ's A0 components, m/s.
    pub delta_rate_in_a0: Vector3<T>,
}

/// The translational part of hinge `h`'s relative state from the motions of its parent and
/// child (MODEL.md §2): what [`hinge_kinematics`] computes before the rotation.
#[inline]
pub fn hinge_translation<T: Real>(h: &Hinge, parent: &BodyMotion<T>, child: &BodyMotion<T>) -> HingeTranslation<T> {
    let dcm_n_a0 = parent.dcm_n_b * lift::<T>(&h.dcm_parent_a0);
    let arm_a0 = parent.dcm_n_b * h.r_a0_in_parent.map(real::<T>);
    let arm_child = child.dcm_n_b * h.r_a_in_child.map(real::<T>);
    let r_a = child.r_in_n + arm_child;
    let arm_parent = r_a - parent.r_in_n;
    let delta_n = arm_parent - arm_a0;
    let dcm_a0_n = dcm_n_a0.transpose();
    // δ̇ = [A0 N](Ṙ_A − Ṙ_A0) − ω_p × δ, the rate of the A0 components.
    let v_a0 = parent.v_in_n + parent.omega_in_n.cross(&arm_a0);
    let v_a = child.v_in_n + child.omega_in_n.cross(&arm_child);
    HingeTranslation {
        dcm_n_a0,
        arm_parent_in_n: arm_parent,
        arm_child_in_n: arm_child,
        delta_in_a0: dcm_a0_n * delta_n,
        delta_rate_in_a0: dcm_a0_n * (v_a - v_a0 - parent.omega_in_n.cross(&delta_n)),
    }
}

/// Relative state of hinge `h` from the motions of its parent and child (MODEL.md §2).
///
/// The Euler angles are taken from `[A A0]` and moved by whole turns in yaw and roll to lie
/// nearest `theta_ref` (MODEL.md §7), so tree and loop hinges alike are continuous.
#[inline]
pub fn hinge_kinematics<T: Real>(
    h: &Hinge,
    parent: &BodyMotion<T>,
    child: &BodyMotion<T>,
    theta_ref: &Euler321,
) -> HingeKinematics<T> {
    let HingeTranslation {
        dcm_n_a0,
        arm_parent_in_n: arm_parent,
        arm_child_in_n: arm_child,
        delta_in_a0,
        delta_rate_in_a0,
    } = hinge_translation(h, parent, child);
    let dcm_n_a = child.dcm_n_b * lift::<T>(&h.dcm_child_a);
    let dcm_a_a0 = dcm_n_a.transpose() * dcm_n_a0;
    let theta = Euler321::from_dcm(&dcm_a_a0).unwrapped_near(theta_ref);
    let omega_rel_in_a = dcm_n_a.transpose() * (child.omega_in_n - parent.omega_in_n);
    HingeKinematics {
        state: HingeState {
            delta_in_a0,
            delta_rate_in_a0,
            theta,
            dcm_a_a0,
            omega_rel_in_a,
            trig: EulerTrig::from_dcm(&dcm_a_a0),
        },
        dcm_n_a0,
        dcm_n_a,
        arm_parent_in_n: arm_parent,
        arm_child_in_n: arm_child,
    }
}

/// Per-evaluation work space, kept to avoid allocating in the right-hand side.
#[derive(Debug, Default)]
struct Scratch {
    motions: Vec<BodyMotion>,
    force_in_n: Vec<Vec3>,
    torque_in_n: Vec<Vec3>,
    /// The locks' constraint rows at this state.
    rows: Vec<Row>,
    work: Workspace,
}

/// The equations of motion of a model, with the per-run memory of its hinges: the
/// continuous-angle references and the laws' discrete memory.
///
/// The state vector holds the bodies (see [`crate::state`]) and then, per hinge, the energy
/// it has dissipated since the start, J (the integral of
/// [`crate::law::HingeLaw::dissipation_power`]).
#[derive(Debug)]
pub struct Dynamics<'m> {
    model: &'m Model,
    theta_refs: RefCell<Vec<Euler321>>,
    memories: RefCell<Vec<LawMemory>>,
    /// Locked directions, grouped by hinge in hinge order.
    locks: RefCell<Vec<Lock>>,
    /// Per hinge: its locks' index range in `locks` (empty if none).
    lock_ranges: RefCell<Vec<std::ops::Range<usize>>>,
    /// Per lock (as in `locks`): whether it is engaged, that is solved for in the
    /// right-hand side. A run starts with every lock disengaged and engages each once it
    /// drifts (see [`Self::engage_drifted_locks`]): a lock that never carries load costs a
    /// drift check per step and nothing per evaluation.
    engaged: RefCell<Vec<bool>>,
    /// The engaged locks (grouped by hinge in hinge order), and per hinge their range there.
    active: RefCell<(Vec<Lock>, Vec<std::ops::Range<usize>>)>,
    event_offsets: Vec<usize>,
    scratch: RefCell<Scratch>,
    evaluations: Cell<u64>,
    /// Of those, evaluations that solved for engaged locks (had constraint rows).
    constrained_evaluations: Cell<u64>,
}

/// A discrete change of a hinge law's memory, located in time.
#[derive(Clone, Debug, PartialEq)]
pub struct LawEvent {
    /// Time, s.
    pub t: f64,
    /// Hinge index.
    pub hinge: usize,
    /// Kind of change.
    pub kind: EventKind,
    /// What happened, from the law.
    pub description: String,
    /// Energy the hinge had dissipated up to the event, J.
    pub hinge_dissipated: f64,
}

/// How near pitch ±90° a hinge may come before the run stops, rad (MODEL.md §7).
pub const GIMBAL_LOCK_MARGIN: f64 = 1e-3;

impl<'m> Dynamics<'m> {
    /// Equations of motion of `model`; `theta_refs` are the hinges' initial continuous angles.
    pub fn new(model: &'m Model, theta_refs: Vec<Euler321>) -> Self {
        let nb = model.bodies.len();
        let mut event_offsets = Vec::with_capacity(model.hinges.len() + 1);
        let mut total = 0;
        for h in &model.hinges {
            event_offsets.push(total);
            total += h.law.event_count();
        }
        event_offsets.push(total);
        Self {
            model,
            theta_refs: RefCell::new(theta_refs),
            memories: RefCell::new(vec![LawMemory::default(); model.hinges.len()]),
            locks: RefCell::new(Vec::new()),
            lock_ranges: RefCell::new(vec![0..0; model.hinges.len()]),
            engaged: RefCell::new(Vec::new()),
            active: RefCell::new((Vec::new(), vec![0..0; model.hinges.len()])),
            event_offsets,
            scratch: RefCell::new(Scratch {
                motions: vec![BodyMotion::default(); nb],
                force_in_n: vec![Vec3::zeros(); nb],
                torque_in_n: vec![Vec3::zeros(); nb],
                rows: Vec::new(),
                work: Workspace::default(),
            }),
            evaluations: Cell::new(0),
            constrained_evaluations: Cell::new(0),
        }
    }

    /// The model.
    pub fn model(&self) -> &'m Model {
        self.model
    }

    /// Number of right-hand-side evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations.get()
    }

    /// Number of right-hand-side evaluations so far that had engaged locks to solve for.
    pub fn constrained_evaluations(&self) -> u64 {
        self.constrained_evaluations.get()
    }

    /// The hinges' current continuous-angle references.
    pub fn theta_refs(&self) -> std::cell::Ref<'_, Vec<Euler321>> {
        self.theta_refs.borrow()
    }

    /// The hinge laws' current memory.
    pub fn memories(&self) -> std::cell::Ref<'_, Vec<LawMemory>> {
        self.memories.borrow()
    }

    /// Length of the state vector: bodies, then one dissipated-energy integral per hinge.
    pub fn state_len(&self) -> usize {
        BODY_STATE_LEN * self.model.bodies.len() + self.model.hinges.len()
    }

    /// Index of hinge `h`'s dissipated energy in the state vector.
    pub fn dissipation_index(&self, h: usize) -> usize {
        BODY_STATE_LEN * self.model.bodies.len() + h
    }

    /// Kinematics of hinge `i` at state `y`, with angle references `refs`.
    fn kinematics_at(&self, i: usize, y: &[f64], refs: &[Euler321]) -> HingeKinematics {
        let h = &self.model.hinges[i];
        hinge_kinematics(h, &BodyMotion::from_state(y, h.parent), &BodyMotion::from_state(y, h.child), &refs[i])
    }

    /// The hinge whose law owns event function `index`, and the index among its own.
    fn event_owner(&self, index: usize) -> (usize, usize) {
        let i = self.event_offsets.partition_point(|&o| o <= index) - 1;
        (i, index - self.event_offsets[i])
    }

    /// Kinematics of every hinge at state `y`, with the current references.
    fn each_hinge<F: FnMut(usize, &HingeKinematics)>(&self, y: &[f64], mut f: F) {
        let refs = self.theta_refs.borrow();
        for i in 0..self.model.hinges.len() {
            f(i, &self.kinematics_at(i, y, &refs));
        }
    }

    /// Sets every law's memory from the initial state, and holds every locked direction at
    /// its value there (every lock engaged).
    pub fn initialize_memory(&self, y: &[f64]) {
        let mut mem = vec![LawMemory::default(); self.model.hinges.len()];
        let mut locks = Vec::new();
        let mut ranges = vec![0..0; self.model.hinges.len()];
        self.each_hinge(y, |i, k| {
            let law = &self.model.hinges[i].law;
            mem[i] = law.initial_memory(&k.state);
            let first = locks.len();
            for (d, _) in law.locked_directions().iter().enumerate().filter(|(_, l)| **l) {
                let target = if d < 3 { k.state.delta_in_a0[d] } else { k.state.theta.as_vector()[euler_index(d)] };
                locks.push(Lock { hinge: i, direction: d, target });
            }
            ranges[i] = first..locks.len();
        });
        *self.memories.borrow_mut() = mem;
        let n = locks.len();
        *self.locks.borrow_mut() = locks;
        *self.lock_ranges.borrow_mut() = ranges;
        self.set_engaged(vec![true; n]);
    }

    /// Sets which locks are engaged, and the list of engaged locks from it.
    fn set_engaged(&self, engaged: Vec<bool>) {
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
        let n = self.locks.borrow().len();
        self.set_engaged(vec![false; n]);
    }

    /// Engages every disengaged lock whose coordinate or rate has drifted beyond
    /// [`crate::constraints::DRIFT_LIMIT`] at `y`. Returns those locks (indices into
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
            for range in ranges.iter().filter(|r| engaged[(*r).clone()].contains(&false)) {
                let moved = drift_mask(self.model, &locks[range.clone()], &refs, y);
                out.extend(range.clone().filter(|&k| !engaged[k] && moved & (1 << (k - range.start)) != 0));
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

    /// Total linear momentum (kg·m/s) and angular momentum about N's origin (kg·m²/s), N
    /// components, of state `y`.
    pub fn momenta(&self, y: &[f64]) -> (Vec3, Vec3) {
        let (mut p, mut h) = (Vec3::zeros(), Vec3::zeros());
        for (i, b) in self.model.bodies.iter().enumerate() {
            let m = BodyMotion::from_state(y, i);
            let mv = m.v_in_n * b.mass;
            p += mv;
            h += m.r_in_n.cross(&mv) + m.dcm_n_b * (b.inertia_in_body * m.omega_in_body());
        }
        (p, h)
    }

    /// Restores total linear and angular momentum to `(p0, h0)` by adding one rigid-body
    /// velocity field to every body (a uniform velocity and a rotation about the
    /// barycenter): the smallest mass-weighted correction, and one that leaves every hinge's
    /// relative velocities unchanged, so the internal motion is untouched. For integrators
    /// that conserve momentum only to their tolerance (the implicit path). Returns the size
    /// of the correction relative to the momenta's scale.
    pub fn restore_momentum(&self, y: &mut [f64], p0: &Vec3, h0: &Vec3) -> f64 {
        let model = self.model;
        let total: f64 = model.total_mass();
        let (p, _) = self.momenta(y);
        let dv = -(p - p0) / total;
        let mut c = Vec3::zeros();
        for (i, b) in model.bodies.iter().enumerate() {
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for k in 0..3 {
                s[VEL + k] += dv[k];
            }
            c += Vec3::new(s[POS], s[POS + 1], s[POS + 2]) * b.mass;
        }
        c /= total;
        let (_, h) = self.momenta(y);
        // Inertia of the whole structure about its barycenter, N components.
        let mut inertia = Mat3::zeros();
        for (i, b) in model.bodies.iter().enumerate() {
            let m = BodyMotion::from_state(y, i);
            let r = m.r_in_n - c;
            inertia += m.dcm_n_b * b.inertia_in_body * m.dcm_n_b.transpose()
                + (Mat3::identity() * r.norm_squared() - r * r.transpose()) * b.mass;
        }
        let Some(inv) = inertia.try_inverse() else { return 0.0 };
        let dw = -(inv * (h - h0));
        for i in 0..model.bodies.len() {
            let m = BodyMotion::from_state(y, i);
            let r = m.r_in_n - c;
            let dv_i = dw.cross(&r);
            let dw_b = m.dcm_n_b.transpose() * dw;
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for k in 0..3 {
                s[VEL + k] += dv_i[k];
                s[OMEGA + k] += dw_b[k];
            }
        }
        let scale = (p0.norm() + h0.norm()).max(1e-300);
        (dv.norm() * total + (inertia * dw).norm()) / scale
    }

    /// Checks that the locked directions are independent at `y`.
    pub fn check_locks(&self, y: &[f64]) -> Result<(), String> {
        let locks = self.locks.borrow();
        if locks.is_empty() {
            return Ok(());
        }
        let motions: Vec<BodyMotion> = (0..self.model.bodies.len()).map(|i| BodyMotion::from_state(y, i)).collect();
        if independent(self.model, &locks, &motions, &self.theta_refs.borrow()) {
            Ok(())
        } else {
            Err("the locked hinge directions are redundant (for example a closed loop of locked hinges): unlock one direction of the loop".into())
        }
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
    /// has drifted (see [`crate::constraints::project`]), or onto every lock's with `force`.
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

    /// Total number of event functions over all hinges.
    pub fn event_count(&self) -> usize {
        *self.event_offsets.last().unwrap_or(&0)
    }

    /// Every hinge's event function values at `y` (see
    /// [`crate::law::HingeLaw::event_values`]), concatenated.
    pub fn event_values(&self, y: &[f64], out: &mut [f64]) {
        if self.event_count() == 0 {
            return;
        }
        let (mem, refs) = (self.memories.borrow(), self.theta_refs.borrow());
        for (i, h) in self.model.hinges.iter().enumerate() {
            let (a, b) = (self.event_offsets[i], self.event_offsets[i + 1]);
            // Only hinges whose laws have events: the others' kinematics are not needed.
            if b > a {
                h.law.event_values(&self.kinematics_at(i, y, &refs).state, &mem[i], &mut out[a..b]);
            }
        }
    }

    /// The parent and child bodies of the hinge whose law owns event function `index`: the
    /// only bodies [`Self::event_value`] reads.
    pub fn event_bodies(&self, index: usize) -> (usize, usize) {
        let h = &self.model.hinges[self.event_owner(index).0];
        (h.parent, h.child)
    }

    /// Event function `index` alone at `y`.
    pub fn event_value(&self, index: usize, y: &[f64]) -> f64 {
        let (i, own) = self.event_owner(index);
        let h = &self.model.hinges[i];
        let k = self.kinematics_at(i, y, &self.theta_refs.borrow());
        // On the stack for the laws' usual counts (a directional law has 30): this runs at
        // every iteration of an event's root search.
        let count = h.law.event_count();
        let mut small = [0.0; 32];
        let mut large = Vec::new();
        let out = if count <= small.len() {
            &mut small[..count]
        } else {
            large.resize(count, 0.0);
            &mut large[..]
        };
        h.law.event_values(&k.state, &self.memories.borrow()[i], out);
        out[own]
    }

    /// Applies event function `index`'s change at state `y`, time `t`.
    pub fn apply_event(&self, index: usize, t: f64, y: &[f64]) -> LawEvent {
        let (i, own) = self.event_owner(index);
        let k = self.kinematics_at(i, y, &self.theta_refs.borrow());
        let (kind, description) =
            self.model.hinges[i].law.apply_event(own, &k.state, &mut self.memories.borrow_mut()[i]);
        LawEvent { t, hinge: i, kind, description, hinge_dissipated: y[self.dissipation_index(i)] }
    }

    /// Records an accepted state: moves every hinge's angle reference to its continuous
    /// angles there and checks the laws' domains. Fails, naming the hinge, if an Euler-angle
    /// law comes within [`GIMBAL_LOCK_MARGIN`] of pitch ±90°, where 3-2-1 laws are singular
    /// (MODEL.md §7), or if a law's own check fails (a table's range, say).
    pub fn accept(&self, t: f64, y: &[f64]) -> Result<(), String> {
        let mut refs = self.theta_refs.borrow_mut();
        let mut memories = self.memories.borrow_mut();
        for (i, h) in self.model.hinges.iter().enumerate() {
            let k = self.kinematics_at(i, y, &refs);
            if h.law.uses_euler_angles() {
                if k.state.theta.near_gimbal_lock(GIMBAL_LOCK_MARGIN) {
                    return Err(format!(
                        "hinge '{}' reached pitch {:.4}° at t = {t:.6} s: 3-2-1 Euler angles are singular at ±90° (MODEL.md §7), so the hinge law is not defined there",
                        h.name,
                        k.state.theta.pitch.to_degrees()
                    ));
                }
                // Between accepted steps yaw and roll move continuously; a jump of more than
                // a quarter turn means the step passed the singular pitch and the branch is lost.
                let jump = (k.state.theta.yaw - refs[i].yaw).abs().max((k.state.theta.roll - refs[i].roll).abs());
                if jump > std::f64::consts::FRAC_PI_2 {
                    return Err(format!(
                        "hinge '{}' passed near pitch ±90° before t = {t:.6} s (yaw or roll jumped by {:.1}° in one step): 3-2-1 Euler angles are singular there (MODEL.md §7)",
                        h.name,
                        jump.to_degrees()
                    ));
                }
            }
            h.law.check(&k.state, &memories[i]).map_err(|m| format!("hinge '{}' at t = {t:.6} s: {m}", h.name))?;
            h.law.sync_memory(&k.state, &mut memories[i]);
            refs[i] = k.state.theta;
        }
        Ok(())
    }

    /// Right-hand side `ẏ = f(y)` (time does not appear).
    pub fn rhs(&self, y: &[f64], dydt: &mut [f64]) {
        self.evaluations.set(self.evaluations.get() + 1);
        let model = self.model;
        let refs = self.theta_refs.borrow();
        let memories = self.memories.borrow();
        let mut scratch = self.scratch.borrow_mut();
        let Scratch { motions, force_in_n, torque_in_n, rows, work } = &mut *scratch;
        let active = self.active.borrow();
        let (locks, lock_ranges) = &*active;
        for (i, m) in motions.iter_mut().enumerate() {
            *m = BodyMotion::from_state(y, i);
        }
        force_in_n.iter_mut().for_each(|f| *f = Vec3::zeros());
        torque_in_n.iter_mut().for_each(|t| *t = Vec3::zeros());
        rows.clear();

        let diss0 = BODY_STATE_LEN * model.bodies.len();
        for (i, (h, theta_ref)) in model.hinges.iter().zip(refs.iter()).enumerate() {
            let (p, c) = (&motions[h.parent], &motions[h.child]);
            let k = hinge_kinematics(h, p, c, theta_ref);
            let memory = &memories[i];
            let (HingeWrench { force_in_a0, torque_in_a }, power) = h.law.wrench_and_dissipation(&k.state, memory);
            dydt[diss0 + i] = power;
            let f_n = k.dcm_n_a0 * force_in_a0;
            let tau_n = k.dcm_n_a * torque_in_a;
            force_in_n[h.parent] += f_n;
            torque_in_n[h.parent] += k.arm_parent_in_n.cross(&f_n) + tau_n;
            force_in_n[h.child] -= f_n;
            torque_in_n[h.child] -= k.arm_child_in_n.cross(&f_n) + tau_n;
            let range = lock_ranges[i].clone();
            if !range.is_empty() {
                hinge_rows(h, &locks[range], p, c, &k, rows);
            }
        }

        for (i, body) in model.bodies.iter().enumerate() {
            let s = &y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            let d = &mut dydt[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            let m = &motions[i];
            let omega_b = Vec3::new(s[OMEGA], s[OMEGA + 1], s[OMEGA + 2]);
            d[POS..POS + 3].copy_from_slice(&s[VEL..VEL + 3]);
            d[QUAT..QUAT + 4].copy_from_slice(&quat_rate(&s[QUAT..QUAT + 4], &omega_b));
            let a = force_in_n[i] / body.mass;
            d[VEL..VEL + 3].copy_from_slice(a.as_slice());
            // Euler's equation in body components: I ω̇ = τ − ω × I ω.
            let tau_b = m.dcm_n_b.tr_mul(&torque_in_n[i]);
            let i_omega = body.inertia_in_body * omega_b;
            let omega_dot = body.inertia_inv_in_body * (tau_b - omega_b.cross(&i_omega));
            d[OMEGA..OMEGA + 3].copy_from_slice(omega_dot.as_slice());
        }
        if !rows.is_empty() {
            self.constrained_evaluations.set(self.constrained_evaluations.get() + 1);
            // Locked directions: the constraint correction (crate::constraints). A singular
            // system (redundant locks) is refused when the run starts.
            let _ = constrain_accelerations(model, rows, motions, dydt, work);
        }
    }
}

impl Dynamics<'_> {
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

impl crate::ode::OdeSystem for Dynamics<'_> {
    fn rhs(&self, _t: f64, y: &[f64], dydt: &mut [f64]) {
        Dynamics::rhs(self, y, dydt);
    }
}

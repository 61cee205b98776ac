//! Equations of motion: Newton–Euler for every body, hinges as wrench pairs (docs/architecture.md).
//!
//! One right-hand-side evaluation walks the bodies once and the hinges once: O(bodies +
//! hinges). The hinge wrench of docs/model.md §4 (paper eq. 14) is applied exactly: with
//! `F_N = [N A0] F` and `τ_N = [N A] τ`, the child receives `−F_N` at A's origin and `−τ_N`,
//! the parent `+F_N` at the same point and `+τ_N`. This follows from the virtual work of
//! eq. 14 and conserves linear and angular momentum for any law.

pub mod actuators;
mod contact_pair;
pub mod diagnose;
pub mod engage;
pub mod events;
pub mod jacobian;
mod lanes;
pub mod locks;
pub mod momentum;
pub mod newton;
pub mod reactions;

use crate::contact::proximity::Proximity;
use crate::contact::{ContactMemory, ContactPoint, ContactRecord, ContactSummary, Frame};
use crate::kinematics::{HingeKinematics, hinge_kinematics};
use crate::law::{EventKind, HingeWrench, LawMemory};
use crate::math::{Euler321, Vec3, quat_rate};
use crate::model::Model;
use crate::state::{BODY_STATE_LEN, BodyMotion, OMEGA, POS, QUAT, VEL};
use locks::{Lock, Row, Workspace, constrain_accelerations, euler_index, hinge_rows};
use std::cell::{Cell, RefCell};
use std::collections::HashMap;

/// Per-evaluation work space, kept to avoid allocating in the right-hand side.
#[derive(Debug, Default)]
struct Scratch {
    motions: Vec<BodyMotion>,
    force_in_n: Vec<Vec3>,
    torque_in_n: Vec<Vec3>,
    /// The locks' constraint rows at this state.
    rows: Vec<Row>,
    work: Workspace,
    /// Contact: the bodies' frames, the points found, the search's work space.
    frames: Vec<crate::contact::Frame>,
    contacts: Vec<ContactPoint>,
    /// The bodies' part of the state `contacts` were found at (by
    /// [`Dynamics::contact_points`], or a right-hand side the proximity list did not cover;
    /// empty: none, or the contact memory changed since): the crossing check, the acceptance
    /// and the Jacobian at one state take its points rather than probing again.
    contacts_at: Vec<f64>,
    contact_work: crate::contact::Workspace,
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
    /// Per lock (as in `locks`): whether it is the restraint's (see
    /// [`Self::restrain_tree_hinges`]) rather than a law's.
    restraint: RefCell<Vec<bool>>,
    /// Whether the restraint has let go.
    released: Cell<bool>,
    /// The engaged locks (grouped by hinge in hinge order), and per hinge their range there.
    active: RefCell<(Vec<Lock>, Vec<std::ops::Range<usize>>)>,
    event_offsets: Vec<usize>,
    /// Contact points in contact at the last accepted state, with their impact speeds.
    contact_memory: RefCell<ContactMemory>,
    /// Contact over the run so far, at accepted steps.
    contact_record: RefCell<ContactRecord>,
    contact_log: RefCell<crate::contact::episodes::ContactLog>,
    /// The approach speeds (m/s) at which points entering contact in the step about to be
    /// accepted crossed into it, located on the step's dense output
    /// ([`Self::set_entry_speeds`]); taken by the next `accept_contacts`.
    entry_speeds: RefCell<Vec<(crate::contact::PointKey, f64)>>,
    /// Per body: whether it touched another at an accepted step since the last
    /// [`Self::take_touched`].
    touched: RefCell<Vec<bool>>,
    /// The pairs that may touch soon (crate::contact::proximity), kept across steps.
    proximity: RefCell<Option<Proximity>>,
    scratch: RefCell<Scratch>,
    evaluations: Cell<u64>,
    /// Of those, evaluations that solved for engaged locks (had constraint rows).
    constrained_evaluations: Cell<u64>,
    /// The time the right-hand side is evaluated at, s: the external loads depend on it
    /// (set by the integrator's call, and by [`Dynamics::accept`] for evaluations at an
    /// accepted state).
    time: Cell<f64>,
    /// The contact points the Newton matrix's structure was last made for, with the state
    /// they are at: the exact Jacobian that follows at that state takes them rather than
    /// probing again (crate::dynamics::jacobian).
    jacobian_points: RefCell<Option<(Vec<f64>, Vec<ContactPoint>)>>,
    /// Per hinge: the motors that drive it (indices into the model's motors).
    motors_of_hinge: Vec<Vec<usize>>,
    /// The motors' and the control's per-run memory (crate::dynamics::actuators).
    actuators: RefCell<actuators::ActuatorMemory>,
    /// Times at which the right-hand side jumps (loads and motors switching, their tables'
    /// corners, the control's samples), s, ascending: no step passes one.
    breaks: RefCell<crate::loads::breaks::Breaks>,
    /// The time of the last accepted state, s.
    accepted: Cell<f64>,
    /// Loads set from outside the run (a stepped run: crate::simulate::stepper), one per
    /// body at most, constant until changed; they act like the model's loads.
    commanded: RefCell<Vec<crate::loads::Load>>,
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

/// How near pitch ±90° a hinge may come before the run stops, rad (docs/model.md §7).
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
            restraint: RefCell::new(Vec::new()),
            released: Cell::new(false),
            active: RefCell::new((Vec::new(), vec![0..0; model.hinges.len()])),
            event_offsets,
            scratch: RefCell::new(Scratch {
                motions: vec![BodyMotion::default(); nb],
                force_in_n: vec![Vec3::zeros(); nb],
                torque_in_n: vec![Vec3::zeros(); nb],
                rows: Vec::new(),
                work: Workspace::default(),
                frames: vec![Frame::default(); nb],
                contacts: Vec::new(),
                contacts_at: Vec::new(),
                contact_work: Default::default(),
            }),
            contact_memory: RefCell::new(ContactMemory::default()),
            contact_record: RefCell::new(ContactRecord::default()),
            contact_log: RefCell::new(Default::default()),
            entry_speeds: RefCell::new(Vec::new()),
            touched: RefCell::new(vec![false; nb]),
            proximity: RefCell::new(None),
            evaluations: Cell::new(0),
            constrained_evaluations: Cell::new(0),
            time: Cell::new(0.0),
            jacobian_points: RefCell::new(None),
            motors_of_hinge: {
                let mut m = vec![Vec::new(); model.hinges.len()];
                for (k, motor) in model.motors.iter().enumerate() {
                    m[motor.hinge].push(k);
                }
                m
            },
            actuators: RefCell::new(Default::default()),
            breaks: RefCell::new(Default::default()),
            accepted: Cell::new(f64::NEG_INFINITY),
            commanded: RefCell::new(Vec::new()),
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

    /// Puts back the angle references and law memories read before with [`Self::theta_refs`]
    /// and [`Self::memories`]: a search that accepted trial states (the equilibrium's
    /// Newton) leaves the dynamics as it found them.
    pub fn restore_history(&self, refs: Vec<Euler321>, memories: Vec<LawMemory>) {
        *self.theta_refs.borrow_mut() = refs;
        *self.memories.borrow_mut() = memories;
    }

    /// The hinge laws' current memory.
    pub fn memories(&self) -> std::cell::Ref<'_, Vec<LawMemory>> {
        self.memories.borrow()
    }

    /// Length of the state vector: bodies, then one dissipated-energy integral per hinge,
    /// then contact's (when on).
    pub fn state_len(&self) -> usize {
        BODY_STATE_LEN * self.model.bodies.len() + self.model.energy_states()
    }

    /// Index of the external work's integrals in the state vector (the work first; see
    /// [`crate::model::LOAD_STATES`]), if anything does work from outside.
    pub fn load_work_index(&self) -> Option<usize> {
        crate::state::work_index(self.model)
    }

    /// Index of the energy contact has dissipated in the state vector, if contact is on.
    pub fn contact_dissipation_index(&self) -> Option<usize> {
        self.model.contact.as_ref().map(|_| BODY_STATE_LEN * self.model.bodies.len() + self.model.hinges.len())
    }

    /// The contact memory: points in contact at the last accepted state.
    pub fn contact_memory(&self) -> std::cell::Ref<'_, ContactMemory> {
        self.contact_memory.borrow()
    }

    /// The contact points at state `y` (empty without contact), with the memory of the last
    /// accepted state.
    pub fn contact_points(&self, y: &[f64]) -> Vec<ContactPoint> {
        let Some(set) = &self.model.contact else { return Vec::new() };
        let mut scratch = self.scratch.borrow_mut();
        let bodies = BODY_STATE_LEN * self.model.bodies.len();
        if !scratch.contacts_at.is_empty() && scratch.contacts_at[..] == y[..bodies] {
            return scratch.contacts.clone();
        }
        let Scratch { frames, contacts, contacts_at, contact_work, .. } = &mut *scratch;
        fill_frames((0..self.model.bodies.len()).map(|i| BodyMotion::from_state(y, i)), frames);
        self.find_contacts(set, frames, contact_work, (contacts, contacts_at), &y[..bodies]);
        contacts.clone()
    }

    /// The contact points at the bodies' `frames` (through the proximity list if there is
    /// one) into `contacts`, and the bodies' part of the state they are for, `at`, into
    /// `contacts_at` (the cache [`Self::contact_points`] reads).
    fn find_contacts(
        &self,
        set: &crate::contact::ContactSet,
        frames: &[crate::contact::Frame],
        work: &mut crate::contact::Workspace,
        (contacts, contacts_at): (&mut Vec<ContactPoint>, &mut Vec<f64>),
        at: &[f64],
    ) {
        contacts.clear();
        match &*self.proximity.borrow() {
            Some(near) => set.evaluate_near(frames, &self.contact_memory.borrow(), near, work, contacts),
            None => set.evaluate(frames, &self.contact_memory.borrow(), work, contacts),
        }
        contacts_at.clear();
        contacts_at.extend_from_slice(at);
    }

    /// Rebuilds the proximity list at the accepted state `y` if the bodies have moved beyond
    /// the reach of the one kept (or there is none).
    fn refresh_proximity(&self, y: &[f64]) {
        let Some(set) = &self.model.contact else { return };
        let mut scratch = self.scratch.borrow_mut();
        let Scratch { frames, .. } = &mut *scratch;
        fill_frames((0..self.model.bodies.len()).map(|i| BodyMotion::from_state(y, i)), frames);
        let mut proximity = self.proximity.borrow_mut();
        let mut motion = Vec::new();
        if proximity.as_mut().is_none_or(|p| !p.rereference(set, frames, &mut motion)) {
            let mut list = Proximity::rebuild(proximity.take(), set, frames, set.skin());
            list.remember(&self.contact_memory.borrow());
            *proximity = Some(list);
        }
    }

    /// Contact at an output row `y` (one evaluation), `None` without contact: what its points
    /// add up to, and per body whether it touched another at an accepted step since the last
    /// row or touches at `y` (the record then starts again).
    pub fn row_contact(&self, y: &[f64]) -> Option<(ContactSummary, Vec<bool>)> {
        let row = self.contact_at(y)?;
        *self.touched.borrow_mut() = vec![false; self.model.bodies.len()];
        Some(row)
    }

    /// [`Self::row_contact`] without starting the record again: what a diagnosis reads
    /// between rows, leaving the next row's record whole.
    pub fn contact_at(&self, y: &[f64]) -> Option<(ContactSummary, Vec<bool>)> {
        self.model.contact.as_ref()?;
        let points = self.contact_points(y);
        let mut touched = self.touched.borrow().clone();
        let log = self.contact_log.borrow();
        mark_touched(points.iter().filter(|p| !log.is_resting(p)), &mut touched);
        Some((ContactSummary::of(&points), touched))
    }

    /// How many pairs of bodies that no hinge joins touch at `y` (0 without contact): a
    /// stowed package's layers pressing on each other, where an opened sheet's touching
    /// pairs are mostly hinged neighbours meeting at their creases.
    pub fn unhinged_pairs_touching(&self, y: &[f64]) -> usize {
        if self.model.contact.is_none() {
            return 0;
        }
        let hinged = self.model.hinged_pairs();
        let pairs: std::collections::HashSet<(usize, usize)> = self
            .contact_points(y)
            .iter()
            .map(|p| {
                let (a, b) = (p.key.body as usize, p.key.other as usize);
                (a.min(b), a.max(b))
            })
            .filter(|pair| !hinged.contains(pair))
            .collect();
        pairs.len()
    }

    /// The points whose contact changes between the last accepted state and `y`: those in
    /// contact at one and not at the other (the keys; empty without contact).
    pub fn contact_changes(&self, y: &[f64]) -> Vec<crate::contact::PointKey> {
        if self.model.contact.is_none() {
            return Vec::new();
        }
        let now = self.contact_points(y);
        let memory = self.contact_memory.borrow();
        let mut changed: Vec<_> = now.iter().map(|p| p.key).filter(|k| !memory.contains_key(k)).collect();
        let in_now: std::collections::HashSet<_> = now.iter().map(|p| p.key).collect();
        changed.extend(memory.keys().filter(|k| !in_now.contains(k)).copied());
        changed
    }

    /// The penetration of contact point `key` at state `y` (m; negative apart), from its two
    /// bodies' numbers alone: see [`crate::contact::ContactSet::depth`].
    pub fn contact_depth(&self, key: &crate::contact::PointKey, y: &[f64]) -> f64 {
        let Some(set) = &self.model.contact else { return f64::NAN };
        let frame = |b: u32| BodyMotion::from_state(y, b as usize).contact_frame();
        set.depth(key, &frame(key.body), &frame(key.other))
    }

    /// The approach rate of contact point `key` at state `y` (m/s, > 0 approaching): see
    /// [`crate::contact::ContactSet::approach_rate`].
    pub fn contact_rate(&self, key: &crate::contact::PointKey, y: &[f64]) -> f64 {
        let Some(set) = &self.model.contact else { return f64::NAN };
        let frame = |b: u32| BodyMotion::from_state(y, b as usize).contact_frame();
        set.approach_rate(key, &frame(key.body), &frame(key.other))
    }

    /// The speeds (m/s) at which points came into contact within the step about to be
    /// accepted, at the instants they crossed (located by the caller on the step's dense
    /// output): the next [`Self::accept`] holds these as their impact speeds rather than
    /// their rates at the step's end, which depend on where the step happened to end.
    pub fn set_entry_speeds(&self, speeds: Vec<(crate::contact::PointKey, f64)>) {
        *self.entry_speeds.borrow_mut() = speeds;
    }

    /// Contact over the run so far (at accepted steps).
    pub fn contact_record(&self) -> ContactRecord {
        *self.contact_record.borrow()
    }

    /// Every contact episode so far (crate::contact::episodes), in the order they started,
    /// each marked `joined` where a hinge joins its two bodies.
    pub fn contact_episodes(&self) -> Vec<crate::contact::episodes::Episode> {
        let joined = self.model.hinged_pairs();
        let mut episodes = self.contact_log.borrow().episodes();
        for e in &mut episodes {
            e.joined = joined.contains(&e.bodies);
        }
        episodes
    }

    /// Up to time `t` (s) an episode that starts is the stowed package's resting contact (the
    /// launch restraint's release, or 0).
    pub fn set_resting_until(&self, t: f64) {
        self.contact_log.borrow_mut().resting_until = t;
    }

    /// Brings the contact memory up to the accepted state `y`: a point newly in contact
    /// keeps its approach speed now as its impact speed; a point out of contact is forgotten.
    fn accept_contacts(&self, t: f64, y: &[f64]) {
        if self.model.contact.is_none() {
            return;
        }
        self.refresh_proximity(y);
        // The step end's points: its last stage's, or the crossing check's, at this very state.
        let points = self.contact_points(y);
        self.contact_record.borrow_mut().record(t, &points);
        // A point new in contact holds the speed at which it crossed into it, where the
        // step's dense output located that (crate::simulate), else its rate now.
        let entry: HashMap<_, _> = std::mem::take(&mut *self.entry_speeds.borrow_mut()).into_iter().collect();
        let new_speed = |p: &ContactPoint, memory: &ContactMemory| {
            (!memory.contains_key(&p.key)).then(|| entry.get(&p.key).copied().unwrap_or(p.rate))
        };
        {
            let memory = self.contact_memory.borrow();
            self.contact_log.borrow_mut().record(t, &points, |p| new_speed(p, &memory));
        }
        // The bodies in an impact are marked for the animation, not the stowed package
        // resting on itself (which would mark the whole wrap from t = 0).
        let log = self.contact_log.borrow();
        mark_touched(points.iter().filter(|p| !log.is_resting(p)), &mut self.touched.borrow_mut());
        drop(log);
        self.scratch.borrow_mut().contacts_at.clear();
        let mut memory = self.contact_memory.borrow_mut();
        let old = std::mem::take(&mut *memory);
        for p in points {
            let speed = old.get(&p.key).copied().or_else(|| new_speed(&p, &old)).unwrap_or(p.rate);
            memory.insert(p.key, speed);
        }
        if let Some(list) = self.proximity.borrow_mut().as_mut() {
            list.remember(&memory);
        }
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
        *self.proximity.borrow_mut() = None;
        self.refresh_proximity(y);
        let n = locks.len();
        *self.restraint.borrow_mut() = vec![false; n];
        *self.locks.borrow_mut() = locks;
        *self.lock_ranges.borrow_mut() = ranges;
        self.set_engaged(vec![true; n]);
        self.start_actuators(y);
    }

    /// Records an accepted state: moves every hinge's angle reference to its continuous
    /// angles there and checks the laws' domains. Fails, naming the hinge, if an Euler-angle
    /// law comes within [`GIMBAL_LOCK_MARGIN`] of pitch ±90°, where 3-2-1 laws are singular
    /// (docs/model.md §7), or if a law's own check fails (a table's range, say).
    pub fn accept(&self, t: f64, y: &[f64]) -> Result<(), String> {
        self.time.set(t);
        self.accepted.set(t);
        let mut refs = self.theta_refs.borrow_mut();
        let mut memories = self.memories.borrow_mut();
        for (i, h) in self.model.hinges.iter().enumerate() {
            let k = self.kinematics_at(i, y, &refs);
            // A motor on an angle drives a 3-2-1 coordinate (crate::loads::motor).
            let euler =
                h.law.uses_euler_angles() || self.motors_of_hinge[i].iter().any(|&m| self.model.motors[m].is_angular());
            if euler {
                if k.state.theta.near_gimbal_lock(GIMBAL_LOCK_MARGIN) {
                    return Err(format!(
                        "hinge '{}' reached pitch {:.4}° at t = {t:.6} s: 3-2-1 Euler angles are singular at ±90° (docs/model.md §7), so the hinge law is not defined there",
                        h.name,
                        k.state.theta.pitch.to_degrees()
                    ));
                }
                // Between accepted steps yaw and roll move continuously; a jump of more than
                // a quarter turn means the step passed the singular pitch and the branch is lost.
                let jump = (k.state.theta.yaw - refs[i].yaw).abs().max((k.state.theta.roll - refs[i].roll).abs());
                if jump > std::f64::consts::FRAC_PI_2 {
                    return Err(format!(
                        "hinge '{}' passed near pitch ±90° before t = {t:.6} s (yaw or roll jumped by {:.1}° in one step): 3-2-1 Euler angles are singular there (docs/model.md §7)",
                        h.name,
                        jump.to_degrees()
                    ));
                }
            }
            h.law.check(&k.state, &memories[i]).map_err(|m| format!("hinge '{}' at t = {t:.6} s: {m}", h.name))?;
            h.law.sync_memory(&k.state, &mut memories[i]);
            refs[i] = k.state.theta;
        }
        self.accept_contacts(t, y);
        self.accept_actuators(t, y);
        Ok(())
    }

    /// Right-hand side `ẏ = f(y)` at the time last set (only the external loads depend on
    /// it).
    pub fn rhs(&self, y: &[f64], dydt: &mut [f64]) {
        self.evaluations.set(self.evaluations.get() + 1);
        let model = self.model;
        let refs = self.theta_refs.borrow();
        let memories = self.memories.borrow();
        let mut scratch = self.scratch.borrow_mut();
        let Scratch { motions, force_in_n, torque_in_n, rows, work, frames, contacts, contacts_at, contact_work } =
            &mut *scratch;
        let active = self.active.borrow();
        let (locks, lock_ranges) = &*active;
        for (i, m) in motions.iter_mut().enumerate() {
            *m = BodyMotion::from_state(y, i);
        }
        force_in_n.iter_mut().for_each(|f| *f = Vec3::zeros());
        torque_in_n.iter_mut().for_each(|t| *t = Vec3::zeros());
        rows.clear();
        let t = self.time.get();
        // What does work from outside the hinges and contacts: loads, motors, control.
        let (mut work_power, mut impulse, mut angular) = (0.0, Vec3::zeros(), Vec3::zeros());

        let diss0 = BODY_STATE_LEN * model.bodies.len();
        for (i, (h, theta_ref)) in model.hinges.iter().zip(refs.iter()).enumerate() {
            let (p, c) = (&motions[h.parent], &motions[h.child]);
            let k = hinge_kinematics(h, p, c, theta_ref);
            let memory = &memories[i];
            let (HingeWrench { mut force_in_a0, mut torque_in_a }, power) =
                h.law.wrench_and_dissipation(&k.state, memory);
            dydt[diss0 + i] = power;
            if let Some((motor, power)) = self.motor_wrench(i, &k.state, t) {
                // Hinge motors (crate::loads::motor): an equal and opposite pair, like the law.
                force_in_a0 += motor.force_in_a0;
                torque_in_a += motor.torque_in_a;
                work_power += power;
            }
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

        if let Some(set) = &model.contact {
            // Contact forces act at the sample point on both bodies, equal and opposite
            // (crate::contact): P and H hold exactly.
            fill_frames(motions.iter().copied(), frames);
            // Summed as found where the proximity list covers the state (an accepted step or
            // a Jacobian lists the points it needs), else listed (and kept for those).
            let summed = match &*self.proximity.borrow() {
                Some(near) => set.wrench_near(frames, near, contact_work, (force_in_n, torque_in_n)),
                None => None,
            };
            let dissipation = summed.unwrap_or_else(|| {
                let at = &y[..BODY_STATE_LEN * model.bodies.len()];
                self.find_contacts(set, frames, contact_work, (contacts, contacts_at), at);
                let mut dissipation = 0.0;
                for p in contacts.iter() {
                    crate::contact::wrench::add_point(p, frames, force_in_n, torque_in_n);
                    dissipation += p.dissipation;
                }
                dissipation
            });
            dydt[diss0 + model.hinges.len()] = dissipation;
        }

        // External loads (crate::loads): their wrench on each body, their power into W.
        let commanded = self.commanded.borrow();
        for load in model.loads.iter().chain(commanded.iter()) {
            let m = &motions[load.body];
            let (f, tau) = load.wrench(t, &m.dcm_n_b);
            force_in_n[load.body] += f;
            torque_in_n[load.body] += tau;
            work_power += crate::loads::power(&f, &tau, &m.v_in_n, &m.omega_in_n);
            impulse += f;
            angular += m.r_in_n.cross(&f) + tau;
        }
        if let Some(c) = &model.control {
            // The hub's control (crate::loads::control): the actuators' torque, the wheels'
            // gyroscopic reaction, the wheels' motor torques as their momenta's rates.
            let hub = &motions[0];
            let wi = crate::state::wheel_index(model);
            let nw = c.wheels().len();
            let efforts = self.actuation(y).unwrap_or_default().efforts;
            let omega_b = hub.omega_in_body();
            let wheel_h = &y[wi..wi + nw];
            let tau_b = c.hub_torque(&efforts) - omega_b.cross(&c.wheel_momentum_in_hub(wheel_h));
            torque_in_n[0] += hub.dcm_n_b * tau_b;
            if nw > 0 {
                // Motor work: u Ω per wheel (the wheel gets u Ω_wheel, the hub −u g·ω).
                for (k, wheel) in c.wheels().iter().enumerate() {
                    work_power += efforts[k] * crate::loads::control::Control::wheel_speed(wheel, wheel_h[k], &omega_b);
                }
                dydt[wi..wi + nw].copy_from_slice(&efforts);
            } else {
                let tau_n = hub.dcm_n_b * c.hub_torque(&efforts);
                work_power += tau_n.dot(&hub.omega_in_n);
                angular += tau_n;
            }
        }
        if let Some(w) = crate::state::work_index(model) {
            dydt[w] = work_power;
            dydt[w + 1..w + 4].copy_from_slice(impulse.as_slice());
            dydt[w + 4..w + 7].copy_from_slice(angular.as_slice());
            dydt[w + 7..w + 10].copy_from_slice(&y[w + 1..w + 4]);
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
            // Locked directions: the constraint correction (crate::dynamics::locks). A singular
            // system (redundant locks) is refused when the run starts.
            let _ = constrain_accelerations(model, rows, motions, dydt, work);
        }
    }
}

/// Marks both bodies of every point as touching.
fn mark_touched<'p>(points: impl Iterator<Item = &'p ContactPoint>, touched: &mut [bool]) {
    for p in points {
        touched[p.key.body as usize] = true;
        touched[p.key.other as usize] = true;
    }
}

/// Every body's frame for contact from its motion.
fn fill_frames(motions: impl Iterator<Item = BodyMotion>, frames: &mut [Frame]) {
    for (f, m) in frames.iter_mut().zip(motions) {
        *f = m.contact_frame();
    }
}

impl crate::integrate::OdeSystem for Dynamics<'_> {
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        // At a break not yet accepted, the step that lands on it sees the left limit of what
        // jumps there (its last stages are at the break); the steps after it the right one.
        let at_break = t > self.accepted.get() && self.breaks.borrow().contains(t);
        self.time.set(if at_break && t > 0.0 { f64::from_bits(t.to_bits() - 1) } else { t });
        Dynamics::rhs(self, y, dydt);
    }

    fn next_break(&self, t: f64) -> Option<f64> {
        let tiny = 1e-12 * t.abs().max(1.0);
        self.breaks.borrow().next_after(t + tiny)
    }

    /// Every body's velocity and angular velocity (crate::state's VEL and OMEGA).
    fn mark_rates(&self, rates: &mut [bool]) {
        use crate::state::{BODY_STATE_LEN, OMEGA, VEL};
        for b in 0..self.model().bodies.len() {
            rates[BODY_STATE_LEN * b + VEL..BODY_STATE_LEN * b + OMEGA + 3].fill(true);
        }
    }
}

impl Dynamics<'_> {
    /// Sets the times at which the right-hand side jumps: the integrator's steps land on
    /// each ([`crate::integrate::OdeSystem::next_break`]).
    pub fn set_breaks(&self, breaks: crate::loads::breaks::Breaks) {
        *self.breaks.borrow_mut() = breaks;
    }
}

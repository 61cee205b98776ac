//! Kinematics: a hinge's relative state from the motions of its two bodies (docs/model.md §2),
//! and the reverse, placing bodies from the hub along the spanning tree from initial
//! conditions given in the paper's relative coordinates (docs/model.md §3).

use crate::law::HingeState;
use crate::math::{Euler321, EulerTrig, Mat3, Real, Vec3, cross, mat_mul_const, mat_tr_mul, mat_tr_vec, mat_vec_const};
use crate::model::{Hinge, Model};
use crate::state::{BodyMotion, State, state_from_motions};
use nalgebra::{Matrix3, Vector3};

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

/// What a hinge's kinematics need from its parent alone: the parent's own quantities and
/// those of the A0 frame fixed in it (N components). The exact Jacobian forms these in the
/// parent's 13 dual lanes only (`crate::dynamics::jacobian`).
#[derive(Clone, Copy, Debug)]
pub struct ParentSide<T: nalgebra::Scalar = f64> {
    /// The parent's CoM, m.
    pub r_in_n: Vector3<T>,
    /// The parent's `ω`, rad/s.
    pub omega_in_n: Vector3<T>,
    /// `[N A0]`.
    pub dcm_n_a0: Matrix3<T>,
    /// A0's origin from the parent CoM, m.
    pub arm_a0_in_n: Vector3<T>,
    /// `Ṙ_A0`, the velocity of A0's origin, m/s.
    pub v_a0_in_n: Vector3<T>,
}

/// What a hinge's kinematics need from its child alone (see [`ParentSide`]).
#[derive(Clone, Copy, Debug)]
pub struct ChildSide<T: nalgebra::Scalar = f64> {
    /// The child's `ω`, rad/s.
    pub omega_in_n: Vector3<T>,
    /// `[N A]`.
    pub dcm_n_a: Matrix3<T>,
    /// A's origin from the child CoM, m.
    pub arm_a_in_n: Vector3<T>,
    /// `R_A`, A's origin, m.
    pub r_a_in_n: Vector3<T>,
    /// `Ṙ_A`, the velocity of A's origin, m/s.
    pub v_a_in_n: Vector3<T>,
}

impl<T: Real> ParentSide<T> {
    /// Hinge `h`'s parent side from the parent's motion.
    #[inline]
    pub fn new(h: &Hinge, parent: &BodyMotion<T>) -> Self {
        let arm_a0 = mat_vec_const(&parent.dcm_n_b, &h.r_a0_in_parent);
        Self {
            r_in_n: parent.r_in_n,
            omega_in_n: parent.omega_in_n,
            dcm_n_a0: mat_mul_const(&parent.dcm_n_b, &h.dcm_parent_a0),
            arm_a0_in_n: arm_a0,
            v_a0_in_n: parent.v_in_n + cross(&parent.omega_in_n, &arm_a0),
        }
    }

    /// Every quantity mapped by `f` (into the lanes of the whole hinge, for the Jacobian).
    pub fn map<U: Real>(&self, f: impl Fn(T) -> U + Copy) -> ParentSide<U> {
        ParentSide {
            r_in_n: self.r_in_n.map(f),
            omega_in_n: self.omega_in_n.map(f),
            dcm_n_a0: self.dcm_n_a0.map(f),
            arm_a0_in_n: self.arm_a0_in_n.map(f),
            v_a0_in_n: self.v_a0_in_n.map(f),
        }
    }
}

impl<T: Real> ChildSide<T> {
    /// Hinge `h`'s child side from the child's motion.
    #[inline]
    pub fn new(h: &Hinge, child: &BodyMotion<T>) -> Self {
        let arm_child = mat_vec_const(&child.dcm_n_b, &h.r_a_in_child);
        Self {
            omega_in_n: child.omega_in_n,
            dcm_n_a: mat_mul_const(&child.dcm_n_b, &h.dcm_child_a),
            arm_a_in_n: arm_child,
            r_a_in_n: child.r_in_n + arm_child,
            v_a_in_n: child.v_in_n + cross(&child.omega_in_n, &arm_child),
        }
    }

    /// Every quantity mapped by `f` (see [`ParentSide::map`]).
    pub fn map<U: Real>(&self, f: impl Fn(T) -> U + Copy) -> ChildSide<U> {
        ChildSide {
            omega_in_n: self.omega_in_n.map(f),
            dcm_n_a: self.dcm_n_a.map(f),
            arm_a_in_n: self.arm_a_in_n.map(f),
            r_a_in_n: self.r_a_in_n.map(f),
            v_a_in_n: self.v_a_in_n.map(f),
        }
    }
}

/// The translational part of a hinge's relative state from its two sides (docs/model.md §2).
#[inline]
fn translation_of_sides<T: Real>(p: &ParentSide<T>, c: &ChildSide<T>) -> HingeTranslation<T> {
    let arm_parent = c.r_a_in_n - p.r_in_n;
    let delta_n = arm_parent - p.arm_a0_in_n;
    // δ̇ = [A0 N](Ṙ_A − Ṙ_A0) − ω_p × δ, the rate of the A0 components.
    let rate_n = c.v_a_in_n - p.v_a0_in_n - cross(&p.omega_in_n, &delta_n);
    HingeTranslation {
        dcm_n_a0: p.dcm_n_a0,
        arm_parent_in_n: arm_parent,
        arm_child_in_n: c.arm_a_in_n,
        delta_in_a0: mat_tr_vec(&p.dcm_n_a0, &delta_n),
        delta_rate_in_a0: mat_tr_vec(&p.dcm_n_a0, &rate_n),
    }
}

/// The translational part of hinge `h`'s relative state from the motions of its parent and
/// child (docs/model.md §2): what [`hinge_kinematics`] computes before the rotation.
#[inline]
pub fn hinge_translation<T: Real>(h: &Hinge, parent: &BodyMotion<T>, child: &BodyMotion<T>) -> HingeTranslation<T> {
    translation_of_sides(&ParentSide::new(h, parent), &ChildSide::new(h, child))
}

/// Relative state of hinge `h` from the motions of its parent and child (docs/model.md §2).
///
/// The Euler angles are taken from `[A A0]` and moved by whole turns in yaw and roll to lie
/// nearest `theta_ref` (docs/model.md §7), so tree and loop hinges alike are continuous.
#[inline]
pub fn hinge_kinematics<T: Real>(
    h: &Hinge,
    parent: &BodyMotion<T>,
    child: &BodyMotion<T>,
    theta_ref: &Euler321,
) -> HingeKinematics<T> {
    kinematics_of_sides(&ParentSide::new(h, parent), &ChildSide::new(h, child), theta_ref)
}

/// [`hinge_kinematics`] from the hinge's two sides.
#[inline]
pub fn kinematics_of_sides<T: Real>(p: &ParentSide<T>, c: &ChildSide<T>, theta_ref: &Euler321) -> HingeKinematics<T> {
    let HingeTranslation {
        dcm_n_a0,
        arm_parent_in_n: arm_parent,
        arm_child_in_n: arm_child,
        delta_in_a0,
        delta_rate_in_a0,
    } = translation_of_sides(p, c);
    let dcm_n_a = c.dcm_n_a;
    let dcm_a_a0 = mat_tr_mul(&dcm_n_a, &dcm_n_a0);
    let theta = Euler321::from_dcm(&dcm_a_a0).unwrapped_near(theta_ref);
    let omega_rel_in_a = mat_tr_vec(&dcm_n_a, &(c.omega_in_n - p.omega_in_n));
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

/// Rates and displacement of one tree hinge (the angles travel separately).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RelativeTwist {
    /// δ, m, A0 components.
    pub delta_in_a0: Vec3,
    /// δ̇ (time derivative of the A0 components), m/s.
    pub delta_rate_in_a0: Vec3,
    /// `ω_{A/A0}`, rad/s, A components.
    pub omega_rel_in_a: Vec3,
}

/// Initial values of one tree hinge; missing values are zero.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HingeInitial {
    /// δ, rates and ω_rel.
    pub twist: RelativeTwist,
    /// `θ_{A/A0}`; `None` means zero unless the placed body's attitude is given instead.
    pub theta: Option<Euler321>,
}

/// Initial conditions of a whole structure (docs/model.md §3, paper Tables 3 and 7).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InitialConditions {
    /// `R_{B/N}`, m, N components.
    pub hub_position_in_n: Vec3,
    /// `θ_{B/N}`.
    pub hub_attitude: Euler321,
    /// `Ṙ_{B/N}`, m/s, N components.
    pub hub_velocity_in_n: Vec3,
    /// `ω_{B/N}`, rad/s, hub components.
    pub hub_omega_in_hub: Vec3,
    /// Per hinge (model order): values for tree hinges; must be `None` for loop hinges.
    pub hinges: Vec<Option<HingeInitial>>,
    /// Per body (model order): `θ_{i/N}` given instead of the angles of the tree hinge that
    /// places the body.
    pub body_attitudes: Vec<Option<Euler321>>,
    /// Per hinge (model order): for a loop hinge, angles its `θ_{A/A0}` starts nearest to
    /// (modulo whole turns of yaw and roll): they choose the branch where the bodies alone
    /// cannot, as for a fold of exactly ±180°. Empty or `None`: principal values.
    pub loop_angles: Vec<Option<Euler321>>,
}

/// Places body `to` from the pose and twist of body `from` across hinge `h` (docs/model.md §3).
///
/// `reversed` is false when `from` is the hinge's parent. The pose follows
/// [`Hinge::place`]; the twist adds the hinge's relative rates: `ω_c = ω_p + [N A] ω_rel`
/// and `Ṙ_A = Ṙ_A0 + [N A0] δ̇ + ω_p × δ`.
pub fn place_motion(h: &Hinge, reversed: bool, from: &BodyMotion, theta: Euler321, rel: &RelativeTwist) -> BodyMotion {
    let dcm_a_a0 = theta.to_dcm();
    let p = h.place(reversed, (from.r_in_n, from.dcm_n_b), &dcm_a_a0, &rel.delta_in_a0);
    if !reversed {
        let (v_p, w_p) = (from.v_in_n, from.omega_in_n);
        let w_c = w_p + p.dcm_n_a * rel.omega_rel_in_a;
        let v_a = v_p + w_p.cross(&p.arm_a0_in_n) + p.dcm_n_a0 * rel.delta_rate_in_a0 + w_p.cross(&p.delta_in_n);
        let v_c = v_a - w_c.cross(&p.arm_a_in_n);
        BodyMotion { r_in_n: p.r_in_n, dcm_n_b: p.dcm_n_b, v_in_n: v_c, omega_in_n: w_c }
    } else {
        let (v_c, w_c) = (from.v_in_n, from.omega_in_n);
        let w_p = w_c - p.dcm_n_a * rel.omega_rel_in_a;
        let v_a = v_c + w_c.cross(&p.arm_a_in_n);
        let v_a0 = v_a - p.dcm_n_a0 * rel.delta_rate_in_a0 - w_p.cross(&p.delta_in_n);
        let v_p = v_a0 - w_p.cross(&p.arm_a0_in_n);
        BodyMotion { r_in_n: p.r_in_n, dcm_n_b: p.dcm_n_b, v_in_n: v_p, omega_in_n: w_p }
    }
}

/// Hinge angles that give body `to` the attitude `[to N]` when placed across `h` from a
/// body whose `[N from]` is known.
fn theta_for_attitude(h: &Hinge, reversed: bool, dcm_n_from: &Mat3, dcm_to_n: &Mat3) -> Euler321 {
    let dcm_a_a0 = if !reversed {
        // [A A0] = [A c][c N][N p][p A0]
        h.dcm_child_a.transpose() * dcm_to_n * dcm_n_from * h.dcm_parent_a0
    } else {
        // [A A0] = [A c][c N][N p][p A0] with c known and p to be placed.
        h.dcm_child_a.transpose() * dcm_n_from.transpose() * dcm_to_n.transpose() * h.dcm_parent_a0
    };
    Euler321::from_dcm(&dcm_a_a0)
}

/// The state vector (bodies, then one zero per hinge for its dissipated energy) and the
/// continuous angle references for the given initial conditions.
///
/// Returns the state and, per hinge, the initial `θ_{A/A0}` (given values for tree hinges,
/// which may lie outside the principal range; principal values for loop hinges).
pub fn initial_state(model: &Model, ic: &InitialConditions) -> (State, Vec<Euler321>) {
    let nb = model.bodies.len();
    let mut motions = vec![BodyMotion::default(); nb];
    motions[0] = BodyMotion {
        r_in_n: ic.hub_position_in_n,
        dcm_n_b: ic.hub_attitude.to_dcm().transpose(),
        v_in_n: ic.hub_velocity_in_n,
        omega_in_n: ic.hub_attitude.to_dcm().transpose() * ic.hub_omega_in_hub,
    };
    let mut theta_refs = vec![Euler321::default(); model.hinges.len()];
    for e in &model.tree {
        let h = &model.hinges[e.hinge];
        let init = ic.hinges.get(e.hinge).copied().flatten().unwrap_or_default();
        let from = motions[e.from];
        let theta = match (init.theta, ic.body_attitudes.get(e.to).copied().flatten()) {
            (Some(t), _) => t,
            (None, Some(att)) => theta_for_attitude(h, e.reversed, &from.dcm_n_b, &att.to_dcm()),
            (None, None) => Euler321::default(),
        };
        theta_refs[e.hinge] = theta;
        motions[e.to] = place_motion(h, e.reversed, &from, theta, &init.twist);
    }
    let mut state: State = state_from_motions(model, &motions);
    // Each hinge's dissipated energy, and contact's, starts at zero (the state's layout,
    // crate::state).
    state.resize(state.len() + model.energy_states(), 0.0);
    for (i, h) in model.hinges.iter().enumerate() {
        if !model.is_tree_hinge[i] {
            let dcm_n_a0 = motions[h.parent].dcm_n_b * h.dcm_parent_a0;
            let dcm_n_a = motions[h.child].dcm_n_b * h.dcm_child_a;
            let principal = Euler321::from_dcm(&(dcm_n_a.transpose() * dcm_n_a0));
            theta_refs[i] = match ic.loop_angles.get(i).copied().flatten() {
                Some(near) => principal.unwrapped_near(&near),
                None => principal,
            };
        }
    }
    (state, theta_refs)
}

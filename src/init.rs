//! Initial conditions in the paper's relative coordinates (MODEL.md §3), turned into body
//! poses and twists by walking the spanning tree from the hub.

use crate::math::{Euler321, Mat3, Vec3};
use crate::model::{Hinge, Model};
use crate::state::{BodyMotion, State, state_from_motions};

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

/// Initial conditions of a whole structure (MODEL.md §3, paper Tables 3 and 7).
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
}

/// Places body `to` from the pose and twist of body `from` across hinge `h` (MODEL.md §3).
///
/// `reversed` is false when `from` is the hinge's parent. Returns the placed body's pose
/// `(R in N, [N to])` and its full motion.
pub fn place_body(
    h: &Hinge,
    reversed: bool,
    from: (Vec3, Mat3),
    theta: Euler321,
    rel: &RelativeTwist,
) -> ((Vec3, Mat3), BodyMotion) {
    let motion = BodyMotion { r_in_n: from.0, dcm_n_b: from.1, v_in_n: Vec3::zeros(), omega_in_n: Vec3::zeros() };
    let placed = place_motion(h, reversed, &motion, theta, rel);
    ((placed.r_in_n, placed.dcm_n_b), placed)
}

/// As [`place_body`], carrying velocities.
pub fn place_motion(h: &Hinge, reversed: bool, from: &BodyMotion, theta: Euler321, rel: &RelativeTwist) -> BodyMotion {
    let dcm_a_a0 = theta.to_dcm();
    let delta = rel.delta_in_a0;
    if !reversed {
        let (r_p, dcm_n_p, v_p, w_p) = (from.r_in_n, from.dcm_n_b, from.v_in_n, from.omega_in_n);
        let dcm_n_a0 = dcm_n_p * h.dcm_parent_a0;
        let dcm_n_a = dcm_n_a0 * dcm_a_a0.transpose();
        let dcm_n_c = dcm_n_a * h.dcm_child_a.transpose();
        let arm_a0 = dcm_n_p * h.r_a0_in_parent;
        let delta_n = dcm_n_a0 * delta;
        let arm_a = dcm_n_c * h.r_a_in_child;
        let r_c = r_p + arm_a0 + delta_n - arm_a;
        let w_c = w_p + dcm_n_a * rel.omega_rel_in_a;
        let v_a = v_p + w_p.cross(&arm_a0) + dcm_n_a0 * rel.delta_rate_in_a0 + w_p.cross(&delta_n);
        let v_c = v_a - w_c.cross(&arm_a);
        BodyMotion { r_in_n: r_c, dcm_n_b: dcm_n_c, v_in_n: v_c, omega_in_n: w_c }
    } else {
        let (r_c, dcm_n_c, v_c, w_c) = (from.r_in_n, from.dcm_n_b, from.v_in_n, from.omega_in_n);
        let dcm_n_a = dcm_n_c * h.dcm_child_a;
        let dcm_n_a0 = dcm_n_a * dcm_a_a0;
        let dcm_n_p = dcm_n_a0 * h.dcm_a0_parent;
        let arm_a = dcm_n_c * h.r_a_in_child;
        let delta_n = dcm_n_a0 * delta;
        let arm_a0 = dcm_n_p * h.r_a0_in_parent;
        let r_p = r_c + arm_a - delta_n - arm_a0;
        let w_p = w_c - dcm_n_a * rel.omega_rel_in_a;
        let v_a = v_c + w_c.cross(&arm_a);
        let v_a0 = v_a - dcm_n_a0 * rel.delta_rate_in_a0 - w_p.cross(&delta_n);
        let v_p = v_a0 - w_p.cross(&arm_a0);
        BodyMotion { r_in_n: r_p, dcm_n_b: dcm_n_p, v_in_n: v_p, omega_in_n: w_p }
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
    // Each hinge's dissipated energy starts at zero (see crate::dynamics::Dynamics).
    state.resize(state.len() + model.hinges.len(), 0.0);
    for (i, h) in model.hinges.iter().enumerate() {
        if !model.is_tree_hinge[i] {
            let dcm_n_a0 = motions[h.parent].dcm_n_b * h.dcm_parent_a0;
            let dcm_n_a = motions[h.child].dcm_n_b * h.dcm_child_a;
            theta_refs[i] = Euler321::from_dcm(&(dcm_n_a.transpose() * dcm_n_a0));
        }
    }
    (state, theta_refs)
}

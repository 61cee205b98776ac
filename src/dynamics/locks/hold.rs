//! Holding the locks between steps: the drift check after every step (which also tells
//! that a free lock has taken load) and the projection back onto the constraint manifold.

use super::rows::{Lock, euler_index, rows};
use super::solve::Workspace;
use crate::kinematics::{hinge_kinematics, hinge_translation};
use crate::math::{Euler321, Vec3};
use crate::model::Model;
use crate::state::{BODY_STATE_LEN, BodyMotion, OMEGA, POS, QUAT, VEL};

/// Drift of a locked coordinate (m or rad) or of its rate (m/s or rad/s) beyond which the
/// state is projected ([`project`]) or a disengaged lock engaged. Well below the 1e-9 the
/// locks promise, and rarely reached at tight tolerances, so the integration is seldom
/// restarted.
pub const DRIFT_LIMIT: f64 = 1e-11;

/// Whether a locked coordinate or its rate has drifted beyond [`DRIFT_LIMIT`] at state `y`
/// (`locks` grouped by hinge).
pub fn drifted(model: &Model, locks: &[Lock], refs: &[Euler321], y: &[f64]) -> bool {
    locks.chunk_by(|a, b| a.hinge == b.hinge).any(|group| drift_mask(model, group, refs, y) != 0)
}

/// Which of `group`'s locks (all of one hinge, so at most six) have drifted beyond
/// [`DRIFT_LIMIT`] in coordinate or rate at state `y`: bit k for `group[k]`. Checked after
/// every step, so from the hinge's kinematics alone (no rows, no allocation), and without
/// angles when only translations are locked.
pub fn drift_mask(model: &Model, group: &[Lock], refs: &[Euler321], y: &[f64]) -> u8 {
    let i = group[0].hinge;
    let h = &model.hinges[i];
    let (p, c) = (BodyMotion::from_state(y, h.parent), BodyMotion::from_state(y, h.child));
    let mask = |beyond: &dyn Fn(&Lock) -> bool| {
        group.iter().enumerate().fold(0u8, |m, (k, lock)| if beyond(lock) { m | (1 << k) } else { m })
    };
    let beyond =
        |value: f64, lock: &Lock, rate: f64| (value - lock.target).abs() > DRIFT_LIMIT || rate.abs() > DRIFT_LIMIT;
    if group.iter().all(|lock| lock.direction < 3) {
        let t = hinge_translation(h, &p, &c);
        return mask(&|l| beyond(t.delta_in_a0[l.direction], l, t.delta_rate_in_a0[l.direction]));
    }
    let k = hinge_kinematics(h, &p, &c, &refs[i]);
    let theta_rate = k.state.trig.rates_from_omega(&k.state.omega_rel_in_a);
    mask(&|l| {
        if l.direction < 3 {
            beyond(k.state.delta_in_a0[l.direction], l, k.state.delta_rate_in_a0[l.direction])
        } else {
            let j = euler_index(l.direction);
            beyond(k.state.theta.as_vector()[j], l, theta_rate[j])
        }
    })
}

/// Projects the state onto the constraint manifold of `locks`: two mass-weighted Newton
/// corrections of the poses, then one of the velocities (the caller decides when, see
/// [`drifted`]). Stops early if the locks are redundant there.
pub fn project(model: &Model, locks: &[Lock], refs: &[Euler321], y: &mut [f64]) {
    let nb = model.bodies.len();
    let motions = |y: &[f64]| (0..nb).map(|i| BodyMotion::from_state(y, i)).collect::<Vec<_>>();
    let mut work = Workspace::default();
    for _ in 0..2 {
        let m = motions(y);
        let rows = rows(model, locks, &m, refs);
        work.prepare(model, &rows, &m);
        let errors: Vec<f64> = rows.iter().map(|r| r.error).collect();
        if !work.correct(model, &rows, &errors) {
            return;
        }
        for &i in &work.touched {
            let d = &work.delta[i];
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for k in 0..3 {
                s[POS + k] += d[k];
            }
            // q ← exp(δφ/2) ⊗ q with δφ in N components (a left rotation).
            let dphi = m[i].dcm_n_b * Vec3::new(d[3], d[4], d[5]);
            let angle = dphi.norm();
            if angle > 0.0 {
                let axis = dphi / angle;
                let (sh, ch) = (0.5 * angle).sin_cos();
                let dq = nalgebra::Quaternion::new(ch, sh * axis.x, sh * axis.y, sh * axis.z);
                let q = nalgebra::Quaternion::new(s[QUAT], s[QUAT + 1], s[QUAT + 2], s[QUAT + 3]);
                let r = dq * q;
                s[QUAT..QUAT + 4].copy_from_slice(&[r.w, r.i, r.j, r.k]);
            }
        }
    }
    // Velocities: remove J V.
    let m = motions(y);
    let rows = rows(model, locks, &m, refs);
    work.prepare(model, &rows, &m);
    let rates: Vec<f64> = rows.iter().map(|r| r.rate).collect();
    if work.correct(model, &rows, &rates) {
        for &i in &work.touched {
            let d = &work.delta[i];
            let s = &mut y[BODY_STATE_LEN * i..BODY_STATE_LEN * (i + 1)];
            for k in 0..3 {
                s[VEL + k] += d[k];
                s[OMEGA + k] += d[3 + k];
            }
        }
    }
}

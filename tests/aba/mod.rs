//! Reduced coordinates for the 1-DOF hinged-panel example, by the articulated-body
//! algorithm: an independent formulation of the locked hinges' dynamics, shared by
//! `tests/locked.rs` (which checks the maximal-coordinate locks against it) and
//! `benches/reduced_1dof.rs` (which times it).
//!
//! Featherstone's articulated-body algorithm in world coordinates (no frame transforms
//! between bodies): a floating hub (body 0) and revolute children turning about A0's z axis
//! with δ, pitch and roll held at zero, the laws evaluated through the same hinge kinematics
//! and law code as the simulator.
#![allow(dead_code)]

use foldsim::dynamics::Dynamics;
use foldsim::kinematics::hinge_kinematics;
use foldsim::kinematics::initial_state;
use foldsim::math::{Euler321, Mat3, Vec3};
use foldsim::scenario::Scenario;
use foldsim::state::{BODY_STATE_LEN as B, BodyMotion};
use nalgebra::{Matrix6, Rotation3, UnitQuaternion, Vector6};

fn skew(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Spatial cross products for v = (ω, v_O): motion `v × m` and force `v ×* f`.
fn cross_motion(v: &Vector6<f64>, m: &Vector6<f64>) -> Vector6<f64> {
    let (w, vo) = (v.fixed_rows::<3>(0).into_owned(), v.fixed_rows::<3>(3).into_owned());
    let (mw, mv) = (m.fixed_rows::<3>(0).into_owned(), m.fixed_rows::<3>(3).into_owned());
    let (a, b) = (w.cross(&mw), w.cross(&mv) + vo.cross(&mw));
    Vector6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}
fn cross_force(v: &Vector6<f64>, f: &Vector6<f64>) -> Vector6<f64> {
    let (w, vo) = (v.fixed_rows::<3>(0).into_owned(), v.fixed_rows::<3>(3).into_owned());
    let (fn_, ff) = (f.fixed_rows::<3>(0).into_owned(), f.fixed_rows::<3>(3).into_owned());
    let (a, b) = (w.cross(&fn_) + vo.cross(&ff), w.cross(&ff));
    Vector6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}

/// Spatial inertia about N's origin, N components, of a body of mass `m`, CoM `c`, central
/// inertia `i_c`.
fn spatial_inertia(m: f64, c: &Vec3, i_c: &Mat3) -> Matrix6<f64> {
    let cx = skew(c);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&(i_c + cx * cx.transpose() * m));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(cx * m));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(cx.transpose() * m));
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&(Mat3::identity() * m));
    out
}

/// The reduced model: hub (body 0) and children on revolute joints about A0's z.
pub struct Reduced<'m> {
    pub s: &'m Scenario,
    pub refs: Vec<Euler321>,
}

type Joint = (usize, Vector6<f64>, Vector6<f64>, Vector6<f64>, f64, f64);

/// Per-evaluation work space (kept, so an evaluation allocates nothing).
#[derive(Default)]
pub struct Scratch {
    pub motions: Vec<BodyMotion>,
    f_ext: Vec<Vector6<f64>>,
    art: Vec<Matrix6<f64>>,
    bias: Vec<Vector6<f64>>,
    /// Per hinge: (index, motion subspace s, velocity-product acceleration c, U = I^A s,
    /// D = sᵀU, u = −sᵀ p^A).
    joint: Vec<Joint>,
    acc: Vec<Vector6<f64>>,
    pub yaw_acc: Vec<f64>,
}

impl Reduced<'_> {
    /// Body motions from the reduced state: hub's 13 numbers, then (yaw, yaw rate) per hinge.
    fn motions(&self, x: &[f64], out: &mut Vec<BodyMotion>) {
        let model = &self.s.model;
        out.clear();
        out.resize(model.bodies.len(), BodyMotion::default());
        out[0] = BodyMotion::from_state(x, 0);
        for (i, h) in model.hinges.iter().enumerate() {
            let (yaw, yaw_rate) = (x[B + 2 * i], x[B + 2 * i + 1]);
            let p = out[h.parent];
            let dcm_n_a0 = p.dcm_n_b * h.dcm_a0_parent.transpose();
            let (s, c) = yaw.sin_cos();
            let dcm_a0_a = Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
            let dcm_n_a = dcm_n_a0 * dcm_a0_a;
            let r_a = p.r_in_n + p.dcm_n_b * h.r_a0_in_parent;
            let r_c = r_a + dcm_n_a * h.r_child_in_a;
            let omega = p.omega_in_n + dcm_n_a0.column(2) * yaw_rate;
            let v_a = p.v_in_n + p.omega_in_n.cross(&(r_a - p.r_in_n));
            out[h.child] = BodyMotion {
                r_in_n: r_c,
                dcm_n_b: dcm_n_a * h.dcm_child_a.transpose(),
                v_in_n: v_a + omega.cross(&(r_c - r_a)),
                omega_in_n: omega,
            };
        }
    }

    /// The reduced state's derivative's accelerations: hub (v̇ N, ω̇ body) and yaw accelerations.
    pub fn accelerations(&self, x: &[f64], scratch: &mut Scratch) -> [f64; 6] {
        let model = &self.s.model;
        let Scratch { motions, f_ext, art, bias, joint, acc, yaw_acc } = scratch;
        self.motions(x, motions);
        let nb = model.bodies.len();
        // Hinge wrenches as external spatial forces (torque about N's origin, force), N.
        f_ext.clear();
        f_ext.resize(nb, Vector6::zeros());
        for (i, h) in model.hinges.iter().enumerate() {
            let (p, c) = (&motions[h.parent], &motions[h.child]);
            let k = hinge_kinematics(h, p, c, &self.refs[i]);
            let w = h.law.wrench(&k.state, &Default::default());
            let f = k.dcm_n_a0 * w.force_in_a0;
            let tau = k.dcm_n_a * w.torque_in_a;
            let r_a = c.r_in_n + k.arm_child_in_n;
            let about_o = tau + r_a.cross(&f);
            let pair = Vector6::new(about_o.x, about_o.y, about_o.z, f.x, f.y, f.z);
            f_ext[h.parent] += pair;
            f_ext[h.child] -= pair;
        }
        // Spatial velocities, inertias, bias forces.
        let spatial_v = |m: &BodyMotion| {
            let vo = m.v_in_n - m.omega_in_n.cross(&m.r_in_n);
            Vector6::new(m.omega_in_n.x, m.omega_in_n.y, m.omega_in_n.z, vo.x, vo.y, vo.z)
        };
        art.clear();
        bias.clear();
        for (b, m) in model.bodies.iter().zip(motions.iter()) {
            let i_c = m.dcm_n_b * b.inertia_in_body * m.dcm_n_b.transpose();
            let inertia = spatial_inertia(b.mass, &m.r_in_n, &i_c);
            let v = spatial_v(m);
            art.push(inertia);
            bias.push(cross_force(&v, &(inertia * v)) - f_ext[art.len() - 1]);
        }
        joint.clear();
        for (i, h) in model.hinges.iter().enumerate().rev() {
            let p = &motions[h.parent];
            let axis = p.dcm_n_b * h.dcm_a0_parent.transpose().column(2);
            let r_a = p.r_in_n + p.dcm_n_b * h.r_a0_in_parent;
            let la = r_a.cross(&axis);
            let s = Vector6::new(axis.x, axis.y, axis.z, la.x, la.y, la.z);
            let c = cross_motion(&spatial_v(&motions[h.child]), &(s * x[B + 2 * i + 1]));
            let u_vec = art[h.child] * s;
            let d = s.dot(&u_vec);
            let u = -s.dot(&bias[h.child]);
            let art_a = art[h.child] - u_vec * u_vec.transpose() / d;
            let bias_a = bias[h.child] + art_a * c + u_vec * (u / d);
            art[h.parent] += art_a;
            bias[h.parent] += bias_a;
            joint.push((i, s, c, u_vec, d, u));
        }
        let a0 = -(art[0].cholesky().expect("SPD").solve(&bias[0]));
        acc.clear();
        acc.resize(nb, Vector6::zeros());
        acc[0] = a0;
        yaw_acc.clear();
        yaw_acc.resize(model.hinges.len(), 0.0);
        for &(i, s, c, u_vec, d, u) in joint.iter().rev() {
            let h = &model.hinges[i];
            let a = acc[h.parent] + c;
            let q_dd = (u - u_vec.dot(&a)) / d;
            acc[h.child] = a + s * q_dd;
            yaw_acc[i] = q_dd;
        }
        let hub = &motions[0];
        let (alpha, ao) = (acc[0].fixed_rows::<3>(0).into_owned(), acc[0].fixed_rows::<3>(3).into_owned());
        let a_c = ao + alpha.cross(&hub.r_in_n) + hub.omega_in_n.cross(&hub.v_in_n);
        let w_dot = hub.dcm_n_b.transpose() * alpha;
        [a_c.x, a_c.y, a_c.z, w_dot.x, w_dot.y, w_dot.z]
    }
}

pub fn quat(dcm_n_b: &Mat3) -> [f64; 4] {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*dcm_n_b));
    [q.w, q.i, q.j, q.k]
}

pub fn example(locked: bool) -> Scenario {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(dir.join("hinged-panels-1dof.toml")).expect("example");
    let text = if locked { text } else { text.replace("{ locked = true }", "{ free = true }") };
    Scenario::from_toml_in(&text, "1dof", &dir).expect("valid")
}

/// A moving state of the 1-DOF example in reduced coordinates: the hub spinning and
/// drifting, both panels folding and turning.
pub fn moving_state(s: &Scenario) -> Vec<f64> {
    let (y0, _) = initial_state(&s.model, &s.initial);
    let mut x = y0[..B].to_vec();
    x[7..13].copy_from_slice(&[0.01, -0.02, 0.005, 0.03, -0.01, 0.02]);
    for (i, yaw) in [(0, 0.087), (1, -0.03)] {
        x.extend_from_slice(&[yaw, 0.05 * (i as f64 + 1.0)]);
    }
    x
}

/// The reduced accelerations at `x` against the maximal-coordinate locked right-hand side at
/// the same state: (that maximal state, largest hub-acceleration difference, largest hub
/// acceleration, largest yaw-acceleration difference).
pub fn compare(s: &Scenario, x: &[f64]) -> (Vec<f64>, f64, f64, f64) {
    let (y0, refs) = initial_state(&s.model, &s.initial);
    let dynamics = Dynamics::new(&s.model, refs.clone());
    dynamics.initialize_memory(&y0);
    for h in &s.model.hinges {
        assert_eq!(h.parent, 0, "children of the hub only");
    }
    let reduced = Reduced { s, refs };
    let mut scratch = Scratch::default();
    let hub_acc = reduced.accelerations(x, &mut scratch);
    let (motions, yaw_acc) = (&scratch.motions, &scratch.yaw_acc);
    let mut y = vec![0.0; dynamics.state_len()];
    for (b, m) in motions.iter().enumerate() {
        let s = &mut y[B * b..B * (b + 1)];
        s[0..3].copy_from_slice(m.r_in_n.as_slice());
        s[3..7].copy_from_slice(&quat(&m.dcm_n_b));
        s[7..10].copy_from_slice(m.v_in_n.as_slice());
        s[10..13].copy_from_slice((m.dcm_n_b.transpose() * m.omega_in_n).as_slice());
    }
    let mut dydt = vec![0.0; y.len()];
    dynamics.rhs(&y, &mut dydt);
    let hub_diff = (0..6).map(|k| (hub_acc[k] - dydt[7 + k]).abs()).fold(0.0, f64::max);
    let scale = (0..6).map(|k| dydt[7 + k].abs()).fold(1e-300, f64::max);
    // Panel i's yaw acceleration from the maximal accelerations: the A0-z component of its
    // angular acceleration relative to the hub (less the hub's ω × relative rate).
    let mut yaw_diff = 0.0f64;
    for (i, h) in s.model.hinges.iter().enumerate() {
        let (p, c) = (&motions[h.parent], &motions[h.child]);
        let alpha =
            |m: &BodyMotion, b: usize| m.dcm_n_b * Vec3::new(dydt[B * b + 10], dydt[B * b + 11], dydt[B * b + 12]);
        let axis = p.dcm_n_b * h.dcm_a0_parent.transpose().column(2);
        let rel = alpha(c, h.child) - alpha(p, h.parent) - p.omega_in_n.cross(&(c.omega_in_n - p.omega_in_n));
        yaw_diff = yaw_diff.max((rel.dot(&axis) - yaw_acc[i]).abs());
    }
    (y, hub_diff, scale, yaw_diff)
}

//! An independent check of the equations of motion: Lagrange's equations (docs/model.md §3,
//! paper eq. 1) in the paper's relative coordinates q = [R_B, θ_B, δ_h, θ_h …], formed by
//! automatic differentiation (num-dual) of the kinetic energy written from positions and
//! direction cosine matrices alone, with the generalized forces of docs/model.md §4 (eq. 14) for
//! tree and loop hinges. The engine integrates bodies in maximal coordinates with hinge
//! wrench pairs; both must give the same body accelerations at random states.
//!
//! Tolerance 1e-9 relative to max(1, |a|) (the core issue's): both sides are exact to
//! round-off (dual numbers carry exact derivatives; the only solve is one 24×24 LU), so a
//! formulation error — a wrong application point, frame or sign — shows at 1e-3 or more.

mod common;
use common::*;
use foldsim::dynamics::Dynamics;
use foldsim::math::Euler321;
use foldsim::model::Model;
use foldsim::scenario::Scenario;
use foldsim::state::{BODY_STATE_LEN, BodyMotion, OMEGA, VEL, state_from_motions};
use nalgebra::{DMatrix, DVector, Matrix3};
use num_dual::{Dual, Dual2, DualNum, HyperDual};

type V<T> = [T; 3];
type M<T> = [[T; 3]; 3];

trait Num: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Num for T {}

fn k<T: Num>(x: f64) -> T {
    T::from(x)
}
fn mm<T: Num>(a: &M<T>, b: &M<T>) -> M<T> {
    let mut r = [[k::<T>(0.0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    r
}
fn tr<T: Num>(a: &M<T>) -> M<T> {
    let mut r = *a;
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = a[j][i];
        }
    }
    r
}
fn mv<T: Num>(a: &M<T>, v: &V<T>) -> V<T> {
    [0, 1, 2].map(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}
fn add<T: Num>(a: &V<T>, b: &V<T>) -> V<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub<T: Num>(a: &V<T>, b: &V<T>) -> V<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot<T: Num>(a: &V<T>, b: &V<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cm<T: Num>(m: &Matrix3<f64>) -> M<T> {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| k(m[(i, j)])))
}
fn cv<T: Num>(v: &nalgebra::Vector3<f64>) -> V<T> {
    [k(v.x), k(v.y), k(v.z)]
}
/// [XY] = M1(roll) M2(pitch) M3(yaw), from the elementary rotations of docs/model.md §1.
fn euler<T: Num>(yaw: T, pitch: T, roll: T) -> M<T> {
    let (o, l) = (k::<T>(0.0), k::<T>(1.0));
    let (s1, c1) = (yaw.sin(), yaw.cos());
    let (s2, c2) = (pitch.sin(), pitch.cos());
    let (s3, c3) = (roll.sin(), roll.cos());
    let m1 = [[l, o, o], [o, c3, s3], [o, -s3, c3]];
    let m2 = [[c2, o, -s2], [o, l, o], [s2, o, c2]];
    let m3 = [[c1, s1, o], [-s1, c1, o], [o, o, l]];
    mm(&m1, &mm(&m2, &m3))
}
/// Principal 3-2-1 angles of [XY].
fn angles<T: Num>(c: &M<T>) -> V<T> {
    [c[0][1].atan2(c[0][0]), -c[0][2].asin(), c[1][2].atan2(c[2][2])]
}
/// ω from [XY] and its rate: [ω×] = −[XY]̇ [XY]ᵀ, X components.
fn omega<T: Num>(c: &M<T>, cdot: &M<T>) -> V<T> {
    let w = mm(cdot, &tr(c));
    [-w[2][1], -w[0][2], -w[1][0]]
}

/// Positions, DCMs and their time derivatives for coordinates q, rates qd.
struct Kin<T> {
    r: Vec<V<T>>,
    rdot: Vec<V<T>>,
    /// [i N] and its rate.
    c: Vec<M<T>>,
    cdot: Vec<M<T>>,
    delta: Vec<V<T>>,
    delta_rate: Vec<V<T>>,
    theta: Vec<V<T>>,
    omega_rel: Vec<V<T>>,
}

/// docs/model.md §3 forward kinematics over the tree; velocities by a dual number along q̇.
fn kin<T: Num>(model: &Model, q: &[T], qd: &[T]) -> Kin<T> {
    type D<T> = Dual<T>;
    let z: Vec<D<T>> = q.iter().zip(qd).map(|(a, b)| Dual::new(*a, *b)).collect();
    let nb = model.bodies.len();
    let mut r: Vec<V<D<T>>> = vec![[k(0.0); 3]; nb];
    let mut c: Vec<M<D<T>>> = vec![[[k(0.0); 3]; 3]; nb];
    r[0] = [z[0], z[1], z[2]];
    c[0] = euler(z[3], z[4], z[5]);
    for (e_idx, e) in model.tree.iter().enumerate() {
        assert!(!e.reversed, "this check walks the tree parent to child");
        let h = &model.hinges[e.hinge];
        let o = 6 + 6 * e_idx;
        let delta = [z[o], z[o + 1], z[o + 2]];
        let c_a_a0 = euler(z[o + 3], z[o + 4], z[o + 5]);
        let (p, ch) = (h.parent, h.child);
        // [cN] = [cA][AA0][A0p][pN]
        let c_a0_n = mm(&cm(&h.dcm_a0_parent), &c[p]);
        let c_a_n = mm(&c_a_a0, &c_a0_n);
        c[ch] = mm(&cm(&h.dcm_child_a), &c_a_n);
        // R_c = R_p + [Np] r_{A0/p} + [N A0] δ + [N A] r_{c/A}
        let r_c = add(
            &add(&r[p], &mv(&tr(&c[p]), &cv(&h.r_a0_in_parent))),
            &add(&mv(&tr(&c_a0_n), &delta), &mv(&tr(&c_a_n), &cv(&h.r_child_in_a))),
        );
        r[ch] = r_c;
    }
    let re = |v: &V<D<T>>| v.map(|x| x.re);
    let ep = |v: &V<D<T>>| v.map(|x| x.eps);
    let rem = |m: &M<D<T>>| m.map(|row| row.map(|x| x.re));
    let epm = |m: &M<D<T>>| m.map(|row| row.map(|x| x.eps));
    let mut out = Kin {
        r: r.iter().map(re).collect(),
        rdot: r.iter().map(ep).collect(),
        c: c.iter().map(rem).collect(),
        cdot: c.iter().map(epm).collect(),
        delta: vec![],
        delta_rate: vec![],
        theta: vec![],
        omega_rel: vec![],
    };
    // Every hinge, tree or loop, from the poses of its two bodies (paper eqs. 20–21).
    for h in &model.hinges {
        let (p, ch) = (h.parent, h.child);
        let c_a0_n = mm(&cm(&h.dcm_a0_parent), &c[p]);
        let c_a_n = mm(&tr(&cm(&h.dcm_child_a)), &c[ch]);
        let r_a0 = add(&r[p], &mv(&tr(&c[p]), &cv(&h.r_a0_in_parent)));
        let r_a = sub(&r[ch], &mv(&tr(&c_a_n), &cv(&h.r_child_in_a)));
        let delta = mv(&c_a0_n, &sub(&r_a, &r_a0));
        let c_rel = mm(&c_a_n, &tr(&c_a0_n));
        out.delta.push(re(&delta));
        out.delta_rate.push(ep(&delta));
        out.theta.push(angles(&rem(&c_rel)));
        out.omega_rel.push(omega(&rem(&c_rel), &epm(&c_rel)));
    }
    out
}

/// Kinetic energy (docs/model.md §3).
fn kinetic<T: Num>(model: &Model, kq: &Kin<T>) -> T {
    let mut t = k::<T>(0.0);
    for (i, b) in model.bodies.iter().enumerate() {
        let w = omega(&kq.c[i], &kq.cdot[i]);
        let iw = mv(&cm(&b.inertia_in_body), &w);
        t += (dot(&kq.rdot[i], &kq.rdot[i]) * b.mass + dot(&w, &iw)) * 0.5;
    }
    t
}

/// The laws as the test writes them (docs/model.md §4), one set of gains for every hinge.
#[derive(Clone, Copy)]
struct Gains {
    k_f: Matrix3<f64>,
    k_t: Matrix3<f64>,
    c_f: Matrix3<f64>,
    c_t: Matrix3<f64>,
    euler_potential: bool,
}

fn phi<T: Num>(theta: &V<T>) -> V<T> {
    [theta[2], theta[1], theta[0]]
}

fn potential<T: Num>(g: &Gains, kq: &Kin<T>) -> T {
    let mut v = k::<T>(0.0);
    for (d, th) in kq.delta.iter().zip(&kq.theta) {
        let p = phi(th);
        v += (dot(d, &mv(&cm(&g.k_f), d)) + dot(&p, &mv(&cm(&g.k_t), &p))) * 0.5;
    }
    v
}

fn seed<T: Num>(x: &[f64]) -> Vec<T> {
    x.iter().map(|&v| k(v)).collect()
}

/// q̈ from Lagrange's equations at (q, q̇).
fn lagrange_qdd(model: &Model, g: &Gains, q: &[f64], qd: &[f64]) -> DVector<f64> {
    let n = q.len();
    let base = kin::<f64>(model, q, qd);
    // Hinge force and torque not derived from V: law 1 whole, law 2 only its damping.
    let mut f = Vec::new();
    let mut tau = Vec::new();
    for h in 0..model.hinges.len() {
        let d = nalgebra::Vector3::from(base.delta[h]);
        let dd = nalgebra::Vector3::from(base.delta_rate[h]);
        let p = nalgebra::Vector3::from(phi(&base.theta[h]));
        let w = nalgebra::Vector3::from(base.omega_rel[h]);
        let (fs, ts) = if g.euler_potential {
            (nalgebra::Vector3::zeros(), nalgebra::Vector3::zeros())
        } else {
            (g.k_f * d, g.k_t * p)
        };
        f.push(fs + g.c_f * dd);
        tau.push(ts + g.c_t * w);
    }
    let unit = |j: usize| -> Vec<f64> { (0..n).map(|i| if i == j { 1.0 } else { 0.0 }).collect() };

    // Mass matrix M_ij = ∂²T/∂q̇_i∂q̇_j (hyper-dual numbers: exact).
    let mut mass = DMatrix::zeros(n, n);
    for i in 0..n {
        for j in i..n {
            let qh: Vec<HyperDual<f64>> = seed(q);
            let qdh: Vec<HyperDual<f64>> = (0..n)
                .map(|l| HyperDual::new(qd[l], if l == i { 1.0 } else { 0.0 }, if l == j { 1.0 } else { 0.0 }, 0.0))
                .collect();
            let m = kinetic(model, &kin(model, &qh, &qdh)).eps1eps2;
            mass[(i, j)] = m;
            mass[(j, i)] = m;
        }
    }
    let mut rhs = DVector::zeros(n);
    for j in 0..n {
        // ∂T/∂q_j, ∂V/∂q_j and Σ F·∂δ/∂q_j.
        let ej = unit(j);
        let qj: Vec<Dual<f64>> = q.iter().zip(&ej).map(|(a, b)| Dual::new(*a, *b)).collect();
        let kq = kin(model, &qj, &seed::<Dual<f64>>(qd));
        let dt_dq = kinetic(model, &kq).eps;
        let dv_dq = if g.euler_potential { potential(g, &kq).eps } else { 0.0 };
        let df_dq: f64 =
            kq.delta.iter().zip(&f).map(|(d, fh)| fh.x * d[0].eps + fh.y * d[1].eps + fh.z * d[2].eps).sum();
        // Σ τ·∂ω_rel/∂q̇_j.
        let qdj: Vec<Dual<f64>> = qd.iter().zip(&ej).map(|(a, b)| Dual::new(*a, *b)).collect();
        let kv = kin(model, &seed::<Dual<f64>>(q), &qdj);
        let dtau: f64 =
            kv.omega_rel.iter().zip(&tau).map(|(w, t)| t.x * w[0].eps + t.y * w[1].eps + t.z * w[2].eps).sum();
        // (Ṁ q̇)_j = ∂²T/∂q̇_j∂q · q̇.
        let qh: Vec<HyperDual<f64>> = q.iter().zip(qd).map(|(a, b)| HyperDual::new(*a, *b, 0.0, 0.0)).collect();
        let qdh: Vec<HyperDual<f64>> = qd.iter().zip(&ej).map(|(a, b)| HyperDual::new(*a, 0.0, *b, 0.0)).collect();
        let mdot_qd = kinetic(model, &kin(model, &qh, &qdh)).eps1eps2;
        rhs[j] = dt_dq - mdot_qd - dv_dq - df_dq - dtau;
    }
    mass.lu().solve(&rhs).expect("mass matrix is positive definite")
}

struct Lcg(u64);
impl Lcg {
    fn uniform(&mut self, half_width: f64) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let u = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        half_width * (2.0 * u - 1.0)
    }
}

fn check(s: &Scenario, g: Gains, states: usize) {
    let model = &s.model;
    let n = 6 * model.bodies.len();
    // Start from the scenario's initial coordinates and perturb them.
    let mut q0 = vec![0.0; n];
    for (e_idx, e) in model.tree.iter().enumerate() {
        if let Some(init) = s.initial.hinges[e.hinge] {
            let o = 6 + 6 * e_idx;
            q0[o..o + 3].copy_from_slice(init.twist.delta_in_a0.as_slice());
            let t = init.theta.unwrap_or_default();
            q0[o + 3..o + 6].copy_from_slice(&[t.yaw, t.pitch, t.roll]);
        }
    }
    let mut rng = Lcg(0x5eed);
    let mut worst: f64 = 0.0;
    for _ in 0..states {
        let q: Vec<f64> = q0
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                let within = i % 6;
                x + if i < 3 {
                    rng.uniform(1.0)
                } else if within < 3 {
                    rng.uniform(0.02)
                } else {
                    rng.uniform(0.3)
                }
            })
            .collect();
        let qd: Vec<f64> =
            (0..n).map(|i| if i % 6 < 3 && i >= 6 { rng.uniform(0.05) } else { rng.uniform(0.5) }).collect();
        let qdd = lagrange_qdd(model, &g, &q, &qd);

        // Body accelerations from q̈: second derivative along q(ε) = q + ε q̇ + ½ε² q̈.
        let q2: Vec<Dual2<f64>> = (0..n).map(|i| Dual2::new(q[i], qd[i], qdd[i])).collect();
        let kq2 = kin(model, &q2, &vec![Dual2::from(0.0); n]);

        // The engine at the same state.
        let base = kin::<f64>(model, &q, &qd);
        let motions: Vec<BodyMotion> = (0..model.bodies.len())
            .map(|i| {
                let c = Matrix3::from_fn(|a, b| base.c[i][a][b]);
                let w_body = nalgebra::Vector3::from(omega(&base.c[i], &base.cdot[i]));
                BodyMotion {
                    r_in_n: nalgebra::Vector3::from(base.r[i]),
                    dcm_n_b: c.transpose(),
                    v_in_n: nalgebra::Vector3::from(base.rdot[i]),
                    omega_in_n: c.transpose() * w_body,
                }
            })
            .collect();
        let mut y = state_from_motions(model, &motions);
        let refs: Vec<Euler321> = base.theta.iter().map(|t| Euler321::new(t[0], t[1], t[2])).collect();
        let dynamics = Dynamics::new(model, refs);
        y.resize(dynamics.state_len(), 0.0);
        let mut dydt = vec![0.0; y.len()];
        dynamics.rhs(&y, &mut dydt);

        for i in 0..model.bodies.len() {
            let o = BODY_STATE_LEN * i;
            let a_engine = nalgebra::Vector3::new(dydt[o + VEL], dydt[o + VEL + 1], dydt[o + VEL + 2]);
            let a_lagrange = nalgebra::Vector3::new(kq2.r[i][0].v2, kq2.r[i][1].v2, kq2.r[i][2].v2);
            // ω̇ in body components: [ω̇×] = −C̈Cᵀ − ĊĊᵀ.
            let c = Matrix3::from_fn(|a, b| kq2.c[i][a][b].re);
            let cd = Matrix3::from_fn(|a, b| kq2.c[i][a][b].v1);
            let cdd = Matrix3::from_fn(|a, b| kq2.c[i][a][b].v2);
            let w = -(cdd * c.transpose() + cd * cd.transpose());
            let wdot_lagrange = nalgebra::Vector3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
            let wdot_engine = nalgebra::Vector3::new(dydt[o + OMEGA], dydt[o + OMEGA + 1], dydt[o + OMEGA + 2]);
            for (e, l) in [(a_engine, a_lagrange), (wdot_engine, wdot_lagrange)] {
                let err = (e - l).norm() / l.norm().max(1.0);
                worst = worst.max(err);
                assert!(
                    err <= 1e-9,
                    "body {}: engine {e:?} vs Lagrange {l:?} (relative {err:e})",
                    model.bodies[i].name
                );
            }
        }
    }
    eprintln!("largest relative acceleration difference over {states} states: {worst:e}");
}

fn with_law(path: &str, law: &str) -> Scenario {
    let text = std::fs::read_to_string(repo(path)).unwrap();
    let text: String = text
        .lines()
        .map(|l| if l.starts_with("law = ") { format!("law = {law}") } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    Scenario::from_toml(&text, path).unwrap()
}

const K_F: [[f64; 3]; 3] = [[100.0, 5.0, -3.0], [5.0, 150.0, 2.0], [-3.0, 2.0, 80.0]];
const K_T: [[f64; 3]; 3] = [[10.0, 1.0, 0.5], [1.0, 12.0, -0.7], [0.5, -0.7, 8.0]];
const C_F: [[f64; 3]; 3] = [[2.0, 0.1, 0.0], [0.3, 1.5, 0.0], [0.0, 0.2, 1.0]];
const C_T: [[f64; 3]; 3] = [[0.5, 0.0, 0.1], [0.0, 0.4, 0.0], [0.05, 0.0, 0.3]];

fn toml_matrix(m: &[[f64; 3]; 3]) -> String {
    format!("[{}]", m.iter().map(|r| format!("[{}, {}, {}]", r[0], r[1], r[2])).collect::<Vec<_>>().join(", "))
}

fn gains(euler_potential: bool) -> (Gains, String) {
    let law = format!(
        "{{ type = \"{}\", k_f = {}, k_theta = {}, c_f = {}, c_theta = {} }}",
        if euler_potential { "euler-potential" } else { "paper-linear" },
        toml_matrix(&K_F),
        toml_matrix(&K_T),
        toml_matrix(&C_F),
        toml_matrix(&C_T)
    );
    let m = |a: &[[f64; 3]; 3]| Matrix3::from_fn(|i, j| a[i][j]);
    (Gains { k_f: m(&K_F), k_t: m(&K_T), c_f: m(&C_F), c_t: m(&C_T), euler_potential }, law)
}

#[test]
fn engine_matches_lagrange_law1_tree_and_loop() {
    let (g, law) = gains(false);
    check(&with_law("examples/paper-3panel.toml", &law), g, 20);
}

#[test]
fn engine_matches_lagrange_law2_tree_and_loop() {
    let (g, law) = gains(true);
    check(&with_law("examples/paper-3panel-euler.toml", &law), g, 20);
}

#[test]
fn engine_matches_lagrange_one_panel() {
    for ep in [false, true] {
        let (g, law) = gains(ep);
        check(&with_law("examples/paper-1panel.toml", &law), g, 20);
    }
}

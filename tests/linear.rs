//! Linear models and modes (docs/linear.md): analytic frequencies, the rigid-body modes, the
//! exact linearisation against differences of the nonlinear right-hand side.

mod common;

use foldsim::dynamics::Dynamics;
use foldsim::linear::Linearization;
use foldsim::linear::equilibrium::Equilibrium;
use foldsim::linear::modes::Modes;
use foldsim::math::{Mat3, Vec3};
use foldsim::scenario::Scenario;
use foldsim::state::BodyMotion;

const B: usize = 13;

/// The dynamics of a scenario at its initial state (memory set, accepted at t = 0).
fn at_start(s: &Scenario) -> (Dynamics<'_>, Vec<f64>) {
    let (y, refs) = foldsim::kinematics::initial_state(&s.model, &s.initial);
    let d = Dynamics::new(&s.model, refs);
    d.initialize_memory(&y);
    d.accept(0.0, &y).unwrap();
    (d, y)
}

/// The modes of a scenario's initial state.
fn modes_at_start(s: &Scenario) -> Modes {
    let (d, y) = at_start(s);
    let lin = Linearization::at(&d, &y, Vec3::zeros()).unwrap();
    let motions: Vec<BodyMotion> = (0..s.model.bodies.len()).map(|i| BodyMotion::from_state(&y, i)).collect();
    let positions: Vec<Vec3> = motions.iter().map(|m| m.r_in_n).collect();
    let dcms: Vec<Mat3> = motions.iter().map(|m| m.dcm_n_b).collect();
    Modes::of(&lin, &positions, &dcms).unwrap()
}

/// A hub and one panel whose centres of mass both lie on the hinge's z axis: the relative
/// rotation about z loads no other direction, so its frequency is `√(k/I_eff)` with
/// `I_eff = I_h I_p / (I_h + I_p)` (the two inertias about z) free-free, and `√(k/I_p)` with
/// the hub held. Bound 1e-9 relative (the eigen-solver's round-off, ~1e-13).
#[test]
fn one_panel_frequency_is_analytic() {
    let (k, ih, ip): (f64, f64, f64) = (10.0, 40.0, 1.5);
    let s = Scenario::from_toml(&one_panel(k, ih, ip), "one-panel.toml").unwrap_or_else(|e| panic!("{e}"));
    let modes = modes_at_start(&s);
    let expected = (k * (ih + ip) / (ih * ip)).sqrt();
    let free =
        modes.free.iter().filter(|m| !m.rigid).map(|m| (m.omega / expected - 1.0).abs()).fold(f64::INFINITY, f64::min);
    let clamped = (k / ip).sqrt();
    let fixed = modes.hub_fixed.iter().map(|m| (m.omega / clamped - 1.0).abs()).fold(f64::INFINITY, f64::min);
    println!(
        "free-free √(k/I_eff) = {expected:.12} rad/s: nearest mode off by {free:.2e}; hub fixed √(k/I_p) = {clamped:.12}: {fixed:.2e}"
    );
    assert!(free < 1e-9 && fixed < 1e-9, "{free:e} {fixed:e}");
}

/// The scenario of [`one_panel_frequency_is_analytic`]: hinge stiffness `k` about z, the
/// hub's and the panel's inertias about z `ih`, `ip`.
fn one_panel(k: f64, ih: f64, ip: f64) -> String {
    hub_and_panel(
        (100.0, [50.0, 45.0, ih]),
        (7.0, [2.0, 1.8, ip]),
        ([0.0, 0.0, 0.8], [0.0, 0.0, 0.4]),
        1e4,
        [30.0, 25.0, k],
    )
}

/// A hub and one panel `p1` on a law-2 hinge `h1` (DOP853 at 1e-10, 1 s): each body's mass
/// (kg) and principal inertia (kg·m²), the hinge's A0 origin in the hub and the panel's centre
/// of mass in A (m), its stretch stiffness (N/m) and rotational stiffnesses (N·m/rad).
fn hub_and_panel(
    hub: (f64, [f64; 3]),
    panel: (f64, [f64; 3]),
    place: ([f64; 3], [f64; 3]),
    k_f: f64,
    k_theta: [f64; 3],
) -> String {
    let ((mh, ih), (mp, ip), (a0, com)) = (hub, panel, place);
    format!(
        r#"
[run]
duration = 1.0
output_step = 0.1
integrator = "dop853"
rtol = 1e-10
atol = 1e-10

[[body]]
name = "hub"
mass = {mh:?}
inertia = {ih:?}

[[body]]
name = "p1"
mass = {mp:?}
inertia = {ip:?}

[[hinge]]
name = "h1"
parent = "hub"
child = "p1"
a0 = {{ position = {a0:?} }}
a = {{ child_com = {com:?} }}
law = {{ type = "euler-potential", k_f = {k_f:?}, k_theta = {k_theta:?} }}
"#
    )
}

/// `foldsim modes` writes the table (six rigid, six free, six hub-fixed rows for one panel)
/// with the analytic frequency in it, and refuses a time outside the run.
#[test]
fn modes_command_writes_the_table() {
    let dir = common::tmp("linear", "cli");
    let scenario = dir.join("one-panel.toml");
    std::fs::write(&scenario, one_panel(10.0, 40.0, 1.5)).unwrap();
    let out = common::foldsim().args(["modes", "-q", "-o"]).arg(dir.join("m.csv")).arg(&scenario).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut reader = csv::Reader::from_path(dir.join("m.csv")).unwrap();
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    let kinds: Vec<&str> = rows.iter().map(|r| &r[0]).collect();
    assert_eq!(kinds.iter().filter(|k| **k == "rigid").count(), 6);
    assert_eq!(kinds.iter().filter(|k| **k == "free").count(), 6);
    assert_eq!(kinds.iter().filter(|k| **k == "hub_fixed").count(), 6);
    let expected = (10.0f64 * 41.5 / 60.0).sqrt();
    assert!(rows.iter().any(|r| (r[3].parse::<f64>().unwrap() / expected - 1.0).abs() < 1e-9));
    let bad = common::foldsim().args(["modes", "--at", "5"]).arg(&scenario).output().unwrap();
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("run.duration = 1 s"));
    // The page of a mode shape (the viewer's own test drives it in a browser, .ci/run), and
    // a mode the table does not have.
    let page = dir.join("mode.html");
    let view = common::foldsim()
        .args(["modes", "-q", "--mode", "free:6", "-o"])
        .arg(dir.join("m.csv"))
        .arg("--view")
        .arg(&page)
        .arg(&scenario)
        .output()
        .unwrap();
    assert!(view.status.success(), "{}", String::from_utf8_lossy(&view.stderr));
    assert!(std::fs::read_to_string(&page).unwrap().contains("free-free mode at"));
    let bad = common::foldsim()
        .args(["modes", "--view"])
        .arg(&page)
        .args(["--mode", "hub_fixed:9"])
        .arg(&scenario)
        .output()
        .unwrap();
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("6 hub_fixed modes"));
}

/// A free chain (hub and three panels, law 2, at its stress-free zero configuration): six
/// rigid-body modes at zero, their eigenvalues ω² within 1e-8 of the first flexible one's
/// (measured 2e-12: round-off of the largest, 4.8e3 s⁻², times 1e-16; in ω that is
/// √(2e-12) ≈ 1.5e-6, as any square root of round-off is), and the hub-fixed
/// modes' effective masses add up to the appendages' mass and inertia about the hub (to
/// 1e-10: every hub-fixed mode counted).
#[test]
fn free_chain_has_six_rigid_modes() {
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    // The tree alone (no loop hinge h32), at zero tree coordinates: an equilibrium.
    let cut = text.find("# The loop hinge").unwrap();
    let s = Scenario::from_toml(&text[..cut], "chain.toml").unwrap_or_else(|e| panic!("{e}"));
    let modes = modes_at_start(&s);
    let first_flexible = modes.free[6].eigenvalue;
    let rigid = modes.free[..6].iter().map(|m| m.eigenvalue.abs()).fold(0.0, f64::max);
    println!(
        "rigid modes' ω² up to {rigid:.2e} s⁻², first flexible {first_flexible:.4} s⁻²: {:.2e}",
        rigid / first_flexible
    );
    assert!(rigid < 1e-8 * first_flexible);
    assert!(modes.free[6..].iter().all(|m| m.eigenvalue >= first_flexible));
    let sums: [f64; 6] = std::array::from_fn(|a| modes.hub_fixed.iter().map(|m| m.effective[a]).sum());
    for (a, (sum, total)) in sums.iter().zip(&modes.appendage_total).enumerate() {
        let rel = (sum / total - 1.0).abs();
        assert!(rel < 1e-10, "axis {a}: {sum} vs {total} ({rel:e})");
    }
    println!("appendage mass and inertia about the hub {:?}; hub-fixed effective sums agree", modes.appendage_total);
}

/// The linear model's accelerations against central differences of the nonlinear right-hand
/// side in the same minimal coordinates (positions shifted, attitudes turned by
/// `q ⊗ (1, h e/2)`, rates shifted), at the three-panel case's initial state (turned, loaded,
/// not an equilibrium) with the bodies spinning. Bound 1e-7 relative to the largest entry
/// (the issue's; the differences' own error at h = 1e-6 is ~1e-9).
#[test]
fn linearisation_matches_differences() {
    for path in ["examples/paper-3panel.toml", "examples/flasher-small.toml"] {
        let s = common::scenario(path);
        let (d, mut y) = at_start(&s);
        let n = s.model.bodies.len();
        for i in 0..n {
            y[B * i + 10] += 0.2;
            y[B * i + 12] -= 0.1 * (i % 3) as f64;
        }
        d.accept(0.0, &y).unwrap();
        let lin = Linearization::at(&d, &y, Vec3::zeros()).unwrap();
        let (jx, jv) = (lin.jx(), lin.jv());
        let h = 1e-6;
        let (mut fp, mut fm) = (vec![0.0; y.len()], vec![0.0; y.len()]);
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for j in 0..n {
            for c in 0..12 {
                let shift = |sign: f64| {
                    let mut z = y.clone();
                    let o = B * j;
                    match c {
                        0..3 => z[o + c] += sign * h,
                        3..6 => {
                            let q = [z[o + 3], z[o + 4], z[o + 5], z[o + 6]];
                            let mut e = [0.0; 3];
                            e[c - 3] = sign * h / 2.0;
                            let r = [
                                q[0] - q[1] * e[0] - q[2] * e[1] - q[3] * e[2],
                                q[1] + q[0] * e[0] + q[2] * e[2] - q[3] * e[1],
                                q[2] + q[0] * e[1] - q[1] * e[2] + q[3] * e[0],
                                q[3] + q[0] * e[2] + q[1] * e[1] - q[2] * e[0],
                            ];
                            let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
                            for k in 0..4 {
                                z[o + 3 + k] = r[k] / norm;
                            }
                        }
                        _ => z[o + 7 + (c - 6)] += sign * h,
                    }
                    z
                };
                d.rhs(&shift(1.0), &mut fp);
                d.rhs(&shift(-1.0), &mut fm);
                for i in 0..n {
                    for r in 0..6 {
                        let fd = (fp[B * i + 7 + r] - fm[B * i + 7 + r]) / (2.0 * h);
                        let exact = if c < 6 { jx[(6 * i + r, 6 * j + c)] } else { jv[(6 * i + r, 6 * j + c - 6)] };
                        worst = worst.max((fd - exact).abs());
                        scale = scale.max(exact.abs());
                    }
                }
            }
        }
        println!("{path}: linearisation vs central differences {:.2e} of the largest entry {scale:.3e}", worst / scale);
        assert!(worst < 1e-7 * scale, "{path}: {worst:e} of {scale:e}");
    }
}

/// Eigenvalues of the state matrix A and the second-order problem (M, K) agree: for the
/// undamped chain (law 2) A's eigenvalues are ±iω with the (M, K) frequencies, to 1e-8 of the
/// largest (nalgebra's general eigenvalues of A against its symmetric solve).
#[test]
fn state_matrix_and_second_order_eigenvalues_agree() {
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    let cut = text.find("# The loop hinge").unwrap();
    let s = Scenario::from_toml(&text[..cut], "chain.toml").unwrap_or_else(|e| panic!("{e}"));
    let (d, y) = at_start(&s);
    let lin = Linearization::at(&d, &y, Vec3::zeros()).unwrap();
    let modes = modes_at_start(&s);
    let a = lin.state_matrix();
    let mut from_a: Vec<f64> = a.complex_eigenvalues().iter().filter(|l| l.im > 1e-6).map(|l| l.im).collect();
    from_a.sort_by(f64::total_cmp);
    let from_mk: Vec<f64> = modes.free.iter().filter(|m| !m.rigid).map(|m| m.omega).collect();
    assert_eq!(from_a.len(), from_mk.len());
    let top = from_mk.last().unwrap();
    let worst = from_a.iter().zip(&from_mk).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    println!("{} frequencies: A against (M, K) {:.2e} of the largest ({top:.4} rad/s)", from_mk.len(), worst / top);
    assert!(worst < 1e-8 * top);
}

/// `foldsim equilibrium` on the three-panel case with its loop (law 2, deflected at the
/// start): Newton converges quadratically to a force below 1e-10 N, and the `[initial]`
/// tables it writes, run as the scenario's initial state, stay at rest (every body slower
/// than 1e-9 m/s and rad/s over 10 s: an equilibrium indeed, checked by the nonlinear run);
/// its modes have the six rigid ones at zero (ω² below 1e-8 of the first flexible one's),
/// which a loaded state's do not.
#[test]
fn equilibrium_stays_at_rest_and_has_rigid_modes() {
    let dir = common::tmp("linear", "equilibrium");
    let out = dir.join("eq.toml");
    let run = common::foldsim()
        .args(["equilibrium", "-q", "-o"])
        .arg(&out)
        .arg(common::repo("examples/paper-3panel-euler.toml"))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    let cut = text.find("# Table 7").unwrap();
    let scenario = format!("{}\n{}", &text[..cut], std::fs::read_to_string(&out).unwrap())
        .replace("duration = 20.0", "duration = 10.0")
        .replace("output_step = 0.05", "output_step = 0.1");
    let s = Scenario::from_toml(&scenario, "eq.toml").unwrap_or_else(|e| panic!("{e}"));
    let (_, rows, _) = common::run(&s);
    let fastest = rows
        .iter()
        .flat_map(|o| o.body_v_in_n.iter().chain(o.body_omega_in_body.iter()).map(|v| v.norm()))
        .fold(0.0, f64::max);
    let modes = modes_at_start(&s);
    let rigid = modes.free[..6].iter().map(|m| m.eigenvalue.abs()).fold(0.0, f64::max);
    let loaded = modes_at_start(&common::scenario("examples/paper-3panel-euler.toml"));
    let loaded_rigid = loaded.free[..6].iter().map(|m| m.eigenvalue.abs()).fold(0.0, f64::max);
    println!(
        "from the equilibrium: fastest body {fastest:.2e} over 10 s; rigid ω² {:.2e} of the first flexible (at the loaded start {:.2e})",
        rigid / modes.free[6].eigenvalue,
        loaded_rigid / loaded.free[6].eigenvalue
    );
    assert!(fastest < 1e-9, "{fastest:e}");
    assert!(rigid < 1e-8 * modes.free[6].eigenvalue);
}

/// A deployed structure (the free chain at its stress-free zero configuration) started along
/// its first flexible mode with a small amplitude (1e-4 of the shape's mass-normalised size)
/// and run with the nonlinear model: its modal coordinate `η = φᵀ M δq` oscillates at the
/// mode's frequency (from the zero crossings over five periods: to 1e-4, the issue's bound;
/// the amplitude's nonlinear shift is ~1e-8) and the motion stays in the mode (what is left
/// of δq beyond `η φ` stays below 1e-3 of η's amplitude, in M's norm).
#[test]
fn a_mode_started_oscillates_at_its_frequency() {
    use foldsim::kinematics::hinge_kinematics;
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    let cut = text.find("# The loop hinge").unwrap();
    let chain = &text[..cut];
    let s = Scenario::from_toml(chain, "chain.toml").unwrap_or_else(|e| panic!("{e}"));
    let (d, y_eq) = at_start(&s);
    let modes = modes_at_start(&s);
    let mode = &modes.free[6];
    let omega = mode.omega;
    let n = s.model.bodies.len();
    // The state moved along the shape by ε: positions in N, attitudes by q ⊗ (1, δφ/2).
    let eps = 1e-4;
    let mut y = y_eq.clone();
    for i in 0..n {
        for c in 0..3 {
            y[B * i + c] += eps * mode.shape[6 * i + c];
        }
        let q = [y[B * i + 3], y[B * i + 4], y[B * i + 5], y[B * i + 6]];
        let e = [0, 1, 2].map(|c| eps * mode.shape[6 * i + 3 + c] / 2.0);
        let r = [
            q[0] - q[1] * e[0] - q[2] * e[1] - q[3] * e[2],
            q[1] + q[0] * e[0] + q[2] * e[2] - q[3] * e[1],
            q[2] + q[0] * e[1] - q[1] * e[2] + q[3] * e[0],
            q[3] + q[0] * e[2] + q[1] * e[1] - q[2] * e[0],
        ];
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        for k in 0..4 {
            y[B * i + 3 + k] = r[k] / norm;
        }
    }
    // As a scenario's initial tables: the hub's pose, every hinge's δ and angles.
    let hub = BodyMotion::from_state(&y, 0);
    let attitude = foldsim::math::Euler321::from_dcm(&hub.dcm_n_b.transpose());
    let mut tables = format!(
        "[initial.hub]\nposition = [{:?}, {:?}, {:?}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\n",
        hub.r_in_n.x, hub.r_in_n.y, hub.r_in_n.z, attitude.yaw, attitude.pitch, attitude.roll
    );
    let refs = d.theta_refs().clone();
    for (i, h) in s.model.hinges.iter().enumerate() {
        let k =
            hinge_kinematics(h, &BodyMotion::from_state(&y, h.parent), &BodyMotion::from_state(&y, h.child), &refs[i]);
        let (dl, t) = (k.state.delta_in_a0, k.state.theta);
        tables += &format!(
            "[initial.hinge.{}]\ndelta = [{:?}, {:?}, {:?}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\n",
            h.name, dl.x, dl.y, dl.z, t.yaw, t.pitch, t.roll
        );
    }
    let period = 2.0 * std::f64::consts::PI / omega;
    let run_text = format!("{chain}\n{tables}")
        .replace("duration = 20.0", &format!("duration = {:?}", 5.2 * period))
        .replace("output_step = 0.05", &format!("output_step = {:?}", period / 400.0));
    let started = Scenario::from_toml(&run_text, "mode.toml").unwrap_or_else(|e| panic!("{e}"));
    let (_, rows, _) = common::run(&started);
    // δq per row from the equilibrium, and its modal coordinate.
    let m = Linearization::at(&d, &y_eq, Vec3::zeros()).unwrap().mass_matrix();
    let eq: Vec<BodyMotion> = (0..n).map(|i| BodyMotion::from_state(&y_eq, i)).collect();
    let mut eta = Vec::new();
    let mut rest = 0.0f64;
    for o in &rows {
        let mut dq = nalgebra::DVector::zeros(6 * n);
        for i in 0..n {
            let dr = o.body_r_in_n[i] - eq[i].r_in_n;
            // δφ from [B_eq N][N B]: its antisymmetric part, body components.
            let rel = eq[i].dcm_n_b.transpose() * foldsim::math::dcm_from_quat(&o.body_quat[i]);
            let dphi = Vec3::new(rel[(2, 1)] - rel[(1, 2)], rel[(0, 2)] - rel[(2, 0)], rel[(1, 0)] - rel[(0, 1)]) * 0.5;
            for c in 0..3 {
                dq[6 * i + c] = dr[c];
                dq[6 * i + 3 + c] = dphi[c];
            }
        }
        let e = (mode.shape.transpose() * &m * &dq)[(0, 0)];
        let left = &dq - &mode.shape * e;
        rest = rest.max((left.transpose() * &m * &left)[(0, 0)].sqrt());
        eta.push((o.t, e));
    }
    let amplitude = eta.iter().map(|(_, e)| e.abs()).fold(0.0, f64::max);
    let crossings: Vec<f64> = eta
        .windows(2)
        .filter(|w| w[0].1 > 0.0 && w[1].1 <= 0.0 || w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1))
        .collect();
    let measured = std::f64::consts::PI * (crossings.len() - 1) as f64 / (crossings.last().unwrap() - crossings[0]);
    println!(
        "mode 1 at {omega:.9} rad/s: nonlinear run {measured:.9} rad/s ({:.2e}) over {} half periods; amplitude {amplitude:.3e}, other modes up to {:.2e} of it",
        measured / omega - 1.0,
        crossings.len() - 1,
        rest / amplitude
    );
    assert!((amplitude / eps - 1.0).abs() < 1e-3);
    assert!((measured / omega - 1.0).abs() < 1e-4);
    assert!(rest < 1e-3 * amplitude);
}

/// The deployed flasher of `text` (its `[initial]` tables cut: every tree coordinate zero,
/// the stress-free design, an equilibrium).
fn deployed(path: &str) -> Scenario {
    let text = std::fs::read_to_string(common::repo(path)).unwrap();
    let cut = text.find("[initial.").unwrap();
    Scenario::from_toml(&text[..cut], "deployed.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The deployed 67-panel flasher (`examples/flasher-small.toml`) linearised at its design
/// state, with its bodies' positions and attitudes there (for `Modes`).
fn deployed_flasher_small() -> (Linearization, Vec<Vec3>, Vec<Mat3>) {
    let s = deployed("examples/flasher-small.toml");
    let (d, y) = at_start(&s);
    let lin = Linearization::at(&d, &y, Vec3::zeros()).unwrap();
    let motions: Vec<BodyMotion> = (0..s.model.bodies.len()).map(|i| BodyMotion::from_state(&y, i)).collect();
    let p = motions.iter().map(|m| m.r_in_n).collect();
    let c = motions.iter().map(|m| m.dcm_n_b).collect();
    (lin, p, c)
}

/// The large-structure path (shift-invert Lanczos on the block-sparse K and M) gives the dense
/// solver's modes on the deployed 67-panel flasher: the 20 lowest flexible frequencies free-free
/// and hub-fixed to the dense solver's own round-off (ε λ_max over ω², 2e-8 here: the stiff
/// off-axis directions set λ_max), each sparse ω² within 1e-3 by its first-order residual bound,
/// the hub-fixed effective masses (summed over repeated frequencies: a repeated mode's shapes
/// are any basis of its eigenspace) to 1e-6 of the appendages' totals (eigenvectors of close
/// pairs carry both solvers' round-off over their gap).
#[test]
fn sparse_lanczos_modes_equal_the_dense_ones() {
    let (lin, p, c) = deployed_flasher_small();
    let dense = Modes::of(&lin, &p, &c).unwrap();
    let sparse = Modes::lowest(&lin, &p, &c, 20).unwrap();
    let rel = |a: &[foldsim::linear::modes::Mode], b: &[foldsim::linear::modes::Mode]| {
        a.iter().zip(b).map(|(x, y)| (x.omega / y.omega - 1.0).abs()).fold(0.0, f64::max)
    };
    let free = rel(&sparse.free[6..26], &dense.free[6..26]);
    let fixed = rel(&sparse.hub_fixed[..20], &dense.hub_fixed[..20]);
    // Effective masses per cluster of equal frequencies (1e-6 apart): a repeated mode's
    // shapes are any basis of its eigenspace, so only their sum is defined.
    let mut effective = 0.0f64;
    let mut start = 0;
    while start < 20 {
        let mut end = start + 1;
        while dense.hub_fixed[end].omega / dense.hub_fixed[start].omega - 1.0 < 1e-6 {
            end += 1;
        }
        if end > 20 {
            break; // the 20th mode's partner is beyond the 20 asked for
        }
        for a in 0..6 {
            let sum = |m: &[foldsim::linear::modes::Mode]| m[start..end].iter().map(|x| x.effective[a]).sum::<f64>();
            effective =
                effective.max((sum(&sparse.hub_fixed) - sum(&dense.hub_fixed)).abs() / dense.appendage_total[a]);
        }
        start = end;
    }
    // The dense solver's own error in ω² is about ε λ_max (Golub & Van Loan §8.1: backward
    // stable), so the two can agree only to that over the lowest ω², halved for ω.
    let largest = dense.free.last().unwrap().eigenvalue;
    let dense_error = f64::EPSILON * largest / dense.free[6].eigenvalue;
    // The sparse pairs' own error bound, independent of either solver: for φ M-normalised,
    // |λ − λ_true| ≤ ‖K φ − λ M φ‖ in M⁻¹'s norm (Parlett, *The Symmetric Eigenvalue
    // Problem*, Thm 4-5-1 applied to M^{-1/2} K M^{-1/2}): a first-order bound (the error of a
    // Rayleigh quotient is of the order of its square over the gap), 1e-3 of ω² at most: the
    // round-off of K φ with K's stiff directions (λ_max 2e7 against ω² 0.2) keeps it near 1e-4.
    let (k, _) = lin.stiffness_and_damping();
    let k = (&k + k.transpose()) * 0.5;
    let m = lin.mass_matrix();
    let m_inv = m.clone().try_inverse().unwrap();
    let bound = sparse.free[6..26]
        .iter()
        .map(|md| {
            let r = &k * &md.shape - &m * &md.shape * md.eigenvalue;
            (r.transpose() * &m_inv * &r)[(0, 0)].sqrt() / md.eigenvalue
        })
        .fold(0.0, f64::max);
    println!(
        "Lanczos against dense, 20 lowest: free-free {free:.2e}, hub fixed {fixed:.2e} (dense's own error up to {dense_error:.1e}: λ_max {largest:.3e} 1/s²); sparse residual bound on ω² {bound:.2e}; effective masses {effective:.2e}; first flexible {:.5} Hz",
        dense.free[6].frequency_hz()
    );
    assert!(bound < 1e-3, "{bound:e}");
    assert!(free < dense_error && fixed < dense_error, "{free:e} {fixed:e}");
    assert!(effective < 1e-6, "{effective:e}");
    assert!(sparse.free[..6].iter().all(|m| m.rigid) && dense.free[..6].iter().all(|m| m.rigid));
}

/// Asked for fewer modes than a Lanczos block holds (1 to 5: one Ritz vector at a time
/// projected out of the rigid modes), the large-structure path gives the dense solver's
/// lowest flexible modes free-free and hub-fixed, to the dense solver's own round-off as
/// above. It crashed for these counts (nalgebra 0.35's product of a strided transposed view
/// with one column wrote out of bounds: dimforge/nalgebra#1616), found by
/// `tests/fuzz_linear.rs` (`foldsim modes examples/flasher-small.toml --count 1`).
#[test]
fn a_few_lanczos_modes_equal_the_dense_ones() {
    let (lin, p, c) = deployed_flasher_small();
    let dense = Modes::of(&lin, &p, &c).unwrap();
    let dense_error = f64::EPSILON * dense.free.last().unwrap().eigenvalue / dense.free[6].eigenvalue;
    for count in 1..=5 {
        let sparse = Modes::lowest(&lin, &p, &c, count).unwrap();
        let flexible: Vec<_> = sparse.free.iter().filter(|m| !m.rigid).collect();
        assert_eq!(flexible.len(), count, "free-free flexible modes for count {count}");
        for (m, want) in flexible.iter().zip(&dense.free[6..]) {
            assert!((m.omega / want.omega - 1.0).abs() < dense_error, "count {count}: {} vs {}", m.omega, want.omega);
        }
        assert!(sparse.hub_fixed.len() >= count, "hub-fixed modes for count {count}");
        for (m, want) in sparse.hub_fixed.iter().zip(&dense.hub_fixed).take(count) {
            assert!((m.omega / want.omega - 1.0).abs() < dense_error, "count {count}: {} vs {}", m.omega, want.omega);
        }
    }
}

/// A panel hinged radially to a spinning hub (held: its mass and inertia 1e9), folding in the
/// spin plane (lead-lag, about the hinge's z parallel to the spin axis). From the unstretched
/// design, `Equilibrium::spinning` finds the relative equilibrium (the hinge stretched by the
/// centrifugal tension, `k_f δ = m Ω² (R + δ + l)`: δ against that closed form to 1e-6, the
/// forces left below 1e-6 N, near the round-off of a 1e9 N/m spring, 1e-7 N);
/// linearised there in the frame turning with the spin, the state matrix's frequency
/// against the closed form `ω² = (k + m Ω² R' l)/(I_c + m l²)` (R' = R + δ the hinge's
/// radius; from `(I_c + m l²) ψ̈ = −k ψ − l T ψ + m Ω² l² ψ`, T the tension), at three spin
/// rates. Bound 2e-7 relative: the closed form is for a pin, the hinge a 1e9 N/m spring (its
/// compliance shifts ω by ~mΩ²/k_f, 1e-8 here, and 10× that at 1e8 N/m, as measured), the
/// held hub's inertia (1e-9 of it), and the nonsymmetric eigen-solver's round-off on a
/// matrix whose stiff directions reach 3e8 s⁻² (~1e-7 over ω², 10× less at 1e8 N/m).
#[test]
fn spinning_radial_panel_is_centrifugally_stiffened() {
    let (k, m, ic, r, l, k_f) = (2.0, 3.0, 0.5, 1.5, 0.8, 1e9);
    let mut worst = 0.0f64;
    for spin in [0.0, 0.7, 2.0] {
        let text = radial_panel(k, m, ic, r, l, k_f);
        let s = Scenario::from_toml(&text, "spinning.toml").unwrap_or_else(|e| panic!("{e}"));
        let (d, y) = at_start(&s);
        let omega = Vec3::new(0.0, 0.0, spin);
        let found = Equilibrium::spinning(&d, &y, omega, 1e-6, 20).unwrap();
        let delta = m * spin * spin * (r + l) / (k_f - m * spin * spin);
        let stretch = found.hinges[0].0;
        let delta_error = if spin > 0.0 { (stretch - Vec3::new(delta, 0.0, 0.0)).norm() / delta } else { 0.0 };
        d.accept(0.0, &found.y).unwrap();
        let lin = Linearization::at(&d, &found.y, omega).unwrap();
        let expected = ((k + m * spin * spin * (r + delta) * l) / (ic + m * l * l)).sqrt();
        let eigen = lin.state_matrix().complex_eigenvalues();
        let nearest = eigen
            .iter()
            .map(|e| (e.im.abs() / expected - 1.0).abs().max(e.re.abs() / expected))
            .fold(f64::INFINITY, f64::min);
        println!(
            "Ω = {spin} rad/s: stretch {:.6e} m ({delta_error:.1e} from the closed form, {} Newton iterations); lead-lag ω = {expected:.9} rad/s (unspun {:.9}); state matrix off by {nearest:.2e}; residual {:.1e}",
            stretch.x,
            found.iterations,
            (k / (ic + m * l * l)).sqrt(),
            lin.residual
        );
        if spin > 0.0 {
            assert!(delta_error < 1e-6, "{delta_error:e}");
        }
        worst = worst.max(nearest);
    }
    assert!(worst < 2e-7, "{worst:e}");
}

/// A hub held (mass and inertia 1e9) with one panel hinged radially at `r` (m), its centre of
/// mass `l` beyond the hinge, folding about z (stiffness `k`), `k_f` the hinge's stretch
/// stiffness, the panel's mass `m` and inertia `ic` about each axis.
fn radial_panel(k: f64, m: f64, ic: f64, r: f64, l: f64, k_f: f64) -> String {
    hub_and_panel((1e9, [1e9; 3]), (m, [ic; 3]), ([r, 0.0, 0.0], [l, 0.0, 0.0]), k_f, [1e4, 1e4, k])
}

/// `foldsim modes --spin-rate 2` on the radial panel from its unstretched design: the
/// relative equilibrium, then the lead-lag mode in the turning frame at the closed form's
/// frequency (as `spinning_radial_panel_is_centrifugally_stiffened`, bound 2e-7), undamped.
#[test]
fn modes_command_takes_a_spin_rate() {
    let (k, m, ic, r, l, k_f, spin) = (2.0, 3.0, 0.5, 1.5, 0.8, 1e9, 2.0);
    let dir = common::tmp("linear", "spin");
    let scenario = dir.join("radial.toml");
    std::fs::write(&scenario, radial_panel(k, m, ic, r, l, k_f)).unwrap();
    let out = dir.join("spin.csv");
    let run =
        common::foldsim().args(["modes", "-q", "--spin-rate", "2", "-o"]).arg(&out).arg(&scenario).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let delta = m * spin * spin * (r + l) / (k_f - m * spin * spin);
    let expected = ((k + m * spin * spin * (r + delta) * l) / (ic + m * l * l)).sqrt();
    let mut reader = csv::Reader::from_path(&out).unwrap();
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    let nearest =
        rows.iter().map(|r| (r[3].parse::<f64>().unwrap() / expected - 1.0).abs()).fold(f64::INFINITY, f64::min);
    assert!(rows.iter().all(|r| &r[0] == "spinning"));
    assert!(nearest < 2e-7, "{nearest:e}");
}

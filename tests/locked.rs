//! Locked directions (hinge-law issue): a hub with two panels, each hinge locked in five
//! directions with a torsion spring in the sixth, is the 1-DOF hinged-panel system whose
//! linearised coupled frequencies are known in closed form. Checked:
//! - the locked motion stays below 1e-9 m or rad (the issue's bound);
//! - both fold-mode frequencies measured from the fold angle match the analytic ones to 5e-3
//!   (the issue's bound; the 5° initial fold shifts a frequency by ~(5°)² ~ 1e-3 relative);
//! - energy and momentum are conserved to 1e-10 relative (absolute for P and H, which are 0).

mod aba;
mod common;
use common::*;
use foldsim::generate::{Params, zfold};
use foldsim::scenario::Scenario;
use nalgebra::{Matrix4, SymmetricEigen};
use std::f64::consts::PI;

/// A hinge's five directions other than its fold (rz).
const OFF_AXIS: &[&str] = &["x", "y", "z", "rx", "ry"];

/// Analytic fold-mode frequencies, rad/s: planar Lagrangian linearised about the straight
/// configuration, coordinates (hub y, hub yaw ψ, fold angles φ1, φ2); hinges at ±d from the
/// hub CoM, panel CoMs a further l out.
fn analytic(m_hub: f64, i_hub: f64, m: f64, i_panel: f64, d: f64, l: f64, k: f64) -> [f64; 2] {
    let r = d + l; // panel CoM distance from the hub CoM
    // Panel 1 CoM velocity (y): Ẏ + r ψ̇ + l φ̇1; panel 2: Ẏ − r ψ̇ − l φ̇2.
    let mass = Matrix4::new(
        m_hub + 2.0 * m,
        0.0,
        m * l,
        -m * l,
        0.0,
        i_hub + 2.0 * m * r * r + 2.0 * i_panel,
        m * r * l + i_panel,
        m * r * l + i_panel,
        m * l,
        m * r * l + i_panel,
        m * l * l + i_panel,
        0.0,
        -m * l,
        m * r * l + i_panel,
        0.0,
        m * l * l + i_panel,
    );
    let stiffness = Matrix4::from_diagonal(&nalgebra::Vector4::new(0.0, 0.0, k, k));
    // K v = ω² M v → symmetric form L⁻¹ K L⁻ᵀ with M = L Lᵀ.
    let l_inv = mass.cholesky().expect("mass matrix SPD").l().try_inverse().unwrap();
    let eig = SymmetricEigen::new(l_inv * stiffness * l_inv.transpose());
    let mut w2: Vec<f64> = eig.eigenvalues.iter().copied().filter(|v| *v > 1e-9).collect();
    w2.sort_by(f64::total_cmp);
    assert_eq!(w2.len(), 2);
    [w2[0].sqrt(), w2[1].sqrt()]
}

/// Frequency of the largest Hann-windowed spectral peak of `x(t)` within [lo, hi], rad/s,
/// refined by golden-section search on the DFT magnitude.
fn peak(t: &[f64], x: &[f64], lo: f64, hi: f64) -> f64 {
    let n = t.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let span = t[n - 1] - t[0];
    let mag = |w: f64| {
        let (mut re, mut im) = (0.0, 0.0);
        for (ti, xi) in t.iter().zip(x) {
            let hann = 0.5 - 0.5 * (2.0 * PI * (ti - t[0]) / span).cos();
            re += hann * (xi - mean) * (w * ti).cos();
            im += hann * (xi - mean) * (w * ti).sin();
        }
        re.hypot(im)
    };
    // Coarse scan, then golden section around the best sample.
    let samples = 400;
    let best = (0..=samples).map(|i| lo + (hi - lo) * i as f64 / samples as f64).fold((lo, 0.0), |acc, w| {
        let m = mag(w);
        if m > acc.1 { (w, m) } else { acc }
    });
    let step = (hi - lo) / samples as f64;
    let (mut a, mut b) = (best.0 - step, best.0 + step);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if mag(c) > mag(d) { b = d } else { a = c }
    }
    0.5 * (a + b)
}

#[test]
fn one_dof_hinged_panels_match_linear_theory() {
    let s = scenario("examples/hinged-panels-1dof.toml");
    let (table, obs, report) = run(&s);

    // Locked directions stay put.
    let mut locked = 0.0f64;
    for h in ["h1", "h2"] {
        for c in ["delta_x", "delta_y", "delta_z", "pitch", "roll"] {
            let i = table.col(&format!("{h}_{c}"));
            locked = locked.max(table.rows.iter().map(|r| r[i].abs()).fold(0.0, f64::max));
        }
    }
    eprintln!("largest locked-direction motion {locked:e}");
    assert!(locked < 1e-9, "locked directions moved {locked:e}");

    // Conservation.
    let d = &report.drift;
    let e_rel = d.energy / obs[0].energy();
    eprintln!("energy {e_rel:e} relative, |ΔP| {:e}, |ΔH| {:e}", d.momentum, d.angular_momentum);
    assert!(e_rel <= 1e-10, "energy drift {e_rel:e}");
    assert!(d.momentum <= 1e-10 && d.angular_momentum <= 1e-10);

    // Frequencies.
    let w = analytic(750.0, 600.0, 100.0, 50.0, 0.5, 1.5, 100.0);
    let t: Vec<f64> = table.rows.iter().map(|r| r[0]).collect();
    let yaw = table.col("h1_yaw");
    let fold: Vec<f64> = table.rows.iter().map(|r| r[yaw]).collect();
    let split = 0.5 * (w[0] + w[1]);
    let measured = [peak(&t, &fold, 0.8 * w[0], split), peak(&t, &fold, split, 1.2 * w[1])];
    for (m, a) in measured.iter().zip(&w) {
        let rel = (m - a).abs() / a;
        eprintln!("fold mode: measured {m:.6} rad/s, analytic {a:.6} rad/s, relative {rel:e}");
        assert!(rel <= 5e-3, "measured {m} vs analytic {a}");
    }
}

/// A long chain of 1-DOF hinges (32 panels z-folded, every hinge locked in five directions,
/// 160 locks whose multiplier system couples neighbours): it unfolds with the locked
/// directions held below 1e-9, and energy and momentum conserved (C = 0) to 1e-9 relative
/// (bounds as for the two-panel case, relaxed ten times for the longer, faster motion).
/// The largest departure over the output rows of any hinge's δ x, y, z, pitch or roll from
/// its first row (m or rad): the five directions these tests lock.
fn locked_motion(table: &Table, s: &foldsim::scenario::Scenario) -> f64 {
    let mut locked = 0.0f64;
    for h in &s.model.hinges {
        for c in ["delta_x", "delta_y", "delta_z", "pitch", "roll"] {
            let i = table.col(&format!("{}_{c}", h.name));
            let first = table.rows[0][i];
            locked = locked.max(table.rows.iter().map(|r| (r[i] - first).abs()).fold(0.0, f64::max));
        }
    }
    locked
}

#[test]
fn long_locked_chain_holds_its_locks() {
    let p = Params { duration: 2.0, tolerance: 1e-11, ..Params::default() };
    let law = "law = { type = \"directional\", angles = \"euler\", x = \"locked\", y = \"locked\", z = \"locked\", rx = \"locked\", ry = \"locked\", rz = { k = 1.0 } }";
    let text: String = zfold(32, &p)
        .lines()
        .map(|l| if l.starts_with("law = ") { law.to_string() } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let s = foldsim::scenario::Scenario::from_toml(&text, "locked chain").unwrap();
    let (table, obs, report) = run(&s);
    let locked = locked_motion(&table, &s);
    let fold = table.col("h32_yaw");
    let moved = table.rows.iter().map(|r| (r[fold] - table.rows[0][fold]).abs()).fold(0.0, f64::max);
    let d = &report.drift;
    let e_rel = d.energy / obs[0].energy();
    eprintln!(
        "locked chain: locked motion {locked:e}, fold moved {moved:.3} rad, energy {e_rel:e}, |ΔP| {:e}, |ΔH| {:e}",
        d.momentum, d.angular_momentum
    );
    assert!(moved > 0.1, "the chain must actually unfold");
    assert!(locked < 1e-9, "locked directions moved {locked:e}");
    assert!(e_rel <= 1e-9, "energy drift {e_rel:e}");
    assert!(
        d.momentum <= 1e-9 * d.momentum_scale.max(1.0)
            && d.angular_momentum <= 1e-9 * d.angular_momentum_scale.max(1.0)
    );
}

/// At a loose tolerance the locked coordinates drift by up to the local error within a step,
/// and the projection that brings them back moves positions at fixed velocities, changing
/// the angular momentum. The z-fold tape-spring example with its five off-axis directions
/// locked, at rtol = atol = 1e-8 (large steps): every output row holds the locks within the
/// issue's 1e-9 (rows are projected too; unprojected, the dense output's rows were off by
/// 1.5e-8 m), and |ΔH| stays within 1e-10 of its scale (the momenta are restored after each
/// projection; without that 7e-8, with it but unprojected rows 3.5e-10, now 1e-11; P is
/// conserved to round-off either way).
#[test]
fn locks_hold_at_loose_tolerance() {
    let s = example_variant(
        "zfold-tape-latch.toml",
        &[(OFF_AXIS, "\"locked\""), (&["duration"], "10.0"), (&["rtol", "atol"], "1e-8")],
    );
    let (table, _, report) = run(&s);
    let locked = locked_motion(&table, &s);
    let d = &report.drift;
    let (p, h) = (d.momentum / d.momentum_scale, d.angular_momentum / d.angular_momentum_scale);
    eprintln!(
        "locked z-fold at rtol 1e-8: locked motion {locked:e} (reported {:e} m, {:e} rad), |ΔP| {p:e}, |ΔH| {h:e} of their scales",
        d.locked_translation, d.locked_rotation
    );
    assert_eq!(d.locks, 20);
    assert!(locked < 1e-9, "locked directions moved {locked:e}");
    assert!(d.locked_translation.max(d.locked_rotation) < 1e-9);
    assert!(p <= 1e-10 && h <= 1e-10, "momenta moved: P {p:e}, H {h:e}");
}

/// The locks' dynamics against an independent formulation: the articulated-body algorithm in
/// reduced coordinates (`tests/aba`: a floating hub and two revolute panels, world-frame
/// spatial algebra, no constraint solve) at a moving state of the 1-DOF example — hub
/// spinning and drifting, both panels folding. The hub's accelerations and the fold
/// accelerations agree to 1e-12 of the hub's acceleration (measured 6.9e-18 and 1.3e-17:
/// both are direct solves; halving the translational locks' velocity-product term γ puts
/// the hub off by 6e-2 of it).
#[test]
fn locks_match_the_articulated_body_algorithm() {
    let s = aba::example(true);
    let x = aba::moving_state(&s);
    let (_, hub_diff, scale, yaw_diff) = aba::compare(&s, &x);
    eprintln!("locks vs articulated body: hub {hub_diff:e} of {scale:e}, folds {yaw_diff:e}");
    assert!(hub_diff <= 1e-12 * scale && yaw_diff <= 1e-12 * scale, "hub {hub_diff:e}, folds {yaw_diff:e}");
}

/// The implicit path holds loaded locks as the explicit one does: the 1-DOF example (five
/// locked directions per hinge, loaded by the folding panels) and the z-fold example with
/// its five off-axis directions locked (tape springs, hysteresis, latches), each run with
/// SDIRK4 and with DOP853 at a tighter tolerance. Their hinge angles agree to the implicit
/// run's accuracy (measured 2e-8 and 5e-8 rad; bound 1e-6 rad). The Newton matrix only
/// steers the iteration (without the lock rows SDIRK4 still agrees, in 3 % more steps; the
/// rows themselves are checked against the dense matrix in `sparse.rs`); what this checks
/// is the implicit path's whole run with loaded locks: its right-hand side, projections and
/// momentum restoration, events and latches.
#[test]
fn implicit_and_explicit_paths_agree_with_locks() {
    for (file, duration) in [("hinged-panels-1dof.toml", "60.0"), ("zfold-tape-latch.toml", "8.0")] {
        let variant = |integrator: &str, tol: &str| {
            let integrator = format!("\"{integrator}\"");
            example_variant(
                file,
                &[
                    (OFF_AXIS, "\"locked\""),
                    (&["duration"], duration),
                    (&["integrator"], &integrator),
                    (&["rtol", "atol"], tol),
                ],
            )
        };
        let (explicit, _, _) = run(&variant("dop853", "1e-11"));
        // SDIRK4, and auto (the default), at the same tolerance.
        for method in ["sdirk4", "auto"] {
            let (implicit, _, ri) = run(&variant(method, "1e-9"));
            let angles: Vec<String> =
                implicit.columns.iter().filter(|c| c.ends_with("_yaw") && c.starts_with('h')).cloned().collect();
            let mut worst = 0.0f64;
            for c in &angles {
                let (a, b) = (implicit.col(c), explicit.col(c));
                for (ra, rb) in implicit.rows.iter().zip(&explicit.rows) {
                    worst = worst.max((ra[a] - rb[b]).abs());
                }
            }
            eprintln!(
                "{file}: {method} ({} steps, {} method spans) against DOP853, hinge yaw: {worst:e} rad",
                ri.steps_accepted,
                ri.methods.len()
            );
            assert!(!angles.is_empty() && implicit.rows.len() == explicit.rows.len());
            assert!(worst <= 1e-6, "{file} {method}: {worst:e} rad");
        }
    }
}

/// A lock is solved for only once it carries load (`Dynamics::disengage_locks`):
/// - the z-fold example with its out-of-plane directions (z, rx, ry) locked deploys in its
///   plane, so those locks carry nothing: no evaluation solves for them, and the run is the
///   run with those directions free, row for row and bit for bit, in as many evaluations;
/// - the 1-DOF example's locks: x and y carry the folding panels' loads from the first step
///   (engaged at t = 0, the step retaken), z, rx and ry none (the motion is planar). Its
///   physics with the locks is checked in `one_dof_hinged_panels_match_linear_theory`.
///
/// Fails if idle locks are solved for (evaluations with rows), if a loaded lock is not
/// engaged, or if the free directions differ from idle locked ones in any digit.
#[test]
fn locks_engage_only_where_loaded() {
    let planar =
        |value: &str| example_variant("zfold-tape-latch.toml", &[(&["z", "rx", "ry"], value), (&["duration"], "3.0")]);
    let (locked, _, rl) = run(&planar("\"locked\""));
    let (free, _, rf) = run(&planar("\"free\""));
    eprintln!(
        "planar z-fold: {} evaluations locked ({} solving for locks), {} free; locks engaged {:?}",
        rl.rhs_evaluations, rl.constrained_evaluations, rf.rhs_evaluations, rl.lock_engagements
    );
    assert_eq!(rl.drift.locks, 12);
    assert!(rl.lock_engagements.is_empty() && rl.constrained_evaluations == 0, "idle locks were solved for");
    assert_eq!(rl.rhs_evaluations, rf.rhs_evaluations);
    assert_eq!(locked.rows, free.rows, "idle locks changed the run");

    let s = example_variant("hinged-panels-1dof.toml", &[(&["duration"], "20.0")]);
    let (_, _, r) = run(&s);
    let engaged: Vec<(String, usize, f64)> =
        r.lock_engagements.iter().map(|(l, t)| (s.model.hinges[l.hinge].name.clone(), l.direction, *t)).collect();
    eprintln!(
        "1-DOF: locks engaged {engaged:?}; {} of {} evaluations solving",
        r.constrained_evaluations, r.rhs_evaluations
    );
    let expected: Vec<(String, usize, f64)> =
        [("h1", 0), ("h1", 1), ("h2", 0), ("h2", 1)].iter().map(|(h, d)| (h.to_string(), *d, 0.0)).collect();
    assert_eq!(engaged, expected, "x and y of both hinges, from the start");
    assert!(r.constrained_evaluations + 100 > r.rhs_evaluations, "engaged locks are solved for from then on");
}

/// A lock that takes load part-way through a run engages then, and the run follows the one
/// that solves for every lock from the start: the z-fold example with z, rx, ry locked and
/// the hub given a 1e-6 rad/s roll, so the deployment leaves its plane slowly and the
/// out-of-plane locks take load as it does. Every lock engages after the start, and the
/// hinge angles agree with the always-engaged run to 1e-9 rad (measured 5e-11: before
/// engaging a lock has moved less than 1e-11; the rest is the two runs' different steps at
/// rtol 1e-10); both hold the locks to 1e-9 m or rad.
#[test]
fn locks_engage_part_way_through_a_run() {
    let mut s = example_variant("zfold-tape-latch.toml", &[(&["z", "rx", "ry"], "\"locked\""), (&["duration"], "8.0")]);
    s.initial.hub_omega_in_hub[0] = 1e-6;
    let (lazy, _, rl) = run(&s);
    s.settings.engage_locks_at_start = true;
    let (eager, _, re) = run(&s);
    let first = rl.lock_engagements.first().map(|e| e.1).unwrap_or(f64::NAN);
    let mut worst = 0.0f64;
    for c in lazy.columns.iter().filter(|c| c.starts_with('h') && (c.ends_with("_yaw") || c.ends_with("_pitch"))) {
        let (a, b) = (lazy.col(c), eager.col(c));
        for (ra, rb) in lazy.rows.iter().zip(&eager.rows) {
            worst = worst.max((ra[a] - rb[b]).abs());
        }
    }
    eprintln!(
        "part-way: {} of {} locks engaged, first at t = {first} s; {} of {} evaluations solving (eager: {} of {}); angles differ by {worst:e} rad; held within {:e} / {:e}",
        rl.lock_engagements.len(),
        rl.drift.locks,
        rl.constrained_evaluations,
        rl.rhs_evaluations,
        re.constrained_evaluations,
        re.rhs_evaluations,
        rl.drift.locked_translation,
        rl.drift.locked_rotation,
    );
    assert!(first > 0.0, "the locks take load after the start: first engaged at {first}");
    assert!(worst <= 1e-9, "lazy and eager locks differ by {worst:e} rad");
    for r in [&rl, &re] {
        assert!(r.drift.locked_translation.max(r.drift.locked_rotation) < 1e-9);
    }
}

/// The long locked chain of the reliability review: 64 panels of 10 kg 1 m apart, five
/// directions locked per hinge and a 20 N·m/rad torsion spring in the sixth, released from a
/// z-fold of +45°, −90°, +90°, …, for 10 s. Fixed-step RK4's largest hinge-angle error
/// against DOP853 at 1e-14 stayed at 2e-6–7e-6 rad for every step from 5e-4 s down: the
/// round-off of its many state updates (~ε |y| each; 80,000 steps), which this chain
/// amplifies enormously (a 1.7e-15 rad change of one initial angle moves the angles at
/// t = 9 s by 1.1e-7 rad). RK4 now sums its state with compensation, and its error falls
/// at fourth order (1e-3 s: 2.2e-6; 5e-4 s: 9.8e-8) to that floor: 3.9e-8 and 4.4e-8 at
/// 2.5e-4 and 1.25e-4 s. Bound 1e-7: the reference's own uncertainty (that sensitivity to
/// one round-off of one angle), 20× below what the uncompensated sum gave.
#[test]
fn rk4_converges_on_a_long_locked_chain() {
    let chain = |integrator: &str| {
        let p = Params { panel_mass: 10.0, duration: 10.0, output_step: 0.1, ..Params::default() };
        let law = "law = { type = \"directional\", angles = \"euler\", x = \"locked\", y = \"locked\", z = \"locked\", rx = \"locked\", ry = \"locked\", rz = { k = 20.0 } }";
        let mut hinge = 0;
        let text: Vec<String> = zfold(64, &p)
            .lines()
            .map(|l| {
                if l.starts_with("law = ") {
                    law.to_string()
                } else if let Some(k) = l.strip_prefix("[initial.hinge.h") {
                    hinge = k.trim_end_matches(']').parse().unwrap();
                    l.to_string()
                } else if l.starts_with("yaw_deg = ") && hinge > 0 {
                    format!(
                        "yaw_deg = {}",
                        if hinge == 1 {
                            45.0
                        } else if hinge % 2 == 0 {
                            -90.0
                        } else {
                            90.0
                        }
                    )
                } else if l.starts_with("integrator = ") {
                    integrator.to_string()
                } else if l.starts_with("rtol = ") || l.starts_with("atol = ") {
                    String::new()
                } else {
                    l.to_string()
                }
            })
            .collect();
        let s = Scenario::from_toml(&text.join("\n"), "locked chain").unwrap_or_else(|e| panic!("{e}"));
        let mut angles = Vec::new();
        let mut sink = |o: &foldsim::observe::Observation| -> Result<(), String> {
            angles.push(o.hinge_theta.iter().map(|t| t.yaw).collect::<Vec<f64>>());
            Ok(())
        };
        foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None)
            .unwrap_or_else(|e| panic!("{e}"));
        angles
    };
    let reference = chain("integrator = \"dop853\"\nrtol = 1e-14\natol = 1e-14");
    for step in ["2.5e-4", "1.25e-4"] {
        let rk4 = chain(&format!("integrator = \"rk4\"\nstep = {step}"));
        let worst = reference
            .iter()
            .zip(&rk4)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
            .fold(0.0, f64::max);
        eprintln!("RK4 step {step} s: largest hinge-angle error {worst:e} rad");
        assert!(worst < 1e-7, "RK4 at {step} s: {worst:e} rad");
    }
}

/// The loads a locked hinge carries are in its `_F_`/`_M_` columns: a hub spinning at ω with a
/// panel on a hinge locked in all six directions turns as one rigid body about the
/// barycenter (z is principal), so the hinge must give the panel exactly its centripetal
/// force `m ω² d` toward the axis and the couple that leaves no torque about its centre of
/// mass. Checked at every output row to 1e-9 of `m ω² d` (the lock solve's round-off and the
/// integrator's 1e-12 tolerance are far below; a sign or frame error is of order 1).
#[test]
fn a_locked_hinge_carries_its_reaction_in_the_load_columns() {
    let text = r#"
[run]
duration = 2.0
output_step = 0.1
integrator = "dop853"
rtol = 1e-12
atol = 1e-12
columns = ["default", "h1_F_*", "h1_M_*"]

[[body]]
name = "hub"
mass = 1000.0
inertia = [500.0, 600.0, 1000.0]

[[body]]
name = "panel"
mass = 2.0
inertia = [0.2, 0.3, 0.5]

[[hinge]]
name = "h1"
parent = "hub"
child = "panel"
a0 = { position = [1.0, 0.2, 0.0] }
a = { child_com = [0.5, 0.3, 0.0] }
law = { type = "directional", angles = "euler", x = "locked", y = "locked", z = "locked", rx = "locked", ry = "locked", rz = "locked" }

[initial.hub]
omega = [0.0, 0.0, 3.0]
"#;
    let s = foldsim::scenario::Scenario::from_toml(text, "spin.toml").unwrap();
    let (_, observations, _) = run(&s);
    let m = 2.0;
    let omega = 3.0;
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for o in &observations {
        // The panel's acceleration in rigid rotation about the moving barycenter's z axis.
        let d = o.body_r_in_n[1] - o.barycenter_in_n;
        let d_perp = nalgebra::Vector3::new(d.x, d.y, 0.0);
        let force_on_panel_n = -d_perp * (m * omega * omega);
        // Law convention: the child receives −F (A0 = hub frame here) at A's origin, −τ (A =
        // panel frame here).
        let q = |b: usize| {
            let [w, x, y, z] = o.body_quat[b];
            nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
                .to_rotation_matrix()
                .into_inner()
        };
        let (dcm_n_hub, dcm_n_panel) = (q(0), q(1));
        let f_expected = -(dcm_n_hub.transpose() * force_on_panel_n);
        let arm_n = -(dcm_n_panel * nalgebra::Vector3::new(0.5, 0.3, 0.0));
        // No torque about the panel's CoM: −(arm × F_N + τ_N) = 0 with F_N = −force_on_panel.
        let tau_n = arm_n.cross(&force_on_panel_n);
        let tau_expected = dcm_n_panel.transpose() * tau_n;
        worst =
            worst.max((o.hinge_force_in_a0[0] - f_expected).norm()).max((o.hinge_torque_in_a[0] - tau_expected).norm());
        scale = scale.max(force_on_panel_n.norm());
    }
    eprintln!("locked-hinge reaction: largest error {worst:.2e} N (N·m) against m ω² d = {scale:.4} N");
    assert!(scale > 1.0 && worst < 1e-9 * scale, "{worst:e} against {scale}");
}

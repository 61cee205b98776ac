//! Conservation laws (docs/model.md §4–5): the hinge forces are internal, so linear and angular
//! momentum are conserved for every law and the barycenter moves uniformly; law 2 without
//! damping conserves E = T + V; law 1 does not, and the report says so.
//!
//! Tolerance 1e-10 (relative to the momentum scale, absolute where the quantity is zero) is
//! the core issue's; at rtol = atol = 1e-12 the integration error of these quantities is
//! ~1e-12, so a formulation error (a force or torque not equal and opposite, a wrong
//! application point) would show up many orders above it.

mod common;
use common::*;
use foldsim::scenario::Scenario;

fn drift_check(path: &str) -> foldsim::simulate::RunReport {
    let s = scenario(path);
    let (_, obs, report) = run(&s);
    let d = &report.drift;
    // P and H start at zero in the canonical cases: absolute bounds.
    assert!(obs[0].momentum_in_n.norm() < 1e-12 && obs[0].angular_momentum_in_n.norm() < 1e-12);
    assert!(d.momentum <= 1e-10, "{path}: |ΔP| = {:e}", d.momentum);
    assert!(d.angular_momentum <= 1e-10, "{path}: |ΔH| = {:e}", d.angular_momentum);
    assert!(d.barycenter <= 1e-10, "{path}: barycenter moved {:e} m", d.barycenter);
    report
}

#[test]
fn law2_conserves_momentum_and_energy() {
    for path in ["examples/paper-1panel-euler.toml", "examples/paper-3panel-euler.toml"] {
        let r = drift_check(path);
        assert!(r.energy_conserving);
        let rel = r.drift.energy / r.drift.energy_initial.abs();
        assert!(rel <= 1e-10, "{path}: relative energy drift {rel:e}");
    }
}

/// Law 1 conserves momentum but not energy (−B(θ)ᵀK_θφ is not a gradient): the change is
/// percent-level (reference README: 1.4 % and 11 %) and must be reported as such.
#[test]
fn law1_conserves_momentum_and_reports_energy_change() {
    for (path, at_least) in [("examples/paper-1panel.toml", 5e-3), ("examples/paper-3panel.toml", 5e-2)] {
        let r = drift_check(path);
        assert!(!r.energy_conserving, "{path}: law 1 must not be reported as energy-conserving");
        let rel = r.drift.energy / r.drift.energy_initial.abs();
        assert!(rel >= at_least, "{path}: energy change {rel:e} should be percent-level");
    }
}

/// Nonzero momentum: the hub moves and spins and every tree hinge starts with rates, so P
/// and H are large and relative conservation is tested (1e-10 of Σ m|v| and Σ |r×mv|+|Iω|),
/// and the barycenter must move in a straight line at P/M.
#[test]
fn momentum_conserved_when_nonzero() {
    let text = std::fs::read_to_string(repo("examples/paper-3panel-euler.toml")).unwrap();
    let text = text.replace("duration = 20.0", "duration = 5.0")
        + r#"
[initial.hub]
position = [0.3, -0.2, 0.1]
velocity = [0.5, -0.25, 0.1]
omega = [0.2, -0.3, 0.4]
pitch_deg = 10.0
"#;
    let text = text
        .replace(
            "[initial.hinge.h1]\n",
            "[initial.hinge.h1]\ndelta_rate = [0.01, -0.02, 0.005]\nomega_rel = [0.1, 0.2, -0.3]\n",
        )
        .replace("[initial.hinge.h31]\n", "[initial.hinge.h31]\nomega_rel = [-0.2, 0.1, 0.3]\n");
    let s = Scenario::from_toml(&text, "momentum").unwrap();
    let (_, obs, r) = run(&s);
    let (p0, h0) = (obs[0].momentum_in_n, obs[0].angular_momentum_in_n);
    assert!(p0.norm() > 10.0 && h0.norm() > 10.0, "test needs real momentum: {p0} {h0}");
    let d = &r.drift;
    assert!(d.momentum / d.momentum_scale <= 1e-10, "ΔP/scale = {:e}", d.momentum / d.momentum_scale);
    assert!(
        d.angular_momentum / d.angular_momentum_scale <= 1e-10,
        "ΔH/scale = {:e}",
        d.angular_momentum / d.angular_momentum_scale
    );
    eprintln!(
        "nonzero momentum: |P0| = {:.3}, |H0| = {:.3}, relative drift P {:e}, H {:e}, E {:e}",
        p0.norm(),
        h0.norm(),
        d.momentum / d.momentum_scale,
        d.angular_momentum / d.angular_momentum_scale,
        d.energy / d.energy_initial
    );
    let m = s.model.total_mass();
    for o in &obs {
        let expected = obs[0].barycenter_in_n + p0 / m * o.t;
        assert!((o.barycenter_in_n - expected).norm() < 1e-10, "barycenter off its line at t={}", o.t);
    }
    assert!(d.energy / d.energy_initial <= 1e-10, "relative energy drift {:e}", d.energy / d.energy_initial);
}

/// The barycenter of a system with momentum moves uniformly: the report gives its departure
/// from `Rc(0) + P(0) t / M`, not the motion itself. The 3-panel case with the hub launched
/// at 0.1 m/s drifts 2 m in 20 s; its departure from uniform motion is round-off (1e-12 m:
/// a few ulps of the 2-m positions, times the rows), where the old figure was the 2 m.
#[test]
fn barycenter_drift_is_measured_from_uniform_motion() {
    let mut s = common::example_variant("paper-3panel.toml", &[]);
    s.initial.hub_velocity_in_n = foldsim::math::Vec3::new(0.1, 0.05, 0.0);
    let (_, obs, report) = common::run(&s);
    let moved = (obs.last().unwrap().barycenter_in_n - obs[0].barycenter_in_n).norm();
    assert!(moved > 1.0, "the barycenter should move, moved {moved} m");
    assert!(report.drift.barycenter < 1e-12, "barycenter departure {:e} m", report.drift.barycenter);
}

/// The radial example: a spinning hub whose four panels, stowed upright, open under the spin
/// and latch flat. Angular momentum is shared: the final spin rate is `ω0 · I0 / I1`, with
/// I the structure's moment of inertia about the spin axis in the first and last output
/// configurations (from the bodies' positions and attitudes in the rows). The latches and
/// the damping leave a rigid rotation about the symmetry axis by t = 20 s; the bound 1e-6
/// (relative) is what is left of the damped vibrations' angular momentum exchange, and far
/// below a wrong share (a panel's inertia about its own CoM left out is 1.3 %).
#[test]
fn radial_panels_share_the_spin_as_they_open() {
    let s = scenario("examples/radial-spin.toml");
    let (table, obs, report) = run(&s);
    assert!(report.drift.angular_momentum < 1e-9, "|ΔH| = {:e}", report.drift.angular_momentum);
    let inertia_about_z = |o: &foldsim::observe::Observation| {
        s.model
            .bodies
            .iter()
            .zip(o.body_r_in_n.iter().zip(&o.body_theta))
            .map(|(b, (r, theta))| {
                let dcm_n_b = theta.to_dcm().transpose();
                let own = (dcm_n_b * b.inertia_in_body * dcm_n_b.transpose())[(2, 2)];
                own + b.mass * (r.x * r.x + r.y * r.y)
            })
            .sum::<f64>()
    };
    let (first, last) = (&obs[0], obs.last().unwrap());
    let w = table.col("w_B_z");
    let (w0, w1) = (table.rows[0][w], table.rows.last().unwrap()[w]);
    assert!((w0 - 2.0 * std::f64::consts::PI * 10.0 / 60.0).abs() < 1e-15, "10 rev/min at the start");
    let expected = w0 * inertia_about_z(first) / inertia_about_z(last);
    assert!(((w1 - expected) / expected).abs() < 1e-6, "spin {w1} rad/s, ω0 I0 / I1 = {expected}");
    assert!(w1 < 0.95 * w0, "the spin drops as the panels open");

    // The spin-deployment columns: the spin rate is the hub's ω about H (here its z axis);
    // I_spin × spin_rate is H in the first and last rows (rigid rotations, 1e-12); the
    // deployed fraction runs from the stowed plates' corners (√(0.5² + 0.3²) m from the
    // axis) over the deployed ones' (√(1.5² + 0.3²) m) to 1 (the stiff hinges stretch
    // 1e-5 m under the spin: bound 1e-4), and the report times 90 % between the rows.
    let (spin, inertia, deployed) = (table.col("spin_rate"), table.col("I_spin"), table.col("deployed"));
    for row in &table.rows {
        assert!((row[spin] - row[w]).abs() < 1e-12, "spin_rate is w_B_z about a z-aligned H");
    }
    let (r0, r1) = (&table.rows[0], table.rows.last().unwrap());
    let (h0, h1) = (r0[inertia] * r0[spin], r1[inertia] * r1[spin]);
    assert!(((h1 - h0) / h0).abs() < 1e-12, "I_spin ω: {h0} → {h1}");
    assert!((r0[inertia] - inertia_about_z(first)).abs() < 1e-12 * r0[inertia]);
    let stowed = (0.34f64 / 2.34).sqrt();
    assert!((r0[deployed] - stowed).abs() < 1e-12, "stowed fraction {} vs {stowed}", r0[deployed]);
    assert!((r1[deployed] - 1.0).abs() < 1e-4, "deployed fraction {}", r1[deployed]);
    let t90 = report.deployed_90.expect("90 % deployed");
    let crossed = table.rows.windows(2).find(|w| w[0][deployed] < 0.9 && w[1][deployed] >= 0.9).expect("a crossing");
    assert!(t90 >= crossed[0][0] && t90 <= crossed[1][0], "90 % at {t90} s");
}

/// A restraint holds the stowed state until `run.release_at`: until then the structure turns
/// as one rigid body (every hinge angle at its initial value, the spin rate constant), and
/// afterwards the panels open exactly as in the run released at t = 0, two seconds later:
/// the relative motion is the same because the rigid phase only turns the whole structure
/// about its momentum axis. Bounds: the held angles to 1e-9 rad (the locks' drift limit is
/// 1e-11, with projections), the shifted motion to 1e-6 rad (both runs at rtol 1e-10 over a
/// latching deployment), the spin to 1e-12 relative.
#[test]
fn a_restraint_holds_the_stowed_state_until_release() {
    let free = scenario("examples/radial-spin.toml");
    let held = common::example_variant("radial-spin.toml", &[(&["duration"], "20.0\nrelease_at = 2.0")]);
    assert_eq!(held.settings.release_at, Some(2.0));
    let (a, _, ra) = run(&free);
    let (b, _, rb) = run(&held);
    assert_eq!(rb.released_at, Some(2.0));
    let yaw = (1..=4).map(|k| b.col(&format!("h{k}_yaw"))).collect::<Vec<_>>();
    let spin = b.col("spin_rate");
    for row in b.rows.iter().filter(|r| r[0] <= 2.0) {
        for &c in &yaw {
            assert!((row[c] - std::f64::consts::FRAC_PI_2).abs() < 1e-9, "t = {}: held yaw {}", row[0], row[c]);
        }
        assert!((row[spin] / b.rows[0][spin] - 1.0).abs() < 1e-12, "t = {}: spin {}", row[0], row[spin]);
    }
    let mut worst = 0.0f64;
    for rb_row in b.rows.iter().filter(|r| r[0] >= 2.0) {
        let t = rb_row[0] - 2.0;
        let Some(ra_row) = a.rows.iter().find(|r| (r[0] - t).abs() < 1e-9) else { continue };
        for &c in &yaw {
            worst = worst.max((rb_row[c] - ra_row[c]).abs());
        }
    }
    assert!(worst < 1e-6, "released motion differs from the free run shifted by 2 s: {worst:e} rad");
    let dt = rb.deployed_90.unwrap() - ra.deployed_90.unwrap();
    assert!((dt - 2.0).abs() < 1e-6, "90 % deployed {dt} s later");
}

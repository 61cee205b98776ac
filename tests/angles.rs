//! Angle branches (docs/model.md §7): hinge angles are continuous in time for tree and loop
//! hinges alike, given angles outside the principal range are kept, and the singular pitch
//! is reported instead of integrated through.

mod common;
use common::*;
use foldsim::scenario::Scenario;
use foldsim::simulate::{SimError, simulate};
use std::f64::consts::PI;

/// hub → p1 (ha) → p2 (hb), and hub → p2 (hc) closing a loop. p2 spins about hb's yaw axis
/// fast enough for hb's yaw to pass +180°; hc is weak so it barely resists.
fn spinning(loop_hinge: &str, hb_initial: &str) -> String {
    let mut s = String::from(
        r#"
[run]
duration = 3.0
output_step = 0.01
integrator = "dop853"
rtol = 1e-12
atol = 1e-12

[[body]]
name = "hub"
mass = 100.0
inertia = [100.0, 100.0, 100.0]

[[body]]
name = "p1"
mass = 10.0
inertia = [1.0, 1.0, 1.5]

[[body]]
name = "p2"
mass = 5.0
inertia = [0.5, 0.5, 0.8]

[[hinge]]
name = "ha"
parent = "hub"
child = "p1"
a0 = { position = [1.0, 0.0, 0.0] }
a = { child_com = [1.0, 0.0, 0.0] }
law = { type = "euler-potential", k_f = 1000.0, k_theta = 100.0 }

[[hinge]]
name = "hb"
parent = "p1"
child = "p2"
a0 = { position = [1.0, 0.0, 0.0] }
a = { child_com = [0.0, 0.0, 0.0] }
law = { type = "paper-linear", k_f = 1000.0, k_theta = [100.0, 100.0, 0.5] }

[[hinge]]
name = "hc"
parent = "hub"
child = "p2"
a0 = "assembled"
a = { child_com = [0.0, 0.0, 0.0] }
law = { type = "paper-linear", k_f = 0.1, k_theta = 0.01 }
"#,
    );
    s.push_str(hb_initial);
    let _ = loop_hinge;
    s
}

#[test]
fn loop_hinge_yaw_is_continuous_past_180_degrees() {
    // Tree {ha, hb}, loop hc (assembled, so it is never a tree hinge): to make hb the loop
    // hinge instead, give hc an explicit A0 equal to its assembled one and initial values
    // that reproduce the same body state.
    let tree_text = spinning("hc", "\n[initial.hinge.hb]\nyaw_deg = 170.0\nomega_rel = [0.0, 0.0, 6.0]\n");
    let tree = Scenario::from_toml(&tree_text, "tree").unwrap();
    let (a, _, _) = run(&tree);
    let yaw = a.col("hb_yaw");
    let most = a.rows.iter().map(|r| r[yaw]).fold(f64::MIN, f64::max);
    assert!(most > PI + 1.0, "hb yaw should pass 180° continuously, reaches only {most}");
    for w in a.rows.windows(2) {
        assert!((w[1][yaw] - w[0][yaw]).abs() < 0.5, "hb yaw jumps at t={}", w[1][0]);
    }
    // The loop hinge hc's angles are continuous too.
    for c in ["hc_yaw", "hc_roll"] {
        let i = a.col(c);
        for w in a.rows.windows(2) {
            assert!((w[1][i] - w[0][i]).abs() < 0.5, "{c} jumps at t={}", w[1][0]);
        }
    }

    // Same structure with hb as the loop hinge: p2 placed from the hub through hc.
    let h = tree.model.hinge_index("hc").unwrap();
    let hc = &tree.model.hinges[h];
    let (y0, refs) = foldsim::kinematics::initial_state(&tree.model, &tree.initial);
    let k = foldsim::kinematics::hinge_kinematics(
        hc,
        &foldsim::state::BodyMotion::from_state(&y0, hc.parent),
        &foldsim::state::BodyMotion::from_state(&y0, hc.child),
        &refs[h],
    );
    let a0 = foldsim::math::Euler321::from_dcm(&hc.dcm_a0_parent);
    let p = hc.r_a0_in_parent;
    let s = &k.state;
    let looped_text = tree_text
        .replace(
            "name = \"hc\"\nparent = \"hub\"\nchild = \"p2\"\na0 = \"assembled\"",
            &format!(
                "name = \"hc\"\nparent = \"hub\"\nchild = \"p2\"\na0 = {{ position = [{:e}, {:e}, {:e}], yaw = {:e}, pitch = {:e}, roll = {:e} }}",
                p.x, p.y, p.z, a0.yaw, a0.pitch, a0.roll
            ),
        )
        .replace("[initial.hinge.hb]\nyaw_deg = 170.0\nomega_rel = [0.0, 0.0, 6.0]\n", "")
        + &format!(
            "[initial.hinge.hc]\ndelta = [{:e}, {:e}, {:e}]\ndelta_rate = [{:e}, {:e}, {:e}]\nomega_rel = [{:e}, {:e}, {:e}]\nyaw = {:e}\npitch = {:e}\nroll = {:e}\n",
            s.delta_in_a0.x, s.delta_in_a0.y, s.delta_in_a0.z,
            s.delta_rate_in_a0.x, s.delta_rate_in_a0.y, s.delta_rate_in_a0.z,
            s.omega_rel_in_a.x, s.omega_rel_in_a.y, s.omega_rel_in_a.z,
            s.theta.yaw, s.theta.pitch, s.theta.roll
        );
    let looped = Scenario::from_toml(&looped_text, "looped").unwrap();
    assert!(!looped.model.is_tree_hinge[looped.model.hinge_index("hb").unwrap()], "hb must now be the loop hinge");
    let (b, _, _) = run(&looped);
    // Same physics (1e-9, as for re-rooting): body states and hb's continuous yaw.
    let mut worst = 0.0f64;
    for (ra, rb) in a.rows.iter().zip(&b.rows) {
        for c in ["p2_R_x", "p2_R_y", "p2_R_z", "p1_R_x", "hb_yaw", "hb_pitch", "hb_roll", "T", "V"] {
            let i = a.col(c);
            worst = worst.max((ra[i] - rb[i]).abs());
        }
    }
    assert!(worst < 1e-9, "tree and loop versions differ by {worst:e}");
}

#[test]
fn tree_hinge_keeps_angles_outside_principal_range() {
    let text = |yaw: f64| spinning("hc", &format!("\n[initial.hinge.hb]\nyaw_deg = {yaw}\n"));
    let wrapped = Scenario::from_toml(&text(370.0), "370").unwrap();
    let plain = Scenario::from_toml(&text(10.0), "10").unwrap();
    let (a, _, _) = run(&wrapped);
    let (b, _, _) = run(&plain);
    let yaw = a.col("hb_yaw");
    assert!((a.rows[0][yaw] - 370f64.to_radians()).abs() < 1e-12, "initial yaw kept at 370°: {}", a.rows[0][yaw]);
    assert!((b.rows[0][yaw] - 10f64.to_radians()).abs() < 1e-12);
    // Same pose, different spring state: the 370° hinge stores a full turn of torsion.
    let v = a.col("V");
    assert!(a.rows[0][v] > b.rows[0][v] + 1.0, "370° must store more energy than 10°");
}

#[test]
fn singular_pitch_is_reported() {
    let text = spinning("hc", "\n[initial.hinge.hb]\npitch_deg = 85.0\nomega_rel = [0.0, 15.0, 0.0]\n");
    let s = Scenario::from_toml(&text, "gimbal").unwrap();
    let mut rows = 0;
    let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> {
        rows += 1;
        Ok(())
    };
    match simulate(&s.model, &s.initial, &s.settings, &mut sink, None) {
        Err(SimError::Physics(m)) => assert!((m.contains("'hb'") || m.contains("'hc'")) && m.contains("±90°"), "{m}"),
        other => panic!("expected a gimbal-lock error, got {other:?}"),
    }
    assert!(rows > 0);
}

//! Animation files (docs/outputs.md): the poses read back from a `.glb` equal the CSV's body
//! positions and quaternions at every frame, to 1e-6 m and 1e-6 rad (the file stores f32:
//! 6e-8 relative, so ~1e-7 m at these examples' sizes of a few metres); the CSV's 3-2-1
//! angles give the same attitude as its quaternions to 1e-7 rad at every angle, pitch ±90°
//! included (radial-spin's panels start upright; the gimbal-lock branch is exact to about
//! 1e-8 rad); the file written from a finished run's CSV is the run's own, byte for byte
//! (the CSV's shortest round-trip digits give back the same doubles).
#![cfg(feature = "animation")]

mod common;
use common::*;
use foldsim::math::Euler321;
use foldsim::output::animation::read_glb;
use nalgebra::{Quaternion, Rotation3, UnitQuaternion};

#[test]
fn animation_poses_match_the_csv_and_the_csv_gives_the_same_file() {
    for example in ["zfold-tape-latch", "flasher-small", "paper-3panel", "radial-spin"] {
        let dir = tmp("animation", example);
        let (csv, glb, again) = (dir.join("run.csv"), dir.join("run.glb"), dir.join("again.glb"));
        let scenario = repo(&format!("examples/{example}.toml"));
        let out = foldsim()
            .arg("run")
            .arg(&scenario)
            .arg("--csv")
            .arg(&csv)
            .arg("--animation")
            .arg(&glb)
            .arg("-q")
            .output()
            .unwrap();
        assert!(out.status.success(), "{example}: {}", String::from_utf8_lossy(&out.stderr));
        let table = read_csv(&csv);
        let back = read_glb(&glb).unwrap();
        assert_eq!(back.times.len(), table.rows.len(), "{example}: a frame per row");
        let s = scenario_at(&scenario);
        assert_eq!(back.nodes.len(), s.model.bodies.len());
        let (mut worst_r, mut worst_angle, mut worst_euler) = (0.0f64, 0.0f64, 0.0f64);
        for (name, translations, rotations) in &back.nodes {
            let c = |suffix: &str| table.col(&format!("{name}{suffix}"));
            let (x, y, z, yaw, pitch, roll) = (c("_R_x"), c("_R_y"), c("_R_z"), c("_yaw"), c("_pitch"), c("_roll"));
            let qc = [c("_q_w"), c("_q_x"), c("_q_y"), c("_q_z")];
            for (k, row) in table.rows.iter().enumerate() {
                assert!((f64::from(back.times[k]) - row[table.col("t")]).abs() <= 1e-6 * row[table.col("t")].max(1.0));
                let t = translations[k];
                let dr = ((f64::from(t[0]) - row[x]).powi(2)
                    + (f64::from(t[1]) - row[y]).powi(2)
                    + (f64::from(t[2]) - row[z]).powi(2))
                .sqrt();
                worst_r = worst_r.max(dr);
                let q = rotations[k];
                let file = UnitQuaternion::from_quaternion(Quaternion::new(
                    f64::from(q[3]),
                    f64::from(q[0]),
                    f64::from(q[1]),
                    f64::from(q[2]),
                ));
                let csv_q =
                    UnitQuaternion::from_quaternion(Quaternion::new(row[qc[0]], row[qc[1]], row[qc[2]], row[qc[3]]));
                worst_angle = worst_angle.max(file.angle_to(&csv_q));
                let dcm_n_b = Euler321::new(row[yaw], row[pitch], row[roll]).to_dcm().transpose();
                let euler_q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(dcm_n_b));
                worst_euler = worst_euler.max(euler_q.angle_to(&csv_q));
            }
        }
        eprintln!(
            "{example}: poses read back to {worst_r:.1e} m and {worst_angle:.1e} rad; angles against quaternions {worst_euler:.1e} rad"
        );
        assert!(worst_r <= 1e-6 && worst_angle <= 1e-6, "{example}: {worst_r:e} m, {worst_angle:e} rad");
        assert!(worst_euler <= 1e-7, "{example}: the CSV's angles are {worst_euler:e} rad off its quaternions");
        let out =
            foldsim().arg("animate").arg(&scenario).arg("--csv").arg(&csv).arg("-o").arg(&again).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        assert!(std::fs::read(&glb).unwrap() == std::fs::read(&again).unwrap(), "{example}: the CSV's file differs");
    }
}

fn scenario_at(path: &std::path::Path) -> foldsim::scenario::Scenario {
    foldsim::scenario::Scenario::from_file(path).unwrap()
}

/// Bad requests are refused by name; a failed run leaves no animation.
#[test]
fn animation_requests_are_checked() {
    let dir = tmp("animation", "bad");
    let scenario = repo("examples/paper-1panel.toml");
    let out = foldsim()
        .arg("run")
        .arg(&scenario)
        .arg("--csv")
        .arg(dir.join("a.csv"))
        .arg("--animation")
        .arg(dir.join("a.glb"))
        .args(["--animation-fps", "0"])
        .output()
        .unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("frame rate"));
    let out = foldsim()
        .arg("run")
        .arg(&scenario)
        .arg("--csv")
        .arg(dir.join("a.csv"))
        .arg("--animation")
        .arg(&scenario)
        .output()
        .unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("is an input"));
    // A CSV without the body columns.
    let csv = dir.join("few.csv");
    let out =
        foldsim().arg("run").arg(&scenario).arg("--csv").arg(&csv).args(["--columns", "t,E", "-q"]).output().unwrap();
    assert!(out.status.success());
    let out = foldsim()
        .arg("animate")
        .arg(&scenario)
        .arg("--csv")
        .arg(&csv)
        .arg("-o")
        .arg(dir.join("b.glb"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("hub_R_x") && err.contains("missing"), "{err}");
    assert!(!dir.join("b.glb").exists());
}

/// The viewer page: every placeholder filled (the browser test in CI loads it), the plotted
/// columns and fold angles embedded; a column the CSV lacks is named.
#[test]
fn viewer_page_is_self_contained() {
    let dir = tmp("animation", "view");
    let scenario = repo("examples/paper-3panel.toml");
    let csv = dir.join("run.csv");
    let out = foldsim().arg("run").arg(&scenario).arg("--csv").arg(&csv).arg("-q").output().unwrap();
    assert!(out.status.success());
    let page = dir.join("run.html");
    let out = foldsim()
        .arg("view")
        .arg(&scenario)
        .arg("--csv")
        .arg(&csv)
        .arg("-o")
        .arg(&page)
        .args(["--columns", "E,h1_yaw"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(!html.contains("{{") && html.contains("window.FOLDSIM_DATA = {\"title\":"));
    assert!(html.contains("\"names\":[\"E\",\"h1_yaw\"]") && html.contains("\"units\":[\"J\",\"rad\"]"));
    assert!(html.contains("FOLDSIM_THREE") && html.contains("The MIT License"), "three.js and its licence are inside");
    assert!(!html.contains("src=\"http") && !html.contains("import "), "nothing is fetched");
    // The same page straight from a run.
    let (csv2, page2) = (dir.join("run2.csv"), dir.join("run2.html"));
    let out = foldsim()
        .arg("run")
        .arg(&scenario)
        .arg("--csv")
        .arg(&csv2)
        .arg("--view")
        .arg(&page2)
        .arg("-q")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read_to_string(&page2).unwrap().contains("window.FOLDSIM_DATA"));
    let out = foldsim()
        .arg("view")
        .arg(&scenario)
        .arg("--csv")
        .arg(&csv)
        .arg("-o")
        .arg(dir.join("bad.html"))
        .args(["--columns", "nope"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("'nope'"), "{err}");
    assert!(!dir.join("bad.html").exists());
}

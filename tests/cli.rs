//! The `foldsim` binary end to end: a run writes the CSV atomically and prints the report; a
//! bad scenario or a failed run leaves no file that looks complete.

mod common;

use common::foldsim;
use std::path::PathBuf;
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    common::tmp("cli", name)
}

#[test]
fn run_writes_csv_and_report() {
    let dir = tmp("run");
    let csv = dir.join("out.csv");
    let out = foldsim()
        .args(["run", concat!(env!("CARGO_MANIFEST_DIR"), "/examples/paper-3panel.toml"), "--csv"])
        .arg(&csv)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    for needle in [
        "simulated time",
        "wall time",
        "steps",
        "rhs evaluations",
        "linear momentum P",
        "angular momentum H",
        "barycenter",
        "energy E",
    ] {
        assert!(stdout.contains(needle), "report lacks '{needle}':\n{stdout}");
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("t,R_B_x,R_B_y,R_B_z,BR_B_x"));
    assert!(header.contains("h32_delta_x") && header.ends_with("T,V,E,D,spin_rate,I_spin,radius,deployed"));
    assert_eq!(lines.count(), 401, "rows at 0, 0.05, …, 20 s");
    assert!(!dir.join("out.csv.partial").exists());
    // Not on a terminal: no progress output.
    assert!(out.stderr.is_empty(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn bad_scenario_is_reported_without_output() {
    let dir = tmp("bad");
    let scenario = dir.join("bad.toml");
    let good = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/paper-1panel.toml")).unwrap();
    std::fs::write(&scenario, good.replace("mass = 10.0", "mass = -10.0")).unwrap();
    let csv = dir.join("bad.csv");
    let out = foldsim().arg("run").arg(&scenario).arg("--csv").arg(&csv).output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("bad.toml:") && stderr.contains("mass"), "{stderr}");
    assert!(!csv.exists() && !dir.join("bad.csv.partial").exists());
}

#[test]
fn failed_run_leaves_only_partial_file() {
    let dir = tmp("fail");
    let scenario = dir.join("gimbal.toml");
    let good =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/paper-1panel-euler.toml")).unwrap();
    // Drive the hinge through pitch 90°.
    let text = good
        .replace("[initial.body.panel]\nroll_deg = 10.0\npitch_deg = 20.0\nyaw_deg = 30.0\n", "")
        .replace("delta = [0.01, 0.01, 0.01]      # m, A0 frame", "pitch_deg = 85.0\nomega_rel = [0.0, 20.0, 0.0]");
    std::fs::write(&scenario, text).unwrap();
    let csv = dir.join("gimbal.csv");
    let out = foldsim().arg("run").arg(&scenario).arg("--csv").arg(&csv).output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("h1") && stderr.contains("±90°") && stderr.contains(".partial"), "{stderr}");
    assert!(!csv.exists(), "a failed run must not leave a complete-looking file");
    assert!(dir.join("gimbal.csv.partial").exists());
}

/// `--csv` naming a device or a pipe (`/dev/null`, `/dev/stdout`, a named pipe) streams the
/// rows to it: renaming a finished `.partial` file over it, as for a regular file, would
/// replace the device or the pipe with a file (run as root, `--csv /dev/null` replaced
/// `/dev/null`). Checked on a named pipe read by a second thread, so a regression cannot
/// harm the machine: the pipe gets the header and every row, stays a pipe, and no
/// `.partial` file is left.
#[cfg(unix)]
#[test]
fn csv_to_a_pipe_streams_into_it() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tmp("fifo");
    let fifo = dir.join("rows.csv");
    std::fs::remove_file(&fifo).ok();
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(&fifo).expect("the pipe reads"))
    };
    let out = foldsim()
        .args(["run", concat!(env!("CARGO_MANIFEST_DIR"), "/examples/paper-1panel.toml"), "-q", "--csv"])
        .arg(&fifo)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Before joining: had the pipe been replaced, the reader would wait for a writer forever.
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo(), "the pipe was replaced by a file");
    assert!(!dir.join("rows.csv.partial").exists());
    let text = reader.join().expect("reader finished");
    let mut lines = text.lines();
    assert!(lines.next().is_some_and(|h| h.starts_with("t,")), "header first");
    assert!(lines.count() > 10, "rows streamed to the pipe");
}

/// `bench/peers/mujoco_zfold.py --help` prints its usage without creating its virtual
/// environment (it installed 197 MB first). Skipped where python3 is missing.
#[test]
fn peer_bench_help_installs_nothing() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/bench/peers/mujoco_zfold.py");
    let venv = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/bench/peers/.venv"));
    let existed = venv.exists();
    let Ok(out) = Command::new("python3").arg(script).arg("--help").output() else {
        eprintln!("python3 not found: skipped");
        return;
    };
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("--panels"));
    assert_eq!(venv.exists(), existed, "--help created the virtual environment");
}

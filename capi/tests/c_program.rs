//! The C test program (capi/tests/c/stepping.c), compiled with the system's C compiler
//! against the built libfoldsim_c.so and include/foldsim.h, and run: every bad call it makes
//! must return its error code with a message (it exits 1 otherwise), and its stepped run
//! must equal the same run made here through `foldsim::session::Session` (what Python's
//! `Simulation` and the FMU also step) to 1e-12 relative to each column's size: the two
//! are the same computation, so anything above round-off is a fault of the C layer (a lost
//! input, a wrong index, an output read at the wrong time). python/tests/test_interop.py
//! compares the same program with the Python package's stepping.

use foldsim::scenario::Scenario;
use foldsim::session::Session;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where cargo put the libfoldsim_c.so built with this test: `cargo test` leaves it in
/// target/<profile>/deps beside the test (only `cargo build` copies it up a level, and a copy
/// there may be older).
fn target_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test's own path");
    exe.parent().expect("target/<profile>/deps/<test>").to_path_buf()
}

#[test]
fn c_program_equals_the_session() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let lib = target_dir();
    assert!(lib.join("libfoldsim_c.so").is_file(), "libfoldsim_c.so is not in {}", lib.display());
    let out = std::env::temp_dir().join(format!("foldsim-c-stepping-{}", std::process::id()));
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let compiled = Command::new(&cc)
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-I"])
        .arg(root.join("include"))
        .arg(root.join("capi/tests/c/stepping.c"))
        .arg("-L")
        .arg(&lib)
        .args(["-lfoldsim_c", "-lm"])
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .arg("-o")
        .arg(&out)
        .output()
        .expect("a C compiler (cc) runs");
    assert!(
        compiled.status.success(),
        "the C program does not compile:\n{}",
        String::from_utf8_lossy(&compiled.stderr)
    );
    let scenario_path = root.join("examples/paper-3panel.toml");
    let (steps, dt) = (200usize, 0.01);
    let ran =
        Command::new(&out).arg(&scenario_path).arg(steps.to_string()).arg(dt.to_string()).output().expect("it runs");
    let _ = std::fs::remove_file(&out);
    let stderr = String::from_utf8_lossy(&ran.stderr);
    assert!(ran.status.success(), "the C program failed:\n{stderr}");
    assert!(!stderr.contains("FAIL"), "{stderr}");
    let stdout = String::from_utf8(ran.stdout).expect("UTF-8");
    let mut lines = stdout.lines();
    let names: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect()).collect();
    assert_eq!(rows.len(), steps + 1);

    let mut session =
        Session::start(Scenario::from_file(&scenario_path).expect("the example reads")).expect("it starts");
    assert_eq!(session.output_names(), names.as_slice());
    let input = |s: &Session, n: &str| s.input_index(n).expect("an input");
    let (tz, fx) = (input(&session, "hub_T_z"), input(&session, "hub_F_x"));
    session.set_input(tz, 0.5).unwrap();
    session.set_input(fx, 1.0).unwrap();
    let mut ours = Vec::new();
    for k in 0..=steps {
        ours.push(session.outputs().to_vec());
        if k == steps {
            break;
        }
        if k == steps / 2 {
            session.set_input(tz, -0.25).unwrap();
        }
        session.advance(dt).unwrap();
    }
    let mut worst = (0.0f64, "");
    for (j, name) in names.iter().enumerate() {
        let size = ours.iter().map(|r| r[j].abs()).fold(1.0, f64::max);
        for (a, b) in rows.iter().zip(&ours) {
            let d = (a[j] - b[j]).abs() / size;
            if d > worst.0 {
                worst = (d, name);
            }
        }
    }
    println!("C program against the session: largest difference {:.1e} ({})", worst.0, worst.1);
    assert!(worst.0 <= 1e-12, "C program and session differ by {:.3e} in {}", worst.0, worst.1);
    // The torque acted: H_z gained 0.5 × 1 s − 0.25 × 1 s = 0.25 N·m·s (hub frame ≈ N here,
    // the hub barely turns off z), so the comparison is not of two idle runs.
    let hz = names.iter().position(|n| *n == "H_z").unwrap();
    let gained = rows[steps][hz] - rows[0][hz];
    assert!((gained - 0.25).abs() < 0.01, "H_z gained {gained}, not about 0.25 N·m·s");
}

//! Every run ends, with a result or a located reason (runs that crept near t = 0 for ever,
//! overflows reported as tolerance problems). Each case runs the binary under a wall-clock
//! guard, so a run that would not end fails the test instead of hanging it.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long any of these cases may take: each must end at load or within its first steps.
const GUARD: Duration = Duration::from_secs(20);

/// A generated 3-panel z-fold (the base case) with `edit` applied to its text.
fn variant(name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("foldsim-stuck-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = foldsim::generate::zfold(3, &foldsim::generate::Params::default());
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, edit(text)).unwrap();
    path
}

/// Runs `foldsim run FILE -q` under the guard: (finished in time, success, stderr).
fn run(scenario: &Path) -> (bool, bool, String) {
    let csv = scenario.with_extension("csv");
    let mut child = Command::new(env!("CARGO_BIN_EXE_foldsim"))
        .args(["run", scenario.to_str().unwrap(), "-q", "--csv", csv.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
            return (true, status.success(), err);
        }
        if start.elapsed() > GUARD {
            child.kill().unwrap();
            child.wait().unwrap();
            return (false, false, String::new());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Runs the case and checks it fails in time with every needle in its message.
fn fails_with(name: &str, edit: impl Fn(String) -> String, needles: &[&str]) {
    let path = variant(name, edit);
    let (ended, ok, err) = run(&path);
    assert!(ended, "{name}: the run did not end within {GUARD:?}");
    assert!(!ok, "{name}: the run succeeded");
    for needle in needles {
        assert!(err.contains(needle), "{name}: the message lacks '{needle}':\n{err}");
    }
}

fn set(text: String, from: &str, to: &str) -> String {
    assert!(text.contains(from), "the generated scenario has no '{from}'");
    text.replacen(from, to, 1)
}

#[test]
fn tolerances_beyond_f64_are_refused_at_load() {
    fails_with(
        "rtol",
        |t| set(set(t, "rtol = 1e-8", "rtol = 1e-20"), "atol = 1e-8", "atol = 1e-20"),
        &["rtol", ":8:", "f64"],
    );
}

/// A tiny absolute tolerance with a sane relative one: the steps collapse at t = 0 (where a
/// floor relative to |t| cannot act) and the run stops at the floor of 1e-12 × duration,
/// saying the steps are far below every hinge's period and naming the tolerances.
#[test]
fn a_collapsing_step_stops_at_the_floor_and_says_why() {
    fails_with(
        "atol",
        |t| set(t, "atol = 1e-8", "atol = 1e-30"),
        &["t = 0 s", "floor", "fastest hinge is hinge 'h", "run.atol"],
    );
}

#[test]
fn a_fixed_step_too_small_is_refused_at_load() {
    fails_with(
        "rk4",
        |t| {
            set(
                set(set(t, "integrator = \"dop853\"", "integrator = \"rk4\"\nstep = 1e-300"), "rtol = 1e-8\n", ""),
                "atol = 1e-8\n",
                "",
            )
        },
        &["run.step", "steps"],
    );
}

#[test]
fn absurd_angles_are_refused_at_load() {
    fails_with("yaw", |t| set(t, "yaw_deg = 30.0", "yaw_deg = 1e17"), &["1000 turns", "yaw"]);
}

/// Offsets, masses and stiffnesses that make a hinge vibrate far faster than any explicit
/// run can follow: refused at load, naming the hinge and direction and what to do.
#[test]
fn hinges_too_fast_to_follow_are_refused_at_load() {
    for (name, from, to) in [
        ("offset", "position = [0.5, 0.0, 0.0]", "position = [1e19, 0.0, 0.0]"),
        ("mass", "mass = 2.0\nshape", "mass = 1e-300\ninertia = [1.0, 1.0, 1.0]\n# shape"),
        ("stiffness", "k_f = 1e6", "k_f = 1e300"),
        ("child_com", "child_com = [0.5, 0.0, 0.0]", "child_com = [1e300, 0.0, 0.0]"),
    ] {
        fails_with(name, |t| set(t, from, to), &["hinge 'h", "direction", "sdirk4", "run.max_steps"]);
    }
}

/// Rates that overflow the accelerations are refused at load naming the body, not reported
/// as a step size that fell to zero.
#[test]
fn overflowing_initial_rates_name_the_body() {
    fails_with(
        "omega",
        |t| format!("{t}\n[initial.hub]\nomega = [1e300, 2e300, 0.0]\n"),
        &["initial state", "body 'hub'", "not finite"],
    );
}

/// A run that keeps going at steps far below what its hinges need is stopped by its step
/// budget (here set low) and says so, with the fastest hinge.
#[test]
fn the_step_budget_stops_a_run_and_says_so() {
    fails_with(
        "budget",
        |t| set(t, "atol = 1e-8", "atol = 1e-8\nmax_steps = 50"),
        &["50 steps", "run.max_steps", "fastest hinge"],
    );
}

/// The same run with a sane budget is unaffected: the bounds do not fire on real runs.
#[test]
fn the_bounds_leave_real_runs_alone() {
    let path = variant("sane", |t| t);
    let (ended, ok, err) = run(&path);
    assert!(ended && ok, "{err}");
}

//! What a run writes, and when it must not: the output's size estimated and refused past a
//! limit, columns chosen, rows flushed while a run goes, Ctrl-C answered, inputs never
//! overwritten, an earlier run's output named, the rate columns right, rates given in rpm and
//! °/s, the generators bounded, and hinge events past the report's twenty written to their table.

mod common;

use common::foldsim;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn tmp(name: &str) -> PathBuf {
    common::tmp("outputs", name)
}

fn example(name: &str) -> String {
    std::fs::read_to_string(common::repo(&format!("examples/{name}"))).unwrap()
}

/// Writes `text` as a scenario in `dir` and runs it with `args`: (success, stdout, stderr).
fn run_text(dir: &Path, text: &str, args: &[&str]) -> (bool, String, String) {
    let scenario = dir.join("s.toml");
    std::fs::write(&scenario, text).unwrap();
    let out = foldsim().arg("run").arg(&scenario).args(args).output().unwrap();
    (out.status.success(), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

/// `duration = 1e12` or `output_step = 1e-12` would write without bound: refused before any
/// file is made, with the size, what to change and the flag that insists.
#[test]
fn unbounded_output_is_refused_before_the_run() {
    let dir = tmp("size");
    let base = example("paper-1panel.toml");
    // 1e12 s, 5e-14 s: more than 1e7 rows, refused at load.
    let csv = dir.join("out.csv");
    for (from, to) in [("duration = 20.0", "duration = 1e12"), ("output_step = 0.05", "output_step = 5e-14")] {
        assert!(base.contains(from));
        let (ok, _, err) = run_text(&dir, &base.replace(from, to), &["--csv", csv.to_str().unwrap()]);
        assert!(!ok && err.contains("output rows") && err.contains("run.output_step"), "{err}");
        assert!(!csv.exists() && !dir.join("out.csv.partial").exists(), "a file was made");
    }
    // 5e6 rows of the default columns: gigabytes, refused by the size estimate.
    let (ok, _, err) =
        run_text(&dir, &base.replace("output_step = 0.05", "output_step = 4e-6"), &["--csv", csv.to_str().unwrap()]);
    assert!(!ok);
    for needle in ["GiB", "run.output_step", "--columns", "--large-output"] {
        assert!(err.contains(needle), "lacks '{needle}': {err}");
    }
    assert!(!csv.exists() && !dir.join("out.csv.partial").exists(), "a file was made");
}

/// Columns chosen on the command line or in the scenario; patterns that match nothing are
/// refused naming the pattern.
#[test]
fn columns_can_be_chosen() {
    let dir = tmp("columns");
    let csv = dir.join("out.csv");
    let base = example("paper-3panel.toml");
    let (ok, _, err) =
        run_text(&dir, &base, &["-q", "--csv", csv.to_str().unwrap(), "--columns", "h?_yaw,h3?_yaw,w_B_z"]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().next().unwrap(), "t,w_B_z,h1_yaw,h2_yaw,h31_yaw,h32_yaw");
    assert_eq!(text.lines().nth(1).unwrap().split(',').count(), 6);

    let with_key = base.replace("[run]\n", "[run]\ncolumns = [\"default\", \"p1_v_?\"]\n");
    assert!(with_key.contains("columns ="));
    let (ok, _, err) = run_text(&dir, &with_key, &["-q", "--csv", csv.to_str().unwrap()]);
    assert!(ok, "{err}");
    let header = std::fs::read_to_string(&csv).unwrap().lines().next().unwrap().to_string();
    assert!(
        header.contains("p1_v_x,p1_v_y,p1_v_z") && header.contains("h1_wrel_z") && !header.contains("p1_w_x"),
        "{header}"
    );

    let (ok, _, err) = run_text(&dir, &base, &["-q", "--csv", csv.to_str().unwrap(), "--columns", "t,nosuch*"]);
    assert!(!ok && err.contains("'nosuch*'") && err.contains("matches no output column"), "{err}");
}

/// A long run's partial file has its header at once and rows within a few seconds (they
/// were held in a buffer: a stuck run left a 0-byte file after a minute), and Ctrl-C stops
/// it saying where it stopped and where its rows are; so does SIGTERM (a batch system's time
/// limit), which used to end it without a word.
#[cfg(unix)]
#[test]
fn a_long_run_shows_its_rows_and_stops_on_ctrl_c_or_sigterm() {
    for signal in ["INT", "TERM"] {
        let dir = tmp(&format!("sig{signal}"));
        let scenario = dir.join("long.toml");
        // A 64-panel chain for 1e4 s: an hour of work, whose output (one row per second) is
        // small.
        let text = foldsim::generate::zfold(
            64,
            &foldsim::generate::Params { duration: 1e4, output_step: 1.0, ..Default::default() },
        );
        std::fs::write(&scenario, text).unwrap();
        let csv = dir.join("long.csv");
        let partial = dir.join("long.csv.partial");
        let mut child = foldsim()
            .args(["run", scenario.to_str().unwrap(), "-q", "--csv", csv.to_str().unwrap()])
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let start = Instant::now();
        let lines = |p: &Path| std::fs::read_to_string(p).map(|t| t.lines().count()).unwrap_or(0);
        while lines(&partial) < 1 && start.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(20));
        }
        assert!(lines(&partial) >= 1, "no header in the partial file after {:?}", start.elapsed());
        while lines(&partial) < 2 && start.elapsed() < Duration::from_secs(15) {
            std::thread::sleep(Duration::from_millis(100));
        }
        assert!(lines(&partial) >= 2, "no row in the partial file after {:?}", start.elapsed());
        let killed = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
        assert!(killed.success());
        let status = child.wait().unwrap();
        let mut err = String::new();
        std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
        assert!(!status.success());
        assert!(err.contains("interrupted at t =") && err.contains("long.csv.partial"), "SIG{signal}: {err}");
        assert!(!csv.exists());
    }
}

/// `--csv` naming the scenario or one of its table files is refused and the file is left as
/// it was (it overwrote the scenario).
#[test]
fn an_input_is_never_written_over() {
    let dir = tmp("inputs");
    let scenario = dir.join("s.toml");
    let text = example("paper-1panel.toml");
    std::fs::write(&scenario, &text).unwrap();
    let out = foldsim().arg("run").arg(&scenario).arg("--csv").arg(&scenario).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("is an input of this command"), "{err}");
    assert_eq!(std::fs::read_to_string(&scenario).unwrap(), text);

    let table = common::repo("examples/tables/fold-twist.csv");
    let before = std::fs::read(&table).unwrap();
    let out = foldsim()
        .arg("run")
        .arg(common::repo("examples/zfold-tape-latch.toml"))
        .arg("--csv")
        .arg(common::repo("examples/tables/../tables/tape-spring-increasing.csv"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("tape-spring-increasing.csv"), "{err}");
    assert_eq!(std::fs::read(&table).unwrap(), before);
}

/// A failed run beside an earlier run's complete output says the complete file is the
/// earlier run's (it said nothing of it).
#[test]
fn an_earlier_output_is_named_when_a_run_fails() {
    let dir = tmp("stale");
    let csv = dir.join("out.csv");
    let good = example("paper-1panel-euler.toml");
    let (ok, _, err) = run_text(&dir, &good, &["-q", "--csv", csv.to_str().unwrap()]);
    assert!(ok, "{err}");
    let bad = good
        .replace("[initial.body.panel]\nroll_deg = 10.0\npitch_deg = 20.0\nyaw_deg = 30.0\n", "")
        .replace("delta = [0.01, 0.01, 0.01]      # m, A0 frame", "pitch_deg = 85.0\nomega_rel = [0.0, 20.0, 0.0]");
    let (ok, _, err) = run_text(&dir, &bad, &["-q", "--csv", csv.to_str().unwrap()]);
    assert!(!ok);
    assert!(err.contains("out.csv.partial") && err.contains("earlier run's complete output"), "{err}");
}

/// The rate columns: `<hinge>_wrel_z` is the yaw rate of a fold about A's z axis, checked
/// against the central difference of the yaw column (1-panel law-2 case, pitch and roll
/// small: `ω_rel = B(θ) θ̇`, so `wrel_z = θ̇1 − sin θ2 θ̇3`... compared with the full
/// relation below), and `w_B` against `B(θ_B) θ̇_B` likewise; rates given in rpm and °/s
/// arrive as rad/s.
#[test]
fn rate_columns_match_the_angles_they_differentiate() {
    use foldsim::math::Euler321;
    let mut s =
        common::example_variant("paper-1panel-euler.toml", &[(&["output_step"], "0.001"), (&["duration"], "2.0")]);
    s.columns = foldsim::observe::Selection::default_for(&s.model);
    let (table, _, _) = common::run(&s);
    let (yaw, pitch, roll) = (table.col("h1_yaw"), table.col("h1_pitch"), table.col("h1_roll"));
    let w = [table.col("h1_wrel_x"), table.col("h1_wrel_y"), table.col("h1_wrel_z")];
    let mut worst = 0.0f64;
    for k in 1..table.rows.len() - 1 {
        let (a, b, c) = (&table.rows[k - 1], &table.rows[k], &table.rows[k + 1]);
        let rate = |i: usize| (c[i] - a[i]) / 0.002;
        let theta_rate = foldsim::math::Vec3::new(rate(yaw), rate(pitch), rate(roll));
        let omega = Euler321::new(b[yaw], b[pitch], b[roll]).rate_matrix() * theta_rate;
        for (j, &col) in w.iter().enumerate() {
            worst = worst.max((omega[j] - b[col]).abs());
        }
    }
    // Central differences at 1 ms on motions of a few rad/s: error ~ h² θ⃛ / 6 ≈ 1e-6.
    assert!(worst < 1e-4, "ω_rel columns differ from B(θ) θ̇ by {worst:e} rad/s");

    let text = example("paper-1panel.toml");
    for (key, expected) in [
        ("omega_rpm = [0.0, 0.0, 60.0]", 2.0 * std::f64::consts::PI),
        ("omega_deg_s = [0.0, 0.0, 90.0]", std::f64::consts::FRAC_PI_2),
    ] {
        assert!(text.contains("omega = [0.0, 0.0, 0.0]"));
        let with = text.replace("omega = [0.0, 0.0, 0.0]", key);
        let s = foldsim::scenario::Scenario::from_toml_in(&with, "rpm", &common::repo("examples"))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!((s.initial.hub_omega_in_hub.z - expected).abs() < 1e-15, "{key}");
    }
    let both = text.replace("omega = [0.0, 0.0, 0.0]", "omega = [0.0, 0.0, 1.0]\nomega_rpm = [0.0, 0.0, 1.0]");
    let e = foldsim::scenario::Scenario::from_toml(&both, "both").unwrap_err();
    assert!(e.message.contains("omega_rpm") && e.location.is_some(), "{e}");
}

/// The generators refuse sizes that would exhaust memory (`--rows 4294967296` grew past
/// 4 GB), at once.
#[test]
fn generators_are_bounded() {
    let start = Instant::now();
    let out = foldsim().args(["generate", "grid", "--rows", "4294967296", "--cols", "2"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("100000"), "{err}");
    let out = foldsim().args(["generate", "zfold", "--panels", "100001"]).output().unwrap();
    assert!(!out.status.success());
    assert!(start.elapsed() < Duration::from_secs(10));
}

/// `foldsim plot` never returned on a column holding ±inf or only NaN, and drew a single NaN
/// as a spike: now it skips non-finite points (gaps), finishes, and refuses columns with no
/// finite value at all, naming them.
#[cfg(feature = "plot")]
#[test]
fn plot_skips_non_finite_points_and_ends() {
    let dir = tmp("plot");
    let csv = dir.join("odd.csv");
    let mut text = String::from("t,h1_yaw,E,allnan\n");
    for k in 0..50 {
        let t = k as f64 * 0.1;
        let yaw = if k == 20 { "NaN".to_string() } else { format!("{}", t.sin()) };
        let e = if k == 30 {
            "inf".to_string()
        } else if k == 31 {
            "-inf".to_string()
        } else {
            format!("{}", t * t)
        };
        text.push_str(&format!("{t},{yaw},{e},NaN\n"));
    }
    std::fs::write(&csv, text).unwrap();
    let png = dir.join("odd.png");
    let mut child = foldsim()
        .args(["plot", csv.to_str().unwrap(), "--columns", "h1_yaw,E,allnan", "-o", png.to_str().unwrap()])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            panic!("foldsim plot did not return within 20 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success());
    assert!(std::fs::metadata(&png).unwrap().len() > 1000, "a PNG was written");
    let out = foldsim()
        .args(["plot", csv.to_str().unwrap(), "--columns", "allnan", "-o", png.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("allnan") && err.contains("no finite value"), "{err}");
}

/// Hinge loads (`_F_*`, `_M_*`, written on request) are the restoring wrench whose power the
/// stored energy follows: for a potential law without damping dV/dt = Σ (F·δ̇ + τ·ω_rel),
/// with V, δ̇ and ω_rel from their own columns. Checked on the law-2 three-panel case (four
/// hinges, one closing a loop) by central differences at 0.25 ms: error ~h² V⃛/6 (measured
/// 5.4e-4 of the power's scale at 1 ms, 3.5e-5 at 0.25 ms: second order, so it is the
/// differencing); a sign or frame error would be of order one.
#[test]
fn hinge_load_columns_carry_the_power_of_the_stored_energy() {
    let mut s =
        common::example_variant("paper-3panel-euler.toml", &[(&["output_step"], "0.00025"), (&["duration"], "2.0")]);
    s.columns = foldsim::observe::Selection::matching(&s.model, &["*".to_string()]).unwrap();
    let (table, _, _) = common::run(&s);
    let v = table.col("V");
    let hinges: Vec<String> = s.model.hinges.iter().map(|h| h.name.clone()).collect();
    let cols = |h: &str, stem: &str| ["x", "y", "z"].map(|a| table.col(&format!("{h}_{stem}_{a}")));
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for k in 1..table.rows.len() - 1 {
        let (a, b, c) = (&table.rows[k - 1], &table.rows[k], &table.rows[k + 1]);
        let dv = (c[v] - a[v]) / 0.0005;
        let mut power = 0.0;
        for h in &hinges {
            let (f, d, m, w) = (cols(h, "F"), cols(h, "delta_rate"), cols(h, "M"), cols(h, "wrel"));
            for j in 0..3 {
                power += b[f[j]] * b[d[j]] + b[m[j]] * b[w[j]];
                scale = scale.max((b[f[j]] * b[d[j]]).abs() + (b[m[j]] * b[w[j]]).abs());
            }
        }
        worst = worst.max((dv - power).abs());
    }
    eprintln!("dV/dt against the hinges' power: {worst:.2e} W of {scale:.2e} W");
    assert!(scale > 1e-3, "the hinges work: {scale} W");
    assert!(worst < 1e-4 * scale, "dV/dt differs from the hinges' power by {worst:e} W (scale {scale:e} W)");
}

/// A panel sprung against an undamped stop rattles on it: the report lists the first 20
/// events and says how many more there are; `--events` writes every one (the report's count,
/// in time order, alternately hitting and leaving the stop, each hit at the stop's angle).
#[test]
fn hinge_events_beyond_the_report_go_to_their_table() {
    let dir = tmp("events");
    let text = r#"
[run]
duration = 4.0
output_step = 0.1
integrator = "dop853"
rtol = 1e-9
atol = 1e-11

[[body]]
name = "hub"
mass = 100.0
inertia = [100.0, 100.0, 100.0]

[[body]]
name = "panel"
mass = 1.0
inertia = [0.1, 0.1, 0.1]

[[hinge]]
name = "h1"
parent = "hub"
child = "panel"
a0 = { position = [0.5, 0.0, 0.0] }
a = { child_com = [0.5, 0.0, 0.0] }
law = { type = "directional", angles = "euler", x = "locked", y = "locked", z = "locked", rx = "locked", ry = "locked", rz = { k = 50.0, rest_deg = 30.0, stop = { at_deg = 0.0, free = "below", stiffness = 1e3, damping = 0.0 } } }

[initial.hinge.h1]
yaw_deg = -30.0
"#;
    let events = dir.join("events.csv");
    let (ok, out, err) = run_text(&dir, text, &["--csv", dir.join("o.csv").to_str().unwrap()]);
    assert!(ok, "{err}");
    let located: usize = out
        .lines()
        .find_map(|l| l.trim().strip_prefix("hinge events: ")?.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("{out}"));
    assert!(located > 30, "{out}");
    assert_eq!(out.lines().filter(|l| l.trim_start().starts_with("t = ")).count(), 20, "{out}");
    assert!(out.contains(&format!("... {} more", located - 20)) && out.contains("--events FILE.csv"), "{out}");

    let (ok, out, err) =
        run_text(&dir, text, &["--csv", dir.join("o.csv").to_str().unwrap(), "--events", events.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(out.contains(&format!("every one in {}", events.display())), "{out}");
    let table = std::fs::read_to_string(&events).unwrap();
    let rows: Vec<Vec<&str>> = table.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(table.lines().next(), Some(foldsim::output::events::HEADER));
    assert_eq!(rows.len(), located);
    let times: Vec<f64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[0] < w[1]), "{times:?}");
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r[1], "\"h1\"");
        assert_eq!(r[2], if i % 2 == 0 { "stop_hit" } else { "stop_left" }, "row {i}: {r:?}");
    }
    assert!(rows[0][3].contains("hits the stop at 0.000000"), "{:?}", rows[0]);
    // Not over an input, and only as a CSV table.
    let (ok, _, err) = run_text(&dir, text, &["--events", dir.join("s.toml").to_str().unwrap()]);
    assert!(!ok && err.contains("--events"), "{err}");
    let (ok, _, err) = run_text(&dir, text, &["--events", dir.join("e.txt").to_str().unwrap()]);
    assert!(!ok && err.contains("--events") && err.contains("csv"), "{err}");
}

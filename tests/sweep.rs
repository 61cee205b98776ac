//! Sweeps (docs/sweep.md): the table is the same on any number of workers; each row is the
//! run it says (checked against an independent run of the changed scenario); the draws
//! follow their distributions; a failed run is recorded and the sweep goes on; bad [sweep]
//! tables are refused with their line.

mod common;

use common::{foldsim, repo, tmp};
use foldsim::scenario::{ScenarioText, SetValue};
use foldsim::sweep::Sweep;
use std::path::Path;
use std::sync::atomic::AtomicBool;

const EXAMPLE: &str = "examples/sweep-paper-1panel.toml";

fn sweep_file(path: &str) -> Sweep {
    Sweep::from_file(&repo(path)).unwrap_or_else(|e| panic!("{e}"))
}

/// The example's text with its [sweep] table replaced by `table`.
fn with_table(file: &str, table: &str) -> Result<Sweep, String> {
    let text = std::fs::read_to_string(repo(file)).unwrap();
    let cut = text.find("\n[sweep]").map_or(text.len(), |i| i + 1);
    let text = format!("{}{table}", &text[..cut]);
    Sweep::new(ScenarioText::new(&text, "test.toml", &repo("examples")).map_err(|e| e.to_string())?)
        .map_err(|e| e.to_string())
}

fn all_rows(s: &Sweep, workers: usize) -> Vec<foldsim::sweep::SweepRow> {
    let mut rows = Vec::new();
    s.run(0..s.runs(), workers, &AtomicBool::new(false), &mut |r| {
        rows.push(r);
        Ok(())
    })
    .unwrap();
    rows
}

#[test]
fn the_cli_table_is_byte_identical_on_1_2_and_3_workers() {
    let dir = tmp("sweep", "workers");
    let mut tables = Vec::new();
    for workers in ["1", "2", "3"] {
        let out = dir.join(format!("w{workers}.csv"));
        let status = foldsim()
            .args(["sweep", repo(EXAMPLE).to_str().unwrap(), "--runs", "80", "--workers", workers, "-q", "-o"])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        assert!(!Path::new(&format!("{}.partial", out.display())).exists(), "the .partial file is renamed");
        tables.push(std::fs::read(&out).unwrap());
    }
    assert_eq!(tables[0], tables[1]);
    assert_eq!(tables[0], tables[2]);
    let mut t = csv::Reader::from_path(dir.join("w1.csv")).unwrap();
    let header: Vec<String> = t.headers().unwrap().iter().map(str::to_string).collect();
    assert_eq!(t.records().count(), 80);
    assert_eq!(&header[..3], ["run", "status", "hinge.h1.law.k_theta"]);
    assert_eq!(header.last().unwrap(), "error");
    // A different seed draws different values.
    let other = dir.join("seed.csv");
    let status = foldsim()
        .args(["sweep", repo(EXAMPLE).to_str().unwrap(), "--runs", "80", "--seed", "1", "-q", "-o"])
        .arg(&other)
        .status()
        .unwrap();
    assert!(status.success());
    assert_ne!(std::fs::read(&other).unwrap(), tables[0]);
}

/// Each row against an independent run: the drawn values set by key path, the scenario run
/// on its own, the metrics recomputed from its full output table. Bound: 0 for the values
/// and the column statistics (the same floating-point run), 1e-12 s for the crossing time
/// (interpolated here independently).
#[test]
fn every_row_is_the_run_of_its_values() {
    let s = sweep_file(EXAMPLE);
    let mut s2 = s.clone();
    s2.set_runs(6).unwrap();
    let rows = all_rows(&s2, 2);
    let base = ScenarioText::from_file(&repo(EXAMPLE)).unwrap();
    let paths: Vec<String> = s.spec().parameters.iter().map(|p| p.path.clone()).collect();
    for row in &rows {
        assert!(row.error.is_none(), "{:?}", row.error);
        let mut text = base.clone();
        for (p, x) in paths.iter().zip(&row.values) {
            text.set(p, &SetValue::Number(*x)).unwrap();
        }
        let scenario = text.build().unwrap();
        assert_eq!(scenario.model.bodies[1].mass, row.values[3], "body.panel.mass set");
        let (table, _, report) = common::run(&scenario);
        let col = |n: &str| table.rows.iter().map(|r| r[table.col(n)]).collect::<Vec<f64>>();
        let pitch = col("h1_pitch");
        let t = col("t");
        let max = pitch.iter().cloned().fold(f64::MIN, f64::max);
        let min_wz = col("w_B_z").iter().cloned().fold(f64::MAX, f64::min);
        let down = (1..pitch.len())
            .find(|&k| pitch[k - 1] > 0.0 && pitch[k] <= 0.0)
            .map(|k| t[k - 1] + (t[k] - t[k - 1]) * pitch[k - 1] / (pitch[k - 1] - pitch[k]));
        let m = &row.metrics;
        assert_eq!(m[0], Some(max));
        assert_eq!(m[1], Some(*pitch.last().unwrap()));
        assert!((m[2].unwrap() - down.unwrap()).abs() < 1e-12, "{:?} vs {down:?}", m[2]);
        assert_eq!(m[3], Some(min_wz));
        assert_eq!(m[4], report.deployed_90);
        assert_eq!(m[5], Some(report.drift.energy));
        assert_eq!(m[9], Some(report.steps_accepted as f64));
    }
}

/// The draws of the example's 1000 runs against their distributions. Bounds: 4 standard
/// errors of each mean (the seed is fixed, so this is one deterministic check, not a
/// flaky one; 4σ still fails a sampler that is wrong by a few percent).
#[test]
fn draws_follow_their_distributions() {
    let s = sweep_file(EXAMPLE);
    let n = s.runs() as f64;
    let draws: Vec<Vec<f64>> = (0..s.runs()).map(|i| s.values(i)).collect();
    let col = |k: usize| draws.iter().map(|d| d[k]).collect::<Vec<f64>>();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let sd = |v: &[f64]| (v.iter().map(|x| (x - mean(v)).powi(2)).sum::<f64>() / (v.len() as f64 - 1.0)).sqrt();
    // normal(10, 1)
    let k = col(0);
    assert!((mean(&k) - 10.0).abs() < 4.0 / n.sqrt(), "mean {}", mean(&k));
    assert!((sd(&k) - 1.0).abs() < 4.0 / (2.0 * n).sqrt(), "sd {}", sd(&k));
    // uniform [0, 0.5): in range, mean 0.25 ± 4 · 0.5/√12/√n
    let c = col(1);
    assert!(c.iter().all(|x| (0.0..0.5).contains(x)));
    assert!((mean(&c) - 0.25).abs() < 4.0 * 0.5 / 12f64.sqrt() / n.sqrt());
    // log-uniform [50, 200): ln uniform on [ln 50, ln 200)
    let l: Vec<f64> = col(2).iter().map(|x| x.ln()).collect();
    let (a, b) = (50f64.ln(), 200f64.ln());
    assert!(l.iter().all(|x| (a..b).contains(x)));
    assert!((mean(&l) - 0.5 * (a + b)).abs() < 4.0 * (b - a) / 12f64.sqrt() / n.sqrt());
    // choice of three: each a third, ± 4 √(p(1−p)/n)
    for v in [9.5, 10.0, 10.5] {
        let share = col(3).iter().filter(|x| **x == v).count() as f64 / n;
        assert!((share - 1.0 / 3.0).abs() < 4.0 * (2.0f64 / 9.0 / n).sqrt(), "{v}: {share}");
    }
    // The same run index gives the same values; runs differ.
    assert_eq!(s.values(17), s.values(17));
    assert_ne!(s.values(17), s.values(18));
}

#[test]
fn a_failed_run_is_recorded_and_the_sweep_goes_on() {
    // k_theta ~ normal(0.5, 1): about a third of the draws are negative, which the scenario
    // refuses; their rows say so, the others run.
    let s = with_table(
        EXAMPLE,
        "[sweep]\nruns = 30\nseed = 3\n[sweep.parameters]\n\"hinge.h1.law.k_theta\" = { distribution = \"normal\", mean = 0.5, sd = 1.0 }\n",
    )
    .unwrap();
    let rows = all_rows(&s, 2);
    assert_eq!(rows.len(), 30);
    let failed: Vec<_> = rows.iter().filter(|r| r.error.is_some()).collect();
    assert!(!failed.is_empty() && failed.len() < 30);
    for r in &rows {
        assert_eq!(r.error.is_some(), r.values[0] < 0.0, "run {}: {:?}", r.run, r.error);
        if let Some(e) = &r.error {
            assert!(e.contains("test.toml:") && e.contains("k_theta"), "{e}");
            assert!(r.metrics.iter().all(Option::is_none));
        }
    }
    // On the command line: the table has them as failed, with the reason.
    let dir = tmp("sweep", "failed");
    let file = dir.join("s.toml");
    let text = std::fs::read_to_string(repo(EXAMPLE)).unwrap().replace("mean = 10.0, sd = 1.0", "mean = 0.5, sd = 1.0");
    std::fs::write(&file, text).unwrap();
    let out = foldsim()
        .args(["sweep", file.to_str().unwrap(), "--runs", "20", "-o"])
        .arg(dir.join("o.csv"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let csv = std::fs::read_to_string(dir.join("o.csv")).unwrap();
    assert!(csv.contains(",failed,") && csv.contains("positive semidefinite"), "{csv}");
}

#[test]
fn latch_lock_and_deployment_metrics_are_the_runs_events() {
    // radial-spin: four panels latch; a list of spin rates.
    let s = with_table(
        "examples/radial-spin.toml",
        "[sweep]\n[sweep.parameters]\n\"initial.hub.omega_rpm.2\" = { distribution = \"list\", values = [10.0, 12.0] }\n[sweep.metrics]\nlatch_h3 = { latch = \"h3\" }\n",
    )
    .unwrap();
    assert_eq!(s.runs(), 2, "a list gives the run count");
    let rows = all_rows(&s, 2);
    for (row, rpm) in rows.iter().zip([10.0, 12.0]) {
        assert_eq!(row.values, vec![rpm]);
        let text = std::fs::read_to_string(repo("examples/radial-spin.toml")).unwrap();
        let mut t = ScenarioText::new(&text, "r", &repo("examples")).unwrap();
        t.set("initial.hub.omega_rpm.2", &SetValue::Number(rpm)).unwrap();
        let (_, _, report) = common::run(&t.build().unwrap());
        let latch =
            report.events.iter().find(|e| e.hinge == 2 && e.kind == foldsim::law::EventKind::Latch).map(|e| e.t);
        assert!(latch.is_some());
        assert_eq!(row.metrics[0], latch);
        assert_eq!(row.metrics[1], report.deployed_90);
    }
    assert!(rows[1].metrics[0] < rows[0].metrics[0], "spun faster, latched sooner");
    // hinged-panels-1dof: locked directions engage at the start.
    let s = with_table(
        "examples/hinged-panels-1dof.toml",
        "[sweep]\nruns = 2\nseed = 1\n[sweep.parameters]\n\"initial.hinge.h1.yaw_deg\" = { distribution = \"uniform\", low = 3.0, high = 6.0 }\n[sweep.metrics]\nlocked_h1 = { lock = \"h1\" }\n",
    )
    .unwrap();
    for row in all_rows(&s, 1) {
        let t = row.metrics[0].expect("h1's locks engage");
        assert!((0.0..1.0).contains(&t), "{t}");
    }
}

#[test]
fn bad_sweep_tables_are_refused_with_their_line_and_what_is_valid() {
    let p = "[sweep]\nruns = 10\nseed = 1\n[sweep.parameters]\n";
    for (table, says) in [
        (format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"gauss\", mean = 1.0, sd = 1.0 }}\n"), "one of normal, uniform"),
        (format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"normal\", mean = 1.0, sd = 0.0 }}\n"), "sd must be > 0"),
        (format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"log-uniform\", low = 0.0, high = 1.0 }}\n"), "0 < low < high"),
        (format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"uniform\", low = 1.0 }}\n"), "needs 'high'"),
        (format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"normal\", mean = 1.0, sd = 1.0, low = 2.0 }}\n"), "'low' does not apply"),
        (format!("{p}\"hinge.h9.law.k_theta\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n"), "no entry named 'h9'"),
        (format!("{p}\"run.nothing.x\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n"), "no key 'nothing'"),
        (
            format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n[sweep.metrics]\nm = {{ column = \"h7_yaw\", stat = \"max\" }}\n"),
            "no output column named 'h7_yaw'",
        ),
        (
            format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n[sweep.metrics]\nm = {{ column = \"h1_yaw\", stat = \"mean\" }}\n"),
            "final, min or max",
        ),
        (
            "[sweep]\nruns = 10\n[sweep.parameters]\n\"hinge.h1.law.k_theta\" = { distribution = \"uniform\", low = 1.0, high = 2.0 }\n".into(),
            "needs 'seed'",
        ),
        (
            "[sweep]\nruns = 0\nseed = 1\n[sweep.parameters]\n\"hinge.h1.law.k_theta\" = { distribution = \"uniform\", low = 1.0, high = 2.0 }\n".into(),
            "1 to 10000000 runs",
        ),
        ("[sweep]\nruns = 3\n[sweep.parameters]\n\"hinge.h1.law.k_theta\" = { distribution = \"list\", values = [1.0, 2.0] }\n".into(), "must agree"),
        ("[sweep]\nrun = 3\n".into(), "unknown key 'sweep.run'"),
        // Paths that would give silently wrong or failed runs: two spellings of one value,
        // the [sweep] table itself, a string, a misspelt key.
        (
            format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n\"hinge.*.law.k_theta\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n"),
            "'hinge.h1.law.k_theta' and 'hinge.*.law.k_theta' both set hinge.0.law.k_theta",
        ),
        (
            format!("{p}\"body.panel.mass\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n\"body.1.mass\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n"),
            "both set body.1.mass",
        ),
        (format!("{p}\"sweep.runs\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n"), "inside [sweep] itself"),
        (format!("{p}\"run.integrator\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n"), "holds \"dop853\": a sweep draws numbers"),
        (format!("{p}\"hinge.h1.law.k_thetaa\" = {{ distribution = \"uniform\", low = 1.0, high = 2.0 }}\n"), "'hinge.h1.law.k_thetaa' is not in the scenario"),
        ("[sweep]\nruns = 3\nseed = 1\n".into(), "at least one entry"),
    ] {
        let e = with_table(EXAMPLE, &table).err().unwrap_or_else(|| panic!("accepted: {table}"));
        assert!(e.contains(says), "{table}\n→ {e}");
        assert!(e.starts_with("test.toml"), "names the file: {e}");
    }
    // Located: the line of the offending entry.
    let e = with_table(
        EXAMPLE,
        &format!("{p}\"hinge.h1.law.k_theta\" = {{ distribution = \"normal\", mean = 1.0, sd = -1.0 }}\n"),
    )
    .unwrap_err();
    let lines = std::fs::read_to_string(repo(EXAMPLE))
        .unwrap()
        .find("\n[sweep]")
        .map(|i| std::fs::read_to_string(repo(EXAMPLE)).unwrap()[..i].lines().count())
        .unwrap();
    assert!(e.starts_with(&format!("test.toml:{}:", lines + 5)), "{e}");
    // A scenario without [sweep]; and --workers 0.
    let out = foldsim()
        .args(["sweep", repo("examples/paper-1panel.toml").to_str().unwrap(), "-o", "/dev/null"])
        .output()
        .unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("no [sweep] table"));
    let out = foldsim().args(["sweep", repo(EXAMPLE).to_str().unwrap(), "--workers", "0"]).output().unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("--workers"));
}

/// A key the scenario leaves out but accepts (a default) may be swept.
#[test]
fn a_key_left_at_its_default_may_be_swept() {
    let s = with_table(
        EXAMPLE,
        "[sweep]\nruns = 2\nseed = 1\n[sweep.parameters]\n\"run.max_steps\" = { distribution = \"choice\", values = [100000, 200000] }\n",
    )
    .unwrap();
    assert!(all_rows(&s, 1).iter().all(|r| r.error.is_none()));
}

/// A sweep whose every run fails exits with failure and the first error; many workers for
/// few runs are capped at the run count, and it says so.
#[test]
fn a_sweep_that_fails_everywhere_fails_and_workers_are_capped() {
    let dir = tmp("sweep", "allfail");
    let file = dir.join("s.toml");
    let text =
        std::fs::read_to_string(repo(EXAMPLE)).unwrap().replace("mean = 10.0, sd = 1.0", "mean = -10.0, sd = 1.0");
    std::fs::write(&file, text).unwrap();
    let out =
        foldsim().args(["sweep", file.to_str().unwrap(), "--runs", "4", "-o"]).arg(dir.join("o.csv")).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(stderr.contains("every run failed") && stderr.contains("run 0:") && stderr.contains("k_theta"), "{stderr}");
    let out = foldsim()
        .args(["sweep", repo(EXAMPLE).to_str().unwrap(), "--runs", "3", "--workers", "10000", "-o"])
        .arg(dir.join("w.csv"))
        .output()
        .unwrap();
    let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{all}");
    assert!(all.contains("10000 workers for 3 runs: using 3"), "{all}");
}

/// `foldsim run` on a sweep file runs its nominal scenario.
#[test]
fn a_sweep_file_runs_as_its_nominal_scenario() {
    let sweep = common::scenario(EXAMPLE);
    let nominal = common::scenario("examples/paper-1panel.toml");
    let (a, _, _) = common::run(&sweep);
    let (b, _, _) = common::run(&nominal);
    assert_eq!(a.rows, b.rows);
}

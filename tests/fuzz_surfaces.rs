//! Fuzzing the surfaces beyond the scenario reader (`tests/fuzz.rs` has that one): sweep
//! tables, generator options and CSV read-back. Every input must end in a result or a
//! refusal in words that names what is wrong; never a panic, never a run that outlives its
//! bound, never a generated scenario that the loader then refuses, never a sweep row that
//! records an internal error.
//!
//! As a test each target takes a small budget (seconds); as a longer command:
//!
//!     FOLDSIM_FUZZ_INPUTS=5000 FOLDSIM_FUZZ_SEED=7 cargo test --release --test fuzz_surfaces -- --nocapture
//!
//! The Python values are fuzzed by `python/tests/test_fuzz.py` (same variables).

mod common;

use common::fuzz::{EXTREMES, Rng};
use foldsim::generate::Params;
use foldsim::generate::options::{FlasherOptions, grid_checked, hinge_axes, panel_model, zfold_checked};
use foldsim::scenario::{Scenario, ScenarioText};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

fn budget(default: usize) -> (usize, Rng, u64) {
    let n = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(default);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    (n, Rng(0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9)), seed)
}

/// Numbers as a fuzzer offers them: the extremes, ordinary values, and their negatives.
const NUMBERS: &[f64] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    2.0,
    10.0,
    1e-300,
    -1e-300,
    1e300,
    -1e300,
    1e19,
    1e-16,
    3.0e38,
    6.5,
    720.0,
    1e5,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MAX,
    f64::MIN_POSITIVE,
];

/// A short, runnable nominal scenario for sweeps: paper-1panel over 0.2 s.
fn nominal() -> String {
    std::fs::read_to_string(common::repo("examples/paper-1panel.toml"))
        .unwrap()
        .replace("duration = 20.0", "duration = 0.2")
}

const PATHS: &[&str] = &[
    "hinge.h1.law.k_theta",
    "hinge.h1.law.k_f",
    "hinge.*.law.c_f",
    "hinge.h?.law.c_theta",
    "hinge.0.law.k_theta",
    "body.panel.mass",
    "body.1.mass",
    "body.hub.inertia.2",
    "body.hub.inertia.9",
    "run.duration",
    "run.output_step",
    "run.integrator",
    "run.rtol",
    "run.max_steps",
    "initial.hub.omega.2",
    "initial.hinge.h1.delta.0",
    "title",
    "sweep.runs",
    "hinge.h9.law.k_f",
    "hinge.h1.law.nothing",
    "nothing.at.all",
    "hinge..law",
    "hinge.h1.law.k_theta.0.1",
    "body",
    "",
];

const DISTRIBUTIONS: &[&str] = &["normal", "uniform", "log-uniform", "choice", "list", "gauss", ""];
const KEYS: &[&str] = &["mean", "sd", "low", "high", "values", "distribution", "extra"];

fn number(rng: &mut Rng) -> String {
    let x = *rng.pick(NUMBERS);
    if rng.below(3) == 0 { rng.pick(EXTREMES).to_string() } else { toml_number(x) }
}

fn toml_number(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{x:?}")
    }
}

/// A random `[sweep]` table.
fn sweep_table(rng: &mut Rng) -> String {
    let mut t = String::from("[sweep]\n");
    if rng.below(6) != 0 {
        let runs = if rng.below(2) == 0 { "2" } else { rng.pick(&["1", "3", "0", "-1", "1e9", "2.5", "\"x\""]) };
        t.push_str(&format!("runs = {runs}\n"));
    }
    if rng.below(6) != 0 {
        let seed = if rng.below(2) == 0 { "1" } else { rng.pick(&["0", "-5", "18446744073709551615", "1.5", "\"s\""]) };
        t.push_str(&format!("seed = {seed}\n"));
    }
    t.push_str("[sweep.parameters]\n");
    for _ in 0..rng.below(4) {
        let path = rng.pick(PATHS);
        if rng.below(2) == 0 {
            // A well-formed entry with ordinary or extreme numbers: these get to run.
            let path = rng.pick(&["hinge.h1.law.k_theta", "hinge.*.law.c_f", "body.panel.mass", "initial.hub.omega.2"]);
            let (a, b) = (rng.pick(&[0.5, 1.0, 2.0, -1.0, 1e-300, 1e300]), rng.pick(&[3.0, 10.0, 0.1, 1e300]));
            let entry = match rng.below(4) {
                0 => format!("distribution = \"normal\", mean = {a:?}, sd = {b:?}"),
                1 => format!("distribution = \"uniform\", low = {a:?}, high = {b:?}"),
                2 => format!("distribution = \"log-uniform\", low = {a:?}, high = {b:?}"),
                _ => format!("distribution = \"choice\", values = [{a:?}, {b:?}]"),
            };
            t.push_str(&format!("\"{path}\" = {{ {entry} }}\n"));
            continue;
        }
        let mut fields = vec![format!("distribution = \"{}\"", rng.pick(DISTRIBUTIONS))];
        for _ in 0..rng.below(4) {
            let key = rng.pick(KEYS);
            let value = if *key == "values" {
                let n = rng.below(4);
                format!("[{}]", (0..n).map(|_| number(rng)).collect::<Vec<_>>().join(", "))
            } else {
                number(rng)
            };
            fields.push(format!("{key} = {value}"));
        }
        t.push_str(&format!("\"{path}\" = {{ {} }}\n", fields.join(", ")));
    }
    if rng.below(2) == 0 {
        t.push_str("[sweep.metrics]\n");
        for i in 0..rng.below(3) {
            let column = rng.pick(&["h1_yaw", "h1_pitch", "E", "nope", "deployed", "t"]);
            let what = match rng.below(4) {
                0 => format!("stat = \"{}\"", rng.pick(&["max", "min", "final", "mean"])),
                1 => format!("crosses = {}", number(rng)),
                2 => format!("latch = \"{}\"", rng.pick(&["h1", "h9"])),
                _ => String::new(),
            };
            t.push_str(&format!("m{i} = {{ column = \"{column}\", {what} }}\n"));
        }
    }
    t
}

#[test]
fn fuzzed_sweep_tables_are_refused_in_words_or_run_to_the_end() {
    let (n, mut rng, seed) = budget(400);
    let base = nominal();
    let (mut refused, mut swept, mut rows) = (0, 0, 0);
    let started = Instant::now();
    for i in 0..n {
        let table = sweep_table(&mut rng);
        let text = format!("{base}\n{table}");
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let text = ScenarioText::new(&text, "fuzz.toml", &common::repo("examples")).map_err(|e| e.to_string())?;
            let mut sweep = foldsim::sweep::Sweep::new(text).map_err(|e| e.to_string())?;
            if sweep.runs() > 3 {
                let _ = sweep.set_runs(3);
            }
            let mut out = Vec::new();
            let take = sweep.runs().min(3);
            sweep
                .run(0..take, 2, &AtomicBool::new(false), &mut |row| {
                    out.push(row);
                    Ok(())
                })
                .map_err(|e| format!("the sweep stopped: {e}"))?;
            Ok::<_, String>(out)
        }));
        match outcome {
            Err(_) => panic!("seed {seed} input {i}: the sweep panicked on:\n{table}"),
            Ok(Err(e)) => {
                assert!(e.starts_with("fuzz.toml"), "seed {seed} input {i}: an error that names no file: {e}\n{table}");
                refused += 1;
            }
            Ok(Ok(out)) => {
                swept += 1;
                for r in out {
                    rows += 1;
                    if let Some(e) = &r.error {
                        assert!(!e.contains("internal error"), "seed {seed} input {i}: run {}: {e}\n{table}", r.run);
                    }
                }
            }
        }
    }
    eprintln!(
        "fuzz sweep tables (seed {seed}): {n} inputs: {refused} refused in words, {swept} swept ({rows} runs) in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert!(swept > 0 && refused > 0, "the fuzzer reaches both outcomes");
}

/// A generator option's name as the library reports it (Python's spelling).
fn key(k: &str) -> String {
    k.to_string()
}

const OPTION_KEYS: &[&str] = &[
    "panel_mass",
    "panel_length",
    "panel_width",
    "k_translation",
    "k_bending",
    "k_fold",
    "fold_deg",
    "duration",
    "output_step",
    "tolerance",
    "hub_radius",
    "thickness",
    "areal_density",
    "hub_mass",
    "hub_inertia",
    "panels",
    "c_fold",
    "k_panel_bending",
    "c_panel_bending",
    "c_translation",
    "c_rotation",
    "k_stop",
    "membrane_bending",
    "membrane_width",
    "membrane_damping_ratio",
    "spin_rpm",
    "integrator",
    "release_at",
    "gores",
    "rings",
    "rows",
    "cols",
];

/// A generated scenario that is accepted must load and start; a refusal must name an option.
fn judge(what: &str, result: Result<String, String>, accepted: &mut usize, refused: &mut usize) {
    match result {
        Ok(text) => {
            let s = Scenario::from_toml(&text, "generated")
                .unwrap_or_else(|e| panic!("{what}: the generator wrote a scenario the loader refuses: {e}"));
            let e = foldsim::simulate::estimate::estimate(&s.model, &s.initial, &s.settings, Duration::from_millis(50));
            assert!(e.projected() > 0.0, "{what}: {e:?}");
            *accepted += 1;
        }
        Err(m) => {
            assert!(OPTION_KEYS.iter().any(|k| m.contains(k)), "{what}: a refusal that names no option: {m}");
            *refused += 1;
        }
    }
}

#[test]
fn fuzzed_generator_options_give_loadable_scenarios_or_name_the_option() {
    let (n, mut rng, seed) = budget(400);
    let (mut accepted, mut refused) = (0, 0);
    let started = Instant::now();
    for i in 0..n {
        // Mostly sensible values with one or two fuzzed, so both outcomes are reached.
        let pick = |rng: &mut Rng, sensible: f64| if rng.below(4) == 0 { *rng.pick(NUMBERS) } else { sensible };
        let what = format!("seed {seed} input {i}");
        let outcome = catch_unwind(AssertUnwindSafe(|| match rng.below(3) {
            0 | 1 => {
                let p = Params {
                    panel_mass: pick(&mut rng, 2.0),
                    panel_length: pick(&mut rng, 1.0),
                    panel_width: pick(&mut rng, 0.5),
                    k_translation: pick(&mut rng, 1e6),
                    k_bending: pick(&mut rng, 1e3),
                    k_fold: pick(&mut rng, 1.0),
                    fold_deg: pick(&mut rng, 30.0),
                    duration: pick(&mut rng, 0.2),
                    output_step: pick(&mut rng, 0.01),
                    tolerance: pick(&mut rng, 1e-8),
                };
                let size = *rng.pick(&[0usize, 1, 2, 3, 5, 100_001, usize::MAX]);
                if rng.below(2) == 0 {
                    (format!("{what} zfold {size} {p:?}"), zfold_checked(size, &p, &key))
                } else {
                    let cols = *rng.pick(&[0usize, 1, 2, 3, 1_000_000]);
                    (format!("{what} grid {size}×{cols} {p:?}"), grid_checked(size, cols, &p, &key))
                }
            }
            _ => {
                let mut o = FlasherOptions {
                    gores: *rng.pick(&[0usize, 2, 3, 4, 6, 1001, usize::MAX]),
                    rings: *rng.pick(&[0usize, 1, 2, 1_000_000, usize::MAX]),
                    duration: 0.2,
                    ..FlasherOptions::default()
                };
                o.hub_radius = pick(&mut rng, 1.0);
                // Thick a third of the time (the crease stops and contact are written then).
                let thick = if rng.below(3) == 0 { 0.01 } else { 0.0 };
                o.thickness = pick(&mut rng, thick);
                o.laws.k_stop = pick(&mut rng, 1e4);
                o.laws.membrane_bending = pick(&mut rng, 3e-5);
                o.laws.membrane_width = if rng.below(2) == 0 { None } else { Some(pick(&mut rng, 0.05)) };
                o.laws.membrane_damping_ratio = pick(&mut rng, 0.5);
                o.areal_density = pick(&mut rng, 1.0);
                o.hub_mass = pick(&mut rng, 100.0);
                o.spin_rpm = pick(&mut rng, 0.0);
                o.duration = pick(&mut rng, 0.2);
                // Left out a quarter of the time: the default then follows the thickness.
                o.tolerance = if rng.below(4) == 0 { None } else { Some(pick(&mut rng, 1e-8)) };
                let integrators = [None, Some("dop853"), Some("sdirk4"), Some("auto"), Some("rk9"), Some("")];
                o.integrator = rng.pick(&integrators).map(String::from);
                o.laws.k_fold = pick(&mut rng, 1.0);
                o.laws.k_bending = pick(&mut rng, 0.1);
                o.laws.c_translation = pick(&mut rng, 10.0);
                // Left out half the time: the fold damping then follows the thickness.
                o.laws.c_fold = if rng.below(2) == 0 { None } else { Some(pick(&mut rng, 0.05)) };
                if rng.below(4) == 0 {
                    o.hub_inertia = Some([pick(&mut rng, 25.0), pick(&mut rng, 25.0), pick(&mut rng, 50.0)]);
                }
                if rng.below(4) == 0 {
                    o.release_at = Some(pick(&mut rng, 0.1));
                }
                if rng.below(4) == 0 {
                    o.output_step = Some(pick(&mut rng, 0.01));
                }
                const MODELS: [&str; 3] = ["triangles", "quads", "ring-quads"];
                let model = MODELS[rng.below(3)];
                o.panels = panel_model(model).unwrap();
                // The hinge axes by name, as the command line gives them: a wrong name is
                // refused naming the valid ones.
                let axes = *rng.pick(&["shifted", "mid-plane", "", "Shifted", "membrane", "mid_plane"]);
                match hinge_axes(axes) {
                    Ok(h) => o.hinge_axes = h,
                    Err(m) => assert!(m.contains("shifted or mid-plane"), "{what}: {m}"),
                }
                (format!("{what} flasher {o:?}"), o.scenario(&key).map(|(text, _)| text))
            }
        }));
        let Ok((what, result)) = outcome else { panic!("seed {seed} input {i}: a generator panicked") };
        judge(&what, result, &mut accepted, &mut refused);
    }
    eprintln!(
        "fuzz generator options (seed {seed}): {n} inputs: {accepted} written and loaded, {refused} refused by option name in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert!(accepted > 0 && refused > 0, "the fuzzer reaches both outcomes");
}

/// A finished run's CSV, mutated: fields replaced, lines dropped, swapped or cut, columns
/// renamed. Reading it back for an animation and a page must end in frames or an error.
#[cfg(feature = "animation")]
#[test]
fn fuzzed_csv_read_back_ends_in_frames_or_an_error() {
    use foldsim::output::animation::{Table, frames_from_table};
    let (n, mut rng, seed) = budget(300);
    let scenario = common::scenario("examples/paper-3panel.toml");
    let dir = common::tmp("fuzz", "csv");
    let csv = dir.join("run.csv");
    let text = {
        let s = Scenario::from_toml(
            &std::fs::read_to_string(common::repo("examples/paper-3panel.toml"))
                .unwrap()
                .replace("duration = 20.0", "duration = 0.5"),
            "p",
        )
        .unwrap();
        let mut sink = foldsim::output::CsvSink::create(&csv, &s.columns).unwrap();
        foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap();
        sink.finish().unwrap();
        std::fs::read_to_string(&csv).unwrap()
    };
    let lines: Vec<&str> = text.lines().collect();
    let (mut framed, mut refused) = (0, 0);
    for i in 0..n {
        let out = mutated_csv(&lines, &mut rng, &["hub_q_w", "p1_R_x", "t", "p2_yaw"]);
        let file = dir.join("fuzz.csv");
        std::fs::write(&file, out.join("\n")).unwrap();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let table = Table::read(&file)?;
            let (frames, kept, _) = frames_from_table(&scenario.model, &table, None)?;
            foldsim::output::viewer::page("fuzz", &scenario.model, &table, &frames, &kept, &[])?;
            Ok::<_, String>(())
        }));
        match outcome {
            Err(_) => panic!("seed {seed} input {i}: read-back panicked on:\n{}", out.join("\n")),
            Ok(Ok(())) => framed += 1,
            Ok(Err(e)) => {
                assert!(!e.is_empty() && !e.contains("Error {") && !e.contains("{ kind"), "seed {seed} input {i}: {e}");
                refused += 1;
            }
        }
    }
    eprintln!("fuzz CSV read-back (seed {seed}): {n} inputs: {framed} animated, {refused} refused in words");
    assert!(framed > 0 && refused > 0, "the fuzzer reaches both outcomes");
}

/// A finished run's CSV lines with one to three mutations: a field replaced, a line dropped,
/// swapped, cut, lengthened or repeated, or one of `columns` renamed in the header.
fn mutated_csv(lines: &[&str], rng: &mut Rng, columns: &[&str]) -> Vec<String> {
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    for _ in 0..1 + rng.below(3) {
        let k = rng.below(out.len());
        match rng.below(7) {
            0 => {
                let mut f: Vec<String> = out[k].split(',').map(str::to_string).collect();
                let j = rng.below(f.len());
                f[j] = rng
                    .pick(&["nan", "inf", "-inf", "", "x", "1e308", "-1e308", "0", "1e-320", "  3  ", "1e200", "-7"])
                    .to_string();
                out[k] = f.join(",");
            }
            1 => {
                out.remove(k);
                if out.is_empty() {
                    out.push(String::new());
                }
            }
            2 => {
                let j = rng.below(out.len());
                out.swap(k, j);
            }
            3 => {
                let cut = rng.below(out[k].len() + 1);
                out[k].truncate(cut);
            }
            4 => out[k].push_str(",9"),
            5 => out[0] = out[0].replacen(rng.pick(columns), "zz", 1),
            _ => out.insert(k, out[k].clone()),
        }
    }
    out
}

/// A contact run's CSV, mutated as above (`mutated_csv`), its poses measured for overlaps
/// (`foldsim overlaps`, `foldsim::verify::overlap`) both ways: it must end in a measure or
/// an error in words, never a panic.
#[test]
fn fuzzed_csv_overlap_checks_end_in_a_measure_or_an_error() {
    use foldsim::output::table::{Table, poses_from_table};
    use foldsim::verify::overlap::{Solids, deepest_overlaps};
    let (n, mut rng, seed) = budget(300);
    let text = std::fs::read_to_string(common::repo("examples/contact-panel-hub.toml"))
        .unwrap()
        .replace("output_step = 0.005", "output_step = 0.05");
    let scenario = Scenario::from_toml(&text, "panel-hub").unwrap();
    let dir = common::tmp("fuzz", "overlaps");
    let csv = dir.join("run.csv");
    let mut sink = foldsim::output::CsvSink::create(&csv, &scenario.columns).unwrap();
    foldsim::simulate::simulate(&scenario.model, &scenario.initial, &scenario.settings, &mut sink, None).unwrap();
    sink.finish().unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let (mut measured, mut refused) = (0, 0);
    for i in 0..n {
        let out = mutated_csv(&lines, &mut rng, &["hub_q_w", "panel_R_x", "t", "panel_q_z", "hub_R_z"]);
        let file = dir.join("fuzz.csv");
        std::fs::write(&file, out.join("\n")).unwrap();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let table = Table::read(&file)?;
            let (poses, _) = poses_from_table(&scenario.model, &table)?;
            for kind in [Solids::Sampled, Solids::Sharp] {
                deepest_overlaps(&scenario.model, &poses, kind, None)?;
            }
            Ok::<_, String>(())
        }));
        match outcome {
            Err(_) => panic!("seed {seed} input {i}: the overlap check panicked on:\n{}", out.join("\n")),
            Ok(Ok(())) => measured += 1,
            Ok(Err(e)) => {
                assert!(!e.is_empty() && !e.contains("Error {") && !e.contains("{ kind"), "seed {seed} input {i}: {e}");
                refused += 1;
            }
        }
    }
    eprintln!("fuzz overlap checks (seed {seed}): {n} inputs: {measured} measured, {refused} refused in words");
    assert!(measured > 0 && refused > 0, "the fuzzer reaches both outcomes");
}

//! Fuzzing the scenario reader and the run: mutations of every example and generated scenario,
//! and hand-made extremes. Every input must end in a result or in an error that names where
//! (a line and column, or the body, hinge or key); never a panic, never a run that outlives
//! its bound.
//!
//! As a test it runs a small budget (the extremes and 400 mutations); as a longer command:
//!
//!     FOLDSIM_FUZZ_INPUTS=20000 FOLDSIM_FUZZ_SEED=7 cargo test --release --test fuzz -- --nocapture
//!
//! Runs are capped at 20,000 steps each (their own step budget is usually larger: the cap
//! keeps the harness fast and is itself the bound checked: a run must stop there with a
//! message), and each input has 20 s of wall time before it counts as stuck.

mod common;

use common::fuzz::{EXTREMES, Rng};

use foldsim::scenario::Scenario;
use std::ops::ControlFlow;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Steps a fuzzed run may take.
const STEP_CAP: usize = 20_000;

/// Wall time after which a run that is stepping is stopped (it counts as run).
const RUN_WALL: Duration = Duration::from_secs(2);

/// Wall time an input may take before it counts as stuck.
const STUCK: Duration = Duration::from_secs(20);

/// Seeds: every example (with its directory, for its table files) and generated structures.
fn seeds() -> Vec<(String, String)> {
    let mut out = Vec::new();
    let dir = common::repo("examples");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    for f in files.into_iter().filter(|f| f.extension().is_some_and(|e| e == "toml")) {
        out.push((f.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read_to_string(&f).unwrap()));
    }
    let p = foldsim::generate::Params { duration: 1.0, ..Default::default() };
    out.push(("zfold3".into(), foldsim::generate::zfold(3, &p)));
    out.push(("grid2x3".into(), foldsim::generate::grid(2, 3, &p)));
    // run.position_tolerance, for the mutations to reach its key.
    let z = foldsim::generate::zfold(3, &p).replacen("rtol = 1e-8\natol = 1e-8", "position_tolerance = 1e-4", 1);
    assert!(z.contains("position_tolerance"), "the z-fold's [run] table changed: update this seed");
    out.push(("zfold3-ptol".into(), z));
    // A small thick flasher: contact, crease stops and membrane hinges (band stops).
    let o = foldsim::generate::options::FlasherOptions {
        gores: 3,
        rings: 1,
        thickness: 0.01,
        duration: 0.5,
        ..Default::default()
    };
    let (thick, _) = o.scenario(&|k: &str| k.to_string()).expect("a small thick flasher");
    assert!(thick.contains("free = \"within\""), "the thick flasher has no membrane hinges: update this seed");
    out.push(("flasher3x1-thick".into(), thick));
    // A table's scale (docs/scenario.md), for the mutations to reach its key.
    let tape = std::fs::read_to_string(dir.join("zfold-tape-latch.toml")).unwrap();
    let scaled = tape.replacen(
        "interpolation = \"linear\", outside = \"extend\" }",
        "interpolation = \"linear\", outside = \"extend\", scale = 1.1 }",
        2,
    );
    assert!(scaled.contains("scale = 1.1"), "the tape-latch example's tables changed: update this seed");
    out.push(("zfold-tape-latch-scaled".into(), scaled));
    out
}

/// One mutation of `text`.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let mut lines: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    if lines.is_empty() {
        return String::new();
    }
    let k = rng.below(lines.len());
    match rng.below(8) {
        // A number, word or value replaced (the most telling mutation: three times as often).
        0..=2 => {
            let line = &lines[k];
            let tokens: Vec<(usize, usize)> = token_spans(line);
            if let Some(&(a, b)) = (!tokens.is_empty()).then(|| rng.pick(&tokens)) {
                let mut l = line.clone();
                let value = *rng.pick::<&str>(EXTREMES);
                l.replace_range(a..b, value);
                lines[k] = l;
            }
        }
        3 => {
            lines.remove(k);
        }
        4 => {
            let l = lines[k].clone();
            lines.insert(k, l);
        }
        5 => {
            let j = rng.below(lines.len());
            lines.swap(k, j);
        }
        6 => {
            // A key renamed to another key of the file.
            let keys: Vec<String> =
                lines.iter().filter_map(|l| l.split_once('=').map(|(key, _)| key.trim().to_string())).collect();
            if let (Some((_, value)), false) = (lines[k].split_once('='), keys.is_empty()) {
                lines[k] = format!("{} = {}", rng.pick(&keys), value.trim());
            }
        }
        _ => {
            // Truncated.
            lines.truncate(k);
        }
    }
    lines.join("\n")
}

/// Byte spans of the numbers and bare or quoted words after a line's `=` or inside its
/// brackets.
fn token_spans(line: &str) -> Vec<(usize, usize)> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let start = line.find('=').map_or(0, |i| i + 1);
    let mut i = start;
    while i < b.len() {
        let c = b[i];
        if c == b'"' {
            let end = line[i + 1..].find('"').map_or(b.len(), |e| i + 2 + e);
            out.push((i, end.min(b.len())));
            i = end;
        } else if c.is_ascii_alphanumeric() || c == b'-' || c == b'.' {
            let mut j = i;
            while j < b.len() && (b[j].is_ascii_alphanumeric() || b"-.+_".contains(&b[j])) {
                j += 1;
            }
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// What became of one input.
#[derive(Debug, PartialEq)]
enum Outcome {
    /// Refused at load, or a run that stopped, with a located message.
    Located,
    /// Loaded and ran to its end (or to the step cap, saying so).
    Ran,
    /// A panic, a message without a location, or a run that did not end.
    Bad(String),
}

/// Whether an error message says where: a `file:line:col:` prefix, or a named body, hinge,
/// key, table (a missing `[[body]]`) or the initial state.
fn located(message: &str, has_line: bool) -> bool {
    has_line
        || [
            "body '",
            "hinge '",
            "'run.",
            "run.",
            "initial.",
            "law.",
            "the initial state",
            "column",
            "[[body]]",
            "[run]",
        ]
        .iter()
        .any(|w| message.contains(w))
}

/// With FOLDSIM_FUZZ_SHOW set, every message is printed (to read them, not only count them).
fn show(message: &str) {
    if std::env::var_os("FOLDSIM_FUZZ_SHOW").is_some() {
        eprintln!("MSG {}", message.lines().next().unwrap_or(""));
    }
}

fn check(name: &str, text: &str) -> Outcome {
    let dir = common::repo("examples");
    let loaded = catch_unwind(|| Scenario::from_toml_in(text, name, &dir));
    let mut s = match loaded {
        Err(_) => return Outcome::Bad(format!("{name}: the reader panicked on:\n{text}")),
        Ok(Err(e)) => {
            let shown = e.to_string();
            show(&shown);
            return if shown.starts_with(name) && located(&e.message, e.location.is_some()) {
                Outcome::Located
            } else {
                Outcome::Bad(format!("{name}: a message without a location: {shown}\n--- input:\n{text}"))
            };
        }
        Ok(Ok(s)) => s,
    };
    s.settings.max_steps = Some(s.settings.max_steps.unwrap_or(usize::MAX).min(STEP_CAP));
    let ran = catch_unwind(AssertUnwindSafe(|| {
        let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> { Ok(()) };
        // Long runs (the large flasher) are stopped after RUN_WALL: what is tested is that
        // they start and step, not how they end.
        let start = Instant::now();
        let mut progress = |_: &foldsim::simulate::Progress<'_, '_>| {
            if start.elapsed() > RUN_WALL { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
        };
        foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, Some(&mut progress))
    }));
    match ran {
        Err(_) => Outcome::Bad(format!("{name}: the run panicked on:\n{text}")),
        Ok(Ok(_)) | Ok(Err(foldsim::simulate::SimError::Interrupted { .. })) => Outcome::Ran,
        Ok(Err(e)) => {
            let m = e.to_string();
            show(&m);
            // A run's errors say when (t = …) and name what stopped it; one refused before
            // its first step (a loop of locked hinges the restraint closed) names the hinges.
            if (m.contains("t = ")
                && (m.contains("hinge '") || m.contains("body '") || m.contains("steps") || m.contains("pitch")))
                || m.contains("run.position_tolerance")
                || m.contains("hinge '")
            {
                Outcome::Located
            } else {
                Outcome::Bad(format!("{name}: a run error that names nothing: {m}\n--- input:\n{text}"))
            }
        }
    }
}

/// Runs `check` with a watchdog: an input that takes longer than [`STUCK`] is reported and
/// the harness stops (a stuck thread cannot be killed).
fn check_in_time(name: String, text: String) -> (Outcome, Duration) {
    let (tx, rx) = mpsc::channel();
    let (n, t) = (name.clone(), text.clone());
    let start = Instant::now();
    std::thread::spawn(move || {
        let _ = tx.send(check(&n, &t));
    });
    match rx.recv_timeout(STUCK) {
        Ok(o) => (o, start.elapsed()),
        Err(_) => {
            eprintln!("{name}: stuck for {STUCK:?} on:\n{text}");
            std::process::exit(101);
        }
    }
}

/// The reliability review's hand-made extremes, each on the 3-panel z-fold.
fn extremes() -> Vec<(String, String)> {
    let base = foldsim::generate::zfold(3, &foldsim::generate::Params { duration: 1.0, ..Default::default() });
    let edits: &[(&str, &str, &str)] = &[
        ("mass 1e-300", "mass = 2.0", "mass = 1e-300"),
        ("stiffness 1e300", "k_f = 1e6", "k_f = 1e300"),
        ("stiffness 1e12", "k_f = 1e6", "k_f = 1e12"),
        ("bending 1e12", "k_theta = [1e3", "k_theta = [1e12"),
        ("child_com 1e300", "child_com = [0.5, 0.0, 0.0]", "child_com = [1e300, 0.0, 0.0]"),
        ("offset 1e5", "position = [0.5, 0.0, 0.0]", "position = [1e5, 0.0, 0.0]"),
        ("offset 1e19", "position = [0.5, 0.0, 0.0]", "position = [1e19, 0.0, 0.0]"),
        ("inertia 1e-12", "mass = 2.0\nshape", "mass = 2.0\ninertia = [1e-12, 1e-12, 1e-12]\n# shape"),
        ("tolerances 1e-20", "rtol = 1e-8\natol = 1e-8", "rtol = 1e-20\natol = 1e-20"),
        ("atol 1e-30", "atol = 1e-8", "atol = 1e-30"),
        ("yaw 1e17 deg", "yaw_deg = 30.0", "yaw_deg = 1e17"),
        ("yaw 1e17 rad", "yaw_deg = 30.0", "yaw = 1e17"),
        ("rk4 step 1e-300", "integrator = \"dop853\"\nrtol = 1e-8\natol = 1e-8", "integrator = \"rk4\"\nstep = 1e-300"),
        (
            "adaptive generalized-alpha 1e-20",
            "integrator = \"dop853\"\nrtol = 1e-8\natol = 1e-8",
            "integrator = \"generalized-alpha\"\nrtol = 1e-20\natol = 1e-20",
        ),
        (
            "adaptive generalized-alpha rho 0, stiff",
            "integrator = \"dop853\"\nrtol = 1e-8\natol = 1e-8",
            "integrator = \"generalized-alpha\"\nrho_inf = 0.0\nrtol = 1e-3\natol = 1e-3",
        ),
        ("adaptive generalized-alpha at 1e-8", "integrator = \"dop853\"", "integrator = \"generalized-alpha\""),
        ("duration 1e12", "duration = 1.0", "duration = 1e12"),
        ("output step 1e-12", "output_step = 0.01", "output_step = 1e-12"),
        ("omega 1e300", "[initial.hinge.h1]", "[initial.hub]\nomega = [1e300, 0.0, 0.0]\n\n[initial.hinge.h1]"),
        ("velocity 1e300", "[initial.hinge.h1]", "[initial.hub]\nvelocity = [1e300, 0.0, 0.0]\n\n[initial.hinge.h1]"),
        ("lever 1e308", "position = [0.5, 0.0, 0.0]", "position = [1e308, 0.0, 0.0]"),
        ("max_steps 0", "atol = 1e-8", "atol = 1e-8\nmax_steps = 0"),
        ("position tolerance 1e-300", "rtol = 1e-8\natol = 1e-8", "position_tolerance = 1e-300"),
        ("position tolerance 1e300", "rtol = 1e-8\natol = 1e-8", "position_tolerance = 1e300"),
        ("position tolerance nan", "rtol = 1e-8\natol = 1e-8", "position_tolerance = nan"),
        ("position tolerance and rtol", "atol = 1e-8", "position_tolerance = 1e-4"),
        (
            "position tolerance, generalized-alpha",
            "integrator = \"dop853\"\nrtol = 1e-8\natol = 1e-8",
            "integrator = \"generalized-alpha\"\nposition_tolerance = 1e-5",
        ),
        (
            "position tolerance, rk4",
            "integrator = \"dop853\"\nrtol = 1e-8\natol = 1e-8",
            "integrator = \"rk4\"\nstep = 1e-3\nposition_tolerance = 1e-5",
        ),
    ];
    edits
        .iter()
        .map(|(name, from, to)| {
            assert!(base.contains(from), "{name}: the base has no '{from}'");
            (name.to_string(), base.replacen(from, to, 1))
        })
        .collect()
}

#[test]
fn fuzzed_inputs_end_with_a_result_or_a_located_reason() {
    let budget: usize = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(400);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    let seeds = seeds();
    let mut inputs = extremes();
    for i in 0..budget {
        let (name, text) = rng.pick(&seeds).clone();
        let mut text = mutate(&text, &mut rng);
        // Some inputs take two or three mutations.
        for _ in 0..rng.below(3) {
            text = mutate(&text, &mut rng);
        }
        inputs.push((format!("{name}#{i}"), text));
    }
    let (mut located, mut ran, mut bad) = (0, 0, Vec::new());
    let mut slowest = (Duration::ZERO, String::new());
    for (name, text) in inputs {
        let (outcome, took) = check_in_time(name.clone(), text);
        if took > slowest.0 {
            slowest = (took, name.clone());
        }
        match outcome {
            Outcome::Located => located += 1,
            Outcome::Ran => ran += 1,
            Outcome::Bad(why) => bad.push(why),
        }
    }
    eprintln!(
        "fuzz (seed {seed}): {} inputs: {ran} ran, {located} refused or stopped with a located message, {} bad; slowest {:?} ({})",
        ran + located + bad.len(),
        bad.len(),
        slowest.0,
        slowest.1
    );
    for b in &bad {
        eprintln!("BAD {}", b.lines().next().unwrap_or(""));
    }
    assert!(bad.is_empty(), "{} bad inputs; the first:\n{}", bad.len(), bad[0]);
}

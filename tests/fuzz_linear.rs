//! Fuzzing the linear commands (`foldsim equilibrium`, `modes`, `linearize`) as a user meets
//! them: the command line with arguments drawn from extremes and mistakes, on small examples.
//! Every call must end within its bound in a result without NaN, or a refusal in words
//! (clap's usage error, or `error:` and a message); never a panic, never a table left by a
//! refusal.
//!
//! As a test it takes a small budget; as a longer command:
//!
//!     FOLDSIM_FUZZ_INPUTS=2000 FOLDSIM_FUZZ_SEED=7 cargo test --release --test fuzz_linear -- --nocapture

mod common;

use common::fuzz::Rng;
use common::{foldsim, repo};
use std::process::Stdio;
use std::time::{Duration, Instant};

/// Wall time a call may take before it counts as stuck.
const STUCK: Duration = Duration::from_secs(60);

const SCENARIOS: &[&str] = &[
    "paper-1panel",
    "paper-3panel",
    "paper-3panel-euler",
    "radial-spin",
    "zfold-tape-latch",
    "contact-panel-hub",
    "contact-zfold",
    "zfold-motor-deploy",
    "hinged-panels-1dof",
    "flasher-small",
];

const NUMBERS: &[&str] =
    &["0", "-0", "1", "-1", "0.5", "2", "1e-300", "1e300", "1e160", "-1e160", "nan", "inf", "-inf", "3e38", "x", ""];

/// One call's arguments: the command, the scenario, and a few options.
fn call(rng: &mut Rng, out: &std::path::Path) -> Vec<String> {
    let cmd = *rng.pick(&["equilibrium", "modes", "linearize"]);
    let mut args = vec![cmd.to_string(), repo(&format!("examples/{}.toml", rng.pick(SCENARIOS))).display().to_string()];
    let ext = *rng.pick(&["csv", "npz", "toml", "gltf", "html", ""]);
    args.push("-o".into());
    args.push(out.with_extension(ext).display().to_string());
    // Mostly the command's own options; one in five of any command's (the parser's refusal).
    let own: &[usize] = match cmd {
        "equilibrium" => &[0, 5],
        "modes" => &[0, 1, 2, 3, 4, 8],
        _ => &[1, 2, 6, 7],
    };
    for _ in 0..rng.below(4) {
        let kind = if rng.below(5) == 0 { rng.below(9) } else { *rng.pick(own) };
        match kind {
            0 => args.extend(["--spin-rate".into(), rng.pick(NUMBERS).to_string()]),
            1 => args.extend(["--at".into(), rng.pick(&["0", "0.5", "1", "-1", "1e9", "nan", "0.01"]).to_string()]),
            2 => args.push("--deployed".into()),
            3 => args.extend(["--count".into(), rng.pick(&["0", "1", "3", "1000", "-1", "x"]).to_string()]),
            4 => args.extend([
                "--mode".into(),
                rng.pick(&["free:0", "free:6", "hub_fixed:0", "hub_fixed:999", "x:1", "free:-1", "free"]).to_string(),
            ]),
            5 => args.extend(["--tolerance".into(), rng.pick(NUMBERS).to_string()]),
            6 => args.extend([
                "--outputs".into(),
                rng.pick(&["sigma_B_*", "nope", "", "*", "q_B_w,w_B_*", "h1_yaw"]).to_string(),
            ]),
            7 => args.extend(["--inputs".into(), rng.pick(&["hub", "nobody", "", "hub,p1", "panel"]).to_string()]),
            _ => args.extend(["--view".into(), out.with_extension(rng.pick(&["html", "csv"])).display().to_string()]),
        }
    }
    args
}

#[test]
fn fuzzed_linear_commands_end_in_a_result_or_words() {
    let n = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(40);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    let dir = common::tmp("fuzz", "linear");
    let (mut ran, mut refused, mut usage) = (0, 0, 0);
    let started = Instant::now();
    for i in 0..n {
        let out = dir.join(format!("out{i}"));
        let args = call(&mut rng, &out);
        let mut child =
            foldsim().args(&args).current_dir(&dir).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        let begun = Instant::now();
        while child.try_wait().unwrap().is_none() {
            if begun.elapsed() > STUCK {
                let _ = child.kill();
                panic!("seed {seed} input {i}: stuck for {STUCK:?}: foldsim {}", args.join(" "));
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        let o = child.wait_with_output().unwrap();
        let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
        let shown = || format!("seed {seed} input {i}: foldsim {}\n{text}", args.join(" "));
        assert!(!text.contains("panicked"), "{}", shown());
        let written: Vec<_> = ["csv", "npz", "toml", "gltf", "html", ""]
            .iter()
            .map(|e| out.with_extension(e))
            .filter(|p| p.is_file())
            .collect();
        match o.status.code() {
            Some(0) => {
                // A result never holds NaN (a refusal may echo a NaN the user gave).
                assert!(!text.contains("NaN"), "{}", shown());
                ran += 1;
                for p in written.iter().filter(|p| p.extension().is_none_or(|e| e != "html")) {
                    let bytes = std::fs::read(p).unwrap();
                    assert!(!String::from_utf8_lossy(&bytes).contains("NaN"), "{} wrote NaN: {}", p.display(), shown());
                }
            }
            Some(2) => usage += 1,
            Some(1) => {
                assert!(text.contains("error: ") && text.trim().len() > 20, "{}", shown());
                // A refusal after the scenario was read writes nothing it was asked for.
                assert!(written.is_empty(), "left {written:?}: {}", shown());
                refused += 1;
            }
            other => panic!("exit {other:?}: {}", shown()),
        }
        for p in written {
            let _ = std::fs::remove_file(p);
        }
    }
    eprintln!(
        "fuzz linear commands (seed {seed}): {n} calls: {ran} ran, {refused} refused in words, {usage} refused by the argument parser, in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert!(ran > 0 && refused > 0, "the fuzzer reaches both outcomes");
}

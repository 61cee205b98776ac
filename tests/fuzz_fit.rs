//! Fuzzing `foldsim fit`'s inputs (docs/fit.md): the data file, the `--free` and `--sigma`
//! arguments. Every input must end in a fit or a refusal in words that names the file, the
//! argument or the run; never a panic, never a fitted value outside its bounds or not finite.
//!
//! As a test it takes a small budget; as a longer command:
//!
//!     FOLDSIM_FUZZ_INPUTS=4000 FOLDSIM_FUZZ_SEED=7 cargo test --release --test fuzz_fit -- --nocapture

mod common;

use common::fuzz::{EXTREMES, Rng};
use foldsim::fit::data::Data;
use foldsim::fit::problem::Problem;
use foldsim::fit::{fit, lm, params};
use foldsim::scenario::ScenarioText;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

const COLUMNS: &[&str] =
    &["h1_yaw", "h1_pitch", "deployed", "E", "h1_F_x", "t", "T", "nope", "", "h1_yaw ", "\"h1_roll\"", "q_B_w"];
const CELLS: &[&str] =
    &["0", "0.1", "-0.2", "1e-3", "", " ", "nan", "NaN", "inf", "1e400", "x", "0x10", "1,2", "\"0.5\""];
const FREE: &[&str] = &[
    "hinge.h1.law.k_theta",
    "hinge.h1.law.c_theta",
    "hinge.*.law.k_f",
    "body.panel.mass",
    "initial.hub.omega.2",
    "hinge.h1.law.type",
    "run.duration",
    "run.rtol",
    "hinge.h9.law.k_f",
    "nothing",
    "",
    "hinge.h1.law.k_theta.0",
];
const BOUNDS: &[&str] = &["", "=1:100", "=0:", "=:5", "=5:1", "=a:b", "=-1e300:1e300", "=nan:1", "=0:0", "=1", "=:"];

/// paper-1panel over 0.2 s (rows every 0.05 s).
fn nominal() -> String {
    std::fs::read_to_string(common::repo("examples/paper-1panel.toml"))
        .unwrap()
        .replace("duration = 20.0", "duration = 0.2")
}

/// A well-formed data file (outputs, ascending times within the run, numbers), some of its
/// cells empty or extreme: these get to the fit.
fn valid_data(rng: &mut Rng) -> String {
    let columns = ["h1_yaw", "h1_pitch", "deployed", "E", "h1_F_x", "q_B_w", "h1_delta_x"];
    let picked: Vec<&str> = (0..1 + rng.below(2)).map(|k| columns[(rng.below(7) + k) % 7]).collect();
    let mut picked = picked;
    picked.dedup();
    let mut text = format!("t,{}\n", picked.join(","));
    let rows = 2 + rng.below(6);
    for r in 0..rows {
        let t = (0.2 * (r + 1) as f64 / rows as f64).min(0.2);
        let cells: Vec<String> = picked
            .iter()
            .map(|_| match rng.below(12) {
                0 => String::new(),
                1 => rng.pick(&["1e300", "-1e300", "1e-300", "0"]).to_string(),
                _ => format!("{}", 0.3 * (rng.below(1000) as f64 / 500.0 - 1.0)),
            })
            .collect();
        text += &format!("{t},{}\n", cells.join(","));
    }
    text
}

fn data_text(rng: &mut Rng) -> String {
    if rng.below(3) != 0 {
        return valid_data(rng);
    }
    let mut header: Vec<String> = vec!["t".into()];
    for _ in 0..rng.below(3) + usize::from(rng.below(4) != 0) {
        header.push(rng.pick(COLUMNS).to_string());
    }
    if rng.below(8) == 0 {
        header.remove(0);
    }
    let mut text = header.join(",") + "\n";
    let rows = rng.below(6);
    let mut t = 0.0;
    for _ in 0..rows {
        t += [0.01, 0.05, 0.0, -0.01, 0.3][rng.below(5)];
        let mut cells = vec![if rng.below(6) == 0 { rng.pick(CELLS).to_string() } else { format!("{t}") }];
        for _ in 1..header.len() + usize::from(rng.below(10) == 0) {
            cells.push(if rng.below(3) == 0 { rng.pick(EXTREMES).to_string() } else { rng.pick(CELLS).to_string() });
        }
        text += &(cells.join(",") + "\n");
    }
    text
}

#[test]
fn fuzzed_fit_inputs_end_in_a_fit_or_a_named_refusal() {
    let n = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(150);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    let base = ScenarioText::new(&nominal(), "s.toml", &common::repo("examples")).unwrap();
    let model = base.build().unwrap();
    let (mut fitted, mut refused) = (0, 0);
    let started = Instant::now();
    for i in 0..n {
        let data = data_text(&mut rng);
        let free: Vec<String> = (0..rng.below(3)).map(|_| format!("{}{}", rng.pick(FREE), rng.pick(BOUNDS))).collect();
        let sigmas = if rng.below(4) == 0 { 1 } else { 0 };
        let sigma: Vec<(String, f64)> = (0..sigmas)
            .map(|_| (rng.pick(COLUMNS).to_string(), *rng.pick(&[1e-3, 0.0, -1.0, f64::NAN, 1e300])))
            .collect();
        let took = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let mut d = Data::parse(&data, "d.csv", &model.model, model.settings.duration)?;
            for (c, s) in &sigma {
                d.set_sigma(c, *s)?;
            }
            let f = params::parse(&free, &base)?;
            let p = Problem::new(base.clone(), f, d)?;
            let options = lm::Options { max_iterations: 3, ..lm::Options::default() };
            let result = fit(&p, &options, &mut |_, _| {})?;
            let _ = result.text(&p);
            Ok::<_, String>((p, result))
        }));
        let what = format!("seed {seed} input {i}: data\n{data}\nfree {free:?} sigma {sigma:?}");
        if std::env::var("FIT_FUZZ_SHOW").is_ok() && took.elapsed().as_secs_f64() > 1.0 {
            println!("slow ({:.1} s): {what}", took.elapsed().as_secs_f64());
        }
        match outcome {
            Err(_) => panic!("{what}: panicked"),
            Ok(Err(e)) => {
                let named = ["d.csv", "--free", "--sigma", "the run with"].iter().any(|w| e.contains(w));
                assert!(named, "{what}: an error that names nothing: {e}");
                if std::env::var("FIT_FUZZ_SHOW").is_ok() {
                    println!("{e}");
                }
                refused += 1;
            }
            Ok(Ok((p, r))) => {
                for (f, x) in p.free.iter().zip(&r.solution.x) {
                    assert!(x.is_finite() && *x >= f.low && *x <= f.high, "{what}: {} = {x}", f.path);
                }
                fitted += 1;
            }
        }
    }
    println!(
        "fit fuzz, seed {seed}: {n} inputs, {fitted} fitted, {refused} refused in words, {:.1} s",
        started.elapsed().as_secs_f64()
    );
}

/// The law file, the bench test and the arguments of `foldsim fit --law`: random bench files
/// (headers, cells, lengths), law files with numbers and words replaced, and free values; a
/// fit or a refusal that names the file, the argument or the law's values.
#[test]
fn fuzzed_law_fits_end_in_a_fit_or_a_named_refusal() {
    use foldsim::fit::law::{Bench, LawProblem};
    let n = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(150);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut rng = Rng(0x2545_F491_4F6C_DD1D ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    let law = std::fs::read_to_string(common::repo("examples/laws/tape-spring.toml")).unwrap();
    let words: Vec<&str> = ["1.0", "1300.0", "\"linear\"", "\"extend\"", "\"euler\"", "\"free\""].to_vec();
    let headers = ["angle_deg,moment_Nm", "angle_rad,moment_Nm", "displacement_m,force_N", "t,h1_yaw", "angle_deg", ""];
    let free_args = [
        "law.rz.tape_spring.increasing.scale=0.5:2",
        "law.rz.tape_spring.decreasing.scale",
        "law.rz.tape_spring.transition_stiffness=1:1e5",
        "law.type",
        "law.rz.nothing",
        "law.x",
        "title",
    ];
    let (mut fitted, mut refused) = (0, 0);
    for i in 0..n {
        let mut text = law.clone();
        if rng.below(2) == 0 {
            let w = *rng.pick(&words);
            let with = *rng.pick(EXTREMES);
            text = text.replacen(w, with, 1);
        }
        let mut bench = format!("{}\n", rng.pick(&headers));
        let rows = rng.below(30);
        let mut a = 0.0;
        for _ in 0..rows {
            a += [0.1, 0.5, -0.3, 0.0, 30.0][rng.below(5)];
            let cell = if rng.below(8) == 0 {
                rng.pick(EXTREMES).to_string()
            } else {
                format!("{}", 0.1 * rng.below(100) as f64)
            };
            bench += &if rng.below(12) == 0 { format!("{a}\n") } else { format!("{a},{cell}\n") };
        }
        let free: Vec<String> = (0..1 + rng.below(2)).map(|_| rng.pick(&free_args).to_string()).collect();
        let direction = *rng.pick(&["rz", "rz", "x", "q"]);
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let t = ScenarioText::new(&text, "law.toml", &common::repo("examples/laws")).map_err(|e| e.to_string())?;
            let b = Bench::parse(&bench, "bench.csv")?;
            let f = params::parse(&free, &t)?;
            let p = LawProblem::new(t, f, b, direction)?;
            let options = lm::Options { max_iterations: 3, ..lm::Options::default() };
            let r = fit(&p, &options, &mut |_, _| {})?;
            Ok::<_, String>((p, r))
        }));
        let what = format!("seed {seed} input {i}: law\n{text}\nbench\n{bench}\nfree {free:?} direction {direction}");
        match outcome {
            Err(_) => panic!("{what}: panicked"),
            Ok(Err(e)) => {
                let named =
                    ["law.toml", "bench.csv", "--free", "--direction", "the law with"].iter().any(|w| e.contains(w));
                assert!(named, "{what}: an error that names nothing: {e}");
                refused += 1;
            }
            Ok(Ok((p, r))) => {
                for (f, x) in p.free.iter().zip(&r.solution.x) {
                    assert!(x.is_finite() && *x >= f.low && *x <= f.high, "{what}: {} = {x}", f.path);
                }
                fitted += 1;
            }
        }
    }
    println!("law fit fuzz, seed {seed}: {n} inputs, {fitted} fitted, {refused} refused in words");
}

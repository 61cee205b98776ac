//! Fuzzing `foldsim export fmu`'s choices (docs/interop.md): output patterns, input names and
//! parameter patterns, any mix of good, bad, empty and odd (wildcards, dots, quotes, markup
//! characters). Each request must give variables or a refusal naming the argument; the
//! variables must be distinct, each in the model description once (escaped), and the
//! archive must build. Never a panic.
//!
//!     FOLDSIM_FUZZ_INPUTS=20000 FOLDSIM_FUZZ_SEED=3 cargo test --release --test fuzz_export -- --nocapture

mod common;

use common::fuzz::Rng;
use foldsim::export::fmu::{Request, archive, model_description, variables};
use foldsim::scenario::ScenarioText;
use std::panic::{AssertUnwindSafe, catch_unwind};

const OUTPUTS: &[&str] =
    &["H_*", "w_B_z", "default", "*", "t", "", "zz", "q_B_?", "h1_*", "<&\"'>", "p1_F_*", "*_speed"];
const INPUTS: &[&str] =
    &["hub", "p1", "p3", "actuators", "hub_T_z", "nobody", "", "mid", "rw_x", "hub_T_z ", "*", "p2_F_x"];
const PARAMS: &[&str] =
    &["*", "body.*.mass", "hinge.*.law.*", "run.*", "", "none", "body.hub.inertia.*", "initial.*", "?", "x"];

fn pick(rng: &mut Rng, items: &[&'static str]) -> String {
    items[rng.below(items.len())].to_string()
}

#[test]
fn every_request_gives_variables_or_a_refusal() {
    let n: usize = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(300);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let texts: Vec<ScenarioText> =
        ["examples/paper-3panel.toml", "examples/zfold-attitude-hold.toml", "examples/zfold-motor-deploy.toml"]
            .iter()
            .map(|p| ScenarioText::from_file(&common::repo(p)).unwrap())
            .collect();
    let (mut made, mut refused) = (0, 0);
    for i in 0..n {
        let text = &texts[rng.below(texts.len())];
        let list =
            |items: &[&'static str], rng: &mut Rng| (0..rng.below(4)).map(|_| pick(rng, items)).collect::<Vec<_>>();
        let request = Request {
            outputs: list(OUTPUTS, &mut rng),
            inputs: list(INPUTS, &mut rng),
            parameters: if rng.below(3) == 0 { None } else { Some(list(PARAMS, &mut rng)) },
        };
        let result = catch_unwind(AssertUnwindSafe(|| {
            let v = variables(text, &request)?;
            let names: Vec<&String> =
                v.outputs.iter().chain(&v.inputs).chain(v.parameters.iter().map(|p| &p.path)).collect();
            let d = model_description(&v, "m", "fuzz <&>", 1.0, 0.1);
            for name in &names {
                let escaped =
                    name.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;");
                assert_eq!(d.matches(&format!("name=\"{escaped}\" ")).count(), 1, "{name} in the description");
            }
            archive(&d, "m", b"\x7fELF", &text.text(), &[], &v)?;
            Ok::<_, String>(names.len())
        }));
        match result {
            Ok(Ok(_)) => made += 1,
            Ok(Err(message)) => {
                assert!(!message.is_empty(), "seed {seed} input {i}: an empty refusal");
                refused += 1;
            }
            Err(_) => panic!("seed {seed} input {i}: a panic on {request:?}"),
        }
    }
    println!("fuzz export (seed {seed}): {n} requests, {made} exported, {refused} refused");
    assert!(made > 0 && refused > 0);
}

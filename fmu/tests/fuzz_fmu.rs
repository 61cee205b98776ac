//! Fuzzing the FMU's functions (docs/interop.md) as a host might call them: any order of
//! the FMI 2.0 calls (setup, initialization, steps, reset, terminate), any value references
//! (outputs, inputs, parameters, out of range), any values (NaN, ±inf, huge), any
//! communication points and step sizes, GUIDs and resource locations good and bad. Every
//! call must return a status: never a panic reaching the host (`fmi2Fatal`), never a crash,
//! never an output that is not finite after a successful step.
//!
//!     FOLDSIM_FUZZ_INPUTS=20000 FOLDSIM_FUZZ_SEED=3 cargo test --release -p foldsim-fmu --test fuzz_fmu -- --nocapture

#[path = "../../tests/common/fuzz.rs"]
#[allow(dead_code)]
mod fuzz;

use foldsim::export::fmu::{Request, SCENARIO_FILE, VARIABLES_FILE, variables};
use foldsim::scenario::ScenarioText;
use foldsim_fmu::*;
use fuzz::Rng;
use std::ffi::{CString, c_void};
use std::path::Path;

const VALUES: &[f64] = &[0.0, 1.0, -1.0, 0.5, 1e-300, 1e300, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 250.0, 2.0];
const STEPS: &[f64] = &[0.01, 0.1, 1e-9, 0.0, -0.1, f64::NAN, f64::INFINITY, 30.0, 0.37, 1e-300];

fn pick(rng: &mut Rng, items: &[f64]) -> f64 {
    items[rng.below(items.len())]
}

/// The radial spin's FMU unpacked: its resources directory's URI and GUID.
fn unpacked() -> (CString, CString) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("examples/radial-spin.toml"))
        .unwrap()
        .replace("duration = 20.0", "duration = 2.0");
    let dir = std::env::temp_dir().join(format!("foldsim-fuzz-fmu-{}/resources", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(SCENARIO_FILE), &text).unwrap();
    let st = ScenarioText::new(&text, "spin.toml", &dir).unwrap();
    let request = Request {
        outputs: vec!["H_*".into(), "w_B_z".into(), "deployed".into()],
        inputs: vec!["hub".into()],
        parameters: None,
    };
    let v = variables(&st, &request).unwrap();
    std::fs::write(dir.join(VARIABLES_FILE), toml::to_string(&v).unwrap()).unwrap();
    (CString::new(format!("file://{}", dir.display())).unwrap(), CString::new(v.guid).unwrap())
}

/// Where the test believes the instance is.
#[derive(Clone, Copy)]
enum Phase {
    None,
    Instantiated,
    Initialization,
    Stepping,
    Failed,
}

#[test]
fn every_call_returns_a_status() {
    let n: usize = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(600);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let (uri, guid) = unpacked();
    let bad_uri = CString::new("http://nowhere/resources").unwrap();
    let bad_guid = CString::new("{0}").unwrap();
    let name = CString::new("fuzz").unwrap();
    // Value references: 5 outputs (H_x, H_y, H_z, w_B_z, deployed), 6 inputs, then parameters.
    let outputs = 5usize;
    let mut c: *mut c_void = std::ptr::null_mut();
    let mut t = 0.0f64;
    let mut counts = [0usize; 5];
    let mut phase = Phase::None;
    for i in 0..n {
        // Four calls in five follow FMI's order (as the test mirrors the instance's phase), so
        // the sequences get deep into stepping; the fifth is any call at all.
        let call = if rng.below(5) == 0 {
            rng.below(12)
        } else {
            match phase {
                Phase::None => 0,
                Phase::Failed => 10,
                Phase::Instantiated => *[1, 2, 7].get(rng.below(3)).unwrap_or(&2),
                Phase::Initialization => *[3, 7, 9].get(rng.below(3)).unwrap_or(&3),
                Phase::Stepping => *[4, 5, 6, 7, 9].get(rng.below(5)).unwrap_or(&4),
            }
        };
        // SAFETY: the FMI calls as a host makes them: `c` is null or an instance from
        // fmi2Instantiate not yet freed; every array holds the count passed with it.
        let status = unsafe {
            match call {
                0 => {
                    fmi2FreeInstance(c);
                    let (u, g) = match rng.below(6) {
                        0 => (bad_uri.as_ptr(), guid.as_ptr()),
                        1 => (uri.as_ptr(), bad_guid.as_ptr()),
                        2 => (std::ptr::null(), guid.as_ptr()),
                        _ => (uri.as_ptr(), guid.as_ptr()),
                    };
                    c = fmi2Instantiate(name.as_ptr(), rng.below(3) as i32, g, u, std::ptr::null(), 0, 0);
                    t = 0.0;
                    if c.is_null() { ERROR } else { OK }
                }
                1 => {
                    let stop = pick(&mut rng, &[1.0, 2.0, 0.5, -1.0, f64::NAN, 3.0]);
                    t = pick(&mut rng, &[0.0, 0.0, 1.0, f64::NAN]);
                    let tol = pick(&mut rng, &[1e-8, 0.0, f64::NAN, 1e-3]);
                    fmi2SetupExperiment(c, rng.below(2) as i32, tol, t, rng.below(2) as i32, stop)
                }
                2 => fmi2EnterInitializationMode(c),
                3 => fmi2ExitInitializationMode(c),
                4..=6 => {
                    let h = pick(&mut rng, STEPS);
                    let current = if rng.below(10) == 0 { t + 0.5 } else { t };
                    let s = fmi2DoStep(c, current, h, 0);
                    if s == OK {
                        t += h;
                        let vr: Vec<u32> = (0..outputs as u32).collect();
                        let mut out = vec![0.0; outputs];
                        assert_eq!(fmi2GetReal(c, vr.as_ptr(), outputs, out.as_mut_ptr()), OK);
                        assert!(
                            out.iter().all(|v| v.is_finite()),
                            "seed {seed} call {i}: outputs {out:?} after a successful step"
                        );
                    }
                    s
                }
                7 | 8 => {
                    let k = 1 + rng.below(3);
                    let vr: Vec<u32> = (0..k).map(|_| rng.below(100) as u32).collect();
                    let values: Vec<f64> = (0..k).map(|_| pick(&mut rng, VALUES)).collect();
                    fmi2SetReal(c, vr.as_ptr(), k, values.as_ptr())
                }
                9 => {
                    let k = rng.below(4);
                    let vr: Vec<u32> = (0..k).map(|_| rng.below(100) as u32).collect();
                    let mut out = vec![0.0; k];
                    let p = if k == 0 && rng.below(2) == 0 { std::ptr::null() } else { vr.as_ptr() };
                    fmi2GetReal(c, p, k, out.as_mut_ptr())
                }
                10 => {
                    t = 0.0;
                    fmi2Reset(c)
                }
                _ => match rng.below(4) {
                    0 => fmi2Terminate(c),
                    1 => fmi2GetFMUstate(c, std::ptr::null_mut()),
                    2 => fmi2SetInteger(c, [0u32].as_ptr(), 1, [1].as_ptr()),
                    _ => {
                        let mut v = 0.0;
                        fmi2GetRealStatus(c, 2, &mut v)
                    }
                },
            }
        };
        assert_ne!(status, FATAL, "seed {seed} call {i}: a panic reached the host");
        phase = match (call, status) {
            (0, OK) | (10, OK) => Phase::Instantiated,
            (0, _) => Phase::None,
            (2, OK) => Phase::Initialization,
            (3, OK) => Phase::Stepping,
            (_, OK) if call == 11 => Phase::Failed, // terminated, or a refused call: reset
            (_, OK) => phase,
            _ if c.is_null() => Phase::None,
            _ => Phase::Failed,
        };
        counts[status as usize] += 1;
    }
    // SAFETY: as above.
    unsafe { fmi2FreeInstance(c) };
    println!(
        "fuzz FMU (seed {seed}): {n} calls: {} ok, {} discard, {} error",
        counts[OK as usize], counts[DISCARD as usize], counts[ERROR as usize]
    );
    assert!(counts[OK as usize] > 0 && counts[ERROR as usize] > 0);
}

//! Fuzzing the C library's calls (docs/interop.md): random sequences of loads (files, text,
//! null, broken scenarios), parameters (key paths good and bad, values NaN, ±inf, huge),
//! inputs by name and index, advances by any dt, outputs by any name, frees. Every call must
//! return a status, and a failure must leave a message: never a panic caught at the boundary
//! (`FOLDSIM_ERROR_INTERNAL`), never a crash, never an output that is not finite after a
//! successful advance.
//!
//!     FOLDSIM_FUZZ_INPUTS=20000 FOLDSIM_FUZZ_SEED=3 cargo test --release -p foldsim-c --test fuzz_capi -- --nocapture

#[path = "../../tests/common/fuzz.rs"]
#[allow(dead_code)]
mod fuzz;

use foldsim_c::*;
use fuzz::Rng;
use std::ffi::{CStr, CString};

const NAMES: &[&str] =
    &["hub_T_z", "hub_F_x", "p1_T_y", "p3_F_z", "hub_T_w", "", "H_z", "hub", "rw_x_torque", "mid_effort"];
const OUTPUTS: &[&str] = &["H_z", "w_B_z", "t", "q_B_w", "h1_F_x", "", "H_w", "deployed", "W", "p1_R_x"];
const PATHS: &[&str] = &[
    "body.hub.mass",
    "body.p1.mass",
    "body.*.mass",
    "hinge.h1.law.k",
    "hinge.*.law.c",
    "hinge.h1.law",
    "run.duration",
    "body.hub.inertia.0",
    "initial.hub.omega_rpm.2",
    "nothing.at.all",
    "",
    "body.9.mass",
];
const VALUES: &[f64] = &[0.0, 1.0, -1.0, 0.5, 1e-300, 1e300, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 100.0, 7.0];
const DTS: &[f64] = &[0.01, 0.1, 1e-9, 0.0, -0.1, f64::NAN, f64::INFINITY, 5.0, 1e-300, 0.37];

fn repo(p: &str) -> CString {
    CString::new(format!("{}/../{p}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn c(s: &str) -> CString {
    CString::new(s).unwrap()
}

fn pick(rng: &mut Rng, items: &[&'static str]) -> &'static str {
    items[rng.below(items.len())]
}

fn message() -> String {
    // SAFETY: the library's own string, valid until the next failing call on this thread.
    unsafe { CStr::from_ptr(foldsim_last_error()) }.to_string_lossy().into_owned()
}

#[test]
fn every_call_returns_a_status_with_a_message() {
    let n: usize = std::env::var("FOLDSIM_FUZZ_INPUTS").ok().and_then(|v| v.parse().ok()).unwrap_or(600);
    let seed: u64 = std::env::var("FOLDSIM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let text = std::fs::read_to_string(repo("examples/paper-3panel.toml").to_str().unwrap()).unwrap();
    let scenarios: Vec<CString> = vec![
        c(&text.replace("duration = 20.0", "duration = 2.0")),
        c(&text.replace("mass = 100.0", "mass = -1.0")),
        c("[run]\nduration = 1.0\n"),
        c("not toml at all ["),
        c(&std::fs::read_to_string(repo("examples/zfold-motor-deploy.toml").to_str().unwrap()).unwrap()),
    ];
    let missing = c("no/such.toml");
    let mut sim: *mut FoldsimSimulation = std::ptr::null_mut();
    let (mut ok, mut refused) = (0usize, 0usize);
    for i in 0..n {
        let status = unsafe {
            match rng.below(10) {
                0 => {
                    foldsim_free(sim);
                    sim = match rng.below(4) {
                        0 => foldsim_load_file(repo("examples/paper-3panel.toml").as_ptr()),
                        1 => foldsim_load_file(if rng.below(2) == 0 { std::ptr::null() } else { missing.as_ptr() }),
                        _ => foldsim_load_text(rng.pick(&scenarios).as_ptr(), std::ptr::null()),
                    };
                    if sim.is_null() { FoldsimStatus::FoldsimErrorRun } else { FoldsimStatus::FoldsimOk }
                }
                1 => foldsim_set_parameter(sim, c(pick(&mut rng, PATHS)).as_ptr(), *rng.pick(VALUES)),
                2 => foldsim_start(sim),
                3 => foldsim_set_input(sim, c(pick(&mut rng, NAMES)).as_ptr(), *rng.pick(VALUES)),
                4 => foldsim_set_input_at(sim, rng.below(40), *rng.pick(VALUES)),
                5 | 6 => {
                    let s = foldsim_advance(sim, *rng.pick(DTS));
                    if s == FoldsimStatus::FoldsimOk {
                        let n = foldsim_output_count(sim);
                        let mut row = vec![0.0; n];
                        assert_eq!(
                            foldsim_get_outputs(sim, row.as_mut_ptr(), n),
                            FoldsimStatus::FoldsimOk,
                            "{}",
                            message()
                        );
                        if let Some(j) = row.iter().position(|v| !v.is_finite()) {
                            panic!("seed {seed} call {i}: output {j} is {} after a successful advance", row[j]);
                        }
                    }
                    s
                }
                7 => {
                    let mut v = 0.0;
                    foldsim_get_output(
                        sim,
                        c(pick(&mut rng, OUTPUTS)).as_ptr(),
                        if rng.below(8) == 0 { std::ptr::null_mut() } else { &mut v },
                    )
                }
                8 => {
                    let n = foldsim_output_count(sim);
                    let mut row = vec![0.0; n + 2];
                    foldsim_get_outputs(sim, row.as_mut_ptr(), n + rng.below(3).min(1))
                }
                _ => {
                    let _ = foldsim_input_name(sim, rng.below(40));
                    let _ = foldsim_output_name(sim, rng.below(300));
                    let mut t = 0.0;
                    foldsim_time(sim, &mut t)
                }
            }
        };
        match status {
            FoldsimStatus::FoldsimOk => ok += 1,
            FoldsimStatus::FoldsimErrorInternal => {
                panic!("seed {seed} call {i}: a panic reached the boundary: {}", message())
            }
            _ => {
                assert!(!message().is_empty(), "seed {seed} call {i}: {status:?} without a message");
                refused += 1;
            }
        }
    }
    unsafe { foldsim_free(sim) };
    println!("fuzz C library (seed {seed}): {n} calls, {ok} done, {refused} refused with a message");
    assert!(ok > 0 && refused > 0);
}

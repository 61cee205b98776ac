//! Cost of the equations of motion against structure size, on the generated structures of
//! `foldsim::generate` (a z-folded chain, and a grid whose hinges mostly close loops), law 2
//! with stiff off-axis hinges:
//! - one right-hand-side evaluation, per hinge, for N = 1 … 4096 panels;
//! - wall time per simulated second with the explicit (DOP853) and implicit (SDIRK4) paths at
//!   rtol = atol = 1e-6 with 1e7 N/m off-axis hinges, for the smaller sizes.
//!
//! Prints the machine's load average beside the figures, since these machines are shared.
//! Run: `cargo bench --bench rhs` (add `-- --quick` for a short pass).

use foldsim::dynamics::Dynamics;
use foldsim::generate::{Params, grid, zfold};
use foldsim::init::initial_state;
use foldsim::scenario::Scenario;
use foldsim::simulate::simulate;
use std::time::Instant;

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

fn structure(kind: &str, n: usize, p: &Params) -> Scenario {
    let text = match kind {
        "chain" => zfold(n, p),
        _ => {
            // The most nearly square grid with n panels.
            let rows = (1..=(n as f64).sqrt() as usize).rev().find(|r| n.is_multiple_of(*r)).unwrap_or(1).max(2);
            let cols = (n / rows).max(2);
            grid(rows, cols, p)
        }
    };
    Scenario::from_toml(&text, kind).expect("generated scenarios are valid")
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick") || !std::env::args().any(|a| a == "--bench");
    let p = Params { duration: 0.2, ..Params::default() };
    println!("foldsim bench (load average {})", load());
    println!("\nright-hand-side evaluation, law 2, k_translation 1e6 N/m, k_bending 1e3 N·m/rad, k_fold 1 N·m/rad");
    println!("{:>6} {:>6} {:>7} {:>6} {:>12} {:>12}", "shape", "panels", "hinges", "loops", "µs/eval", "ns/hinge");
    for kind in ["chain", "grid"] {
        for n in [1usize, 4, 16, 64, 256, 1024, 4096] {
            if kind == "grid" && n < 4 {
                continue;
            }
            let s = structure(kind, n, &p);
            let model = &s.model;
            let (mut y, refs) = initial_state(model, &s.initial);
            for (i, v) in y.iter_mut().enumerate() {
                *v += 1e-4 * ((i * 7919) % 13) as f64; // a deformed state, every term live
            }
            let dynamics = Dynamics::new(model, refs);
            dynamics.initialize_memory(&y);
            let mut dydt = vec![0.0; y.len()];
            let budget = if quick { 0.02 } else { 0.5 };
            let (mut evals, start) = (0u64, Instant::now());
            while start.elapsed().as_secs_f64() < budget {
                for _ in 0..8 {
                    dynamics.rhs(&y, &mut dydt);
                }
                evals += 8;
            }
            let per = start.elapsed().as_secs_f64() / evals as f64;
            let hinges = model.hinges.len();
            let loops = model.is_tree_hinge.iter().filter(|t| !**t).count();
            println!(
                "{kind:>6} {:>6} {hinges:>7} {loops:>6} {:>12.3} {:>12.1}",
                model.bodies.len() - 1,
                per * 1e6,
                per * 1e9 / hinges as f64
            );
            std::hint::black_box(&dydt);
        }
    }
    let p = Params { duration: 2.0, tolerance: 1e-6, k_translation: 1e7, k_bending: 1e4, ..p };
    println!(
        "\nwall time per simulated second, rtol = atol = {:e}, {} s simulated, k_translation 1e7 N/m, k_bending 1e4 N·m/rad",
        p.tolerance, p.duration
    );
    println!(
        "{:>6} {:>6} {:>8} {:>10} {:>10} {:>14}",
        "shape", "panels", "method", "steps", "rhs evals", "wall s / sim s"
    );
    for kind in ["chain", "grid"] {
        for n in [4usize, 16, 64] {
            for method in ["dop853", "sdirk4"] {
                let mut s = structure(kind, n, &p);
                if method == "sdirk4" {
                    s.settings.integrator =
                        foldsim::simulate::Integrator::Sdirk4 { rtol: p.tolerance, atol: p.tolerance };
                }
                let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> { Ok(()) };
                let r = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).expect("runs");
                println!(
                    "{kind:>6} {n:>6} {method:>8} {:>10} {:>10} {:>14.4}",
                    r.steps_accepted,
                    r.rhs_evaluations,
                    r.wall_seconds / s.settings.duration
                );
            }
        }
    }
    println!("\nload average after: {}", load());
}

//! Cost of the equations of motion against structure size, on the generated structures of
//! `foldsim::generate` (a z-folded chain, and a grid whose hinges mostly close loops), law 2
//! with stiff off-axis hinges:
//! - one right-hand-side evaluation, per hinge, for N = 1 … 4096 panels (the fastest of ten
//!   batches: other load on a shared machine only slows batches down);
//! - wall time per simulated second with the explicit (DOP853) and implicit (SDIRK4) paths at
//!   rtol = atol = 1e-6 with 1e7 N/m off-axis hinges, 0.1 s from release, for the same N,
//!   with the hinge-angle accuracy each reached (against a 1000× tighter run, N ≤ 256).
//!
//! Prints the machine's load average beside the figures, since these machines are shared.
//! Run: `cargo bench --bench rhs` (about 10 minutes on 2 cores). Options after `--`:
//! `--quick` (short budgets and windows), `--rhs` or `--wall` (one section), `--max N`,
//! `--profile chain|grid N` (only that structure's RHS loop for 5 s, to run under a profiler).

use foldsim::dynamics::Dynamics;
use foldsim::generate::{Params, grid, zfold};
use foldsim::kinematics::initial_state;
use foldsim::scenario::Scenario;
use foldsim::simulate::simulate;
use std::time::Instant;

mod common;
use common::load;

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

/// Max over the run's output rows of every hinge angle's distance to `reference`'s at the
/// same row, rad; or the rows' hinge angles when `reference` is None.
type Angles = Vec<Vec<[f64; 3]>>;

/// Runs `s` with `method`, returning the report and the hinge angles at every output row.
fn timed_run(s: &Scenario, method: &str, tolerance: f64) -> (foldsim::simulate::RunReport, Angles) {
    let mut settings = s.settings;
    settings.integrator = match method {
        "sdirk4" => foldsim::simulate::Integrator::Sdirk4 { rtol: tolerance, atol: tolerance },
        _ => foldsim::simulate::Integrator::Dop853 { rtol: tolerance, atol: tolerance },
    };
    let mut rows: Angles = Vec::new();
    let mut sink = |o: &foldsim::observe::Observation| -> Result<(), String> {
        rows.push(o.hinge_theta.iter().map(|t| [t.yaw, t.pitch, t.roll]).collect());
        Ok(())
    };
    let r = simulate(&s.model, &s.initial, &settings, &mut sink, None).expect("runs");
    (r, rows)
}

fn max_angle_error(a: &Angles, b: &Angles) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(ra, rb)| ra.iter().zip(rb))
        .flat_map(|(x, y)| (0..3).map(move |k| (x[k] - y[k]).abs()))
        .fold(0.0, f64::max)
}

const USAGE: &str = "cargo bench --bench rhs [-- OPTIONS]

Cost of one right-hand-side evaluation per hinge (z-fold chain and grid, 1 to 4096 panels),
and wall time per simulated second of the explicit and implicit paths with the accuracy each
reached. Prints the machine load before and after. About 10 minutes.

  --quick            short budgets (the default under `cargo test --benches`)
  --max N            largest panel count (default 4096)
  --rhs              only the right-hand-side section
  --wall             only the wall-time section
  --profile SHAPE N  only SHAPE's (zfold or grid) right-hand-side loop with N panels, for 5 s
  -h, --help         this text";

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return;
    }
    let quick = args.iter().any(|a| a == "--quick") || !args.iter().any(|a| a == "--bench");
    let max_n: usize = args
        .iter()
        .position(|a| a == "--max")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(4096);
    let only_wall = args.iter().any(|a| a == "--wall");
    let only_rhs = args.iter().any(|a| a == "--rhs");
    let sizes: Vec<usize> = [1usize, 4, 16, 64, 256, 1024, 4096].into_iter().filter(|n| *n <= max_n).collect();
    let p = Params { duration: 0.2, ..Params::default() };
    // `-- --profile SHAPE N`: only that structure's RHS loop, for 5 s, for a profiler.
    if let Some(i) = args.iter().position(|a| a == "--profile") {
        let n = args[i + 2].parse().expect("panel count");
        rhs_cost(&structure(&args[i + 1], n, &p), 5.0);
        return;
    }
    println!("foldsim bench (load average {})", load());
    if !only_wall {
        rhs_section(&sizes, &p, quick);
    }
    if !only_rhs {
        wall_section(&sizes, quick);
    }
    println!("\nload average after: {}", load());
}

/// Seconds per right-hand-side evaluation of `s` at a deformed state (every term live):
/// the fastest of ten batches over `budget` s in all, since a shared machine's other load
/// only ever slows a batch down.
fn rhs_cost(s: &Scenario, budget: f64) -> f64 {
    let model = &s.model;
    let (mut y, refs) = initial_state(model, &s.initial);
    for (i, v) in y.iter_mut().enumerate() {
        *v += 1e-4 * ((i * 7919) % 13) as f64;
    }
    let dynamics = Dynamics::new(model, refs);
    dynamics.initialize_memory(&y);
    let mut dydt = vec![0.0; y.len()];
    let mut best = f64::INFINITY;
    for _ in 0..10 {
        let (mut evals, start) = (0u64, Instant::now());
        while start.elapsed().as_secs_f64() < budget / 10.0 {
            dynamics.rhs(&y, &mut dydt);
            evals += 1;
        }
        best = best.min(start.elapsed().as_secs_f64() / evals as f64);
    }
    std::hint::black_box(&dydt);
    best
}

fn rhs_section(sizes: &[usize], p: &Params, quick: bool) {
    println!("\nright-hand-side evaluation, law 2, k_translation 1e6 N/m, k_bending 1e3 N·m/rad, k_fold 1 N·m/rad");
    println!("{:>6} {:>6} {:>7} {:>6} {:>12} {:>12}", "shape", "panels", "hinges", "loops", "µs/eval", "ns/hinge");
    for kind in ["chain", "grid"] {
        for &n in sizes {
            if kind == "grid" && n < 4 {
                continue;
            }
            let s = structure(kind, n, p);
            let model = &s.model;
            let per = rhs_cost(&s, if quick { 0.02 } else { 0.5 });
            let hinges = model.hinges.len();
            let loops = model.is_tree_hinge.iter().filter(|t| !**t).count();
            println!(
                "{kind:>6} {:>6} {hinges:>7} {loops:>6} {:>12.3} {:>12.1}",
                model.bodies.len() - 1,
                per * 1e6,
                per * 1e9 / hinges as f64
            );
        }
    }
    // Linearity, 64 → 4096 panels: the two sizes measured alternately (so that the machine's
    // other load falls on both alike), the fastest batch of each.
    if sizes.contains(&4096) {
        for kind in ["chain", "grid"] {
            let (small, large) = (structure(kind, 64, p), structure(kind, 4096, p));
            let (mut a, mut b) = (f64::INFINITY, f64::INFINITY);
            for _ in 0..if quick { 1 } else { 5 } {
                a = a.min(rhs_cost(&small, 0.2) / small.model.hinges.len() as f64);
                b = b.min(rhs_cost(&large, 0.2) / large.model.hinges.len() as f64);
            }
            println!(
                "{kind:>6}: per-hinge cost at 4096 panels / at 64, measured alternately: {:.1} / {:.1} ns = {:.2}",
                b * 1e9,
                a * 1e9,
                b / a
            );
        }
    }
}

/// Wall time per simulated second for both paths, with the accuracy each reached: the max
/// hinge-angle difference, over the output rows, to a DOP853 run at a 1000× tighter
/// tolerance (for N ≤ 256; larger references would dominate the bench's time).
fn wall_section(sizes: &[usize], quick: bool) {
    let tolerance = 1e-6;
    let duration = if quick { 0.01 } else { 1.0 };
    let p = Params {
        duration,
        output_step: duration / 10.0,
        tolerance,
        k_translation: 1e7,
        k_bending: 1e4,
        ..Params::default()
    };
    println!(
        "\nwall time per simulated second, rtol = atol = {tolerance:e}, {duration} s simulated from release, \
         k_translation 1e7 N/m, k_bending 1e4 N·m/rad, k_fold 1 N·m/rad, 2 kg panels"
    );
    println!(
        "{:>6} {:>6} {:>8} {:>8} {:>10} {:>14} {:>16} {:>14}",
        "shape", "panels", "method", "steps", "rhs evals", "wall s / sim s", "µs / (step·body)", "angle err rad"
    );
    for kind in ["chain", "grid"] {
        for &n in sizes {
            if kind == "grid" && n < 4 {
                continue;
            }
            let s = structure(kind, n, &p);
            let reference = (n <= 256).then(|| timed_run(&s, "dop853", tolerance * 1e-3).1);
            for method in ["dop853", "sdirk4"] {
                let (r, rows) = timed_run(&s, method, tolerance);
                let err =
                    reference.as_ref().map(|rf| format!("{:.1e}", max_angle_error(&rows, rf))).unwrap_or("–".into());
                println!(
                    "{kind:>6} {n:>6} {method:>8} {:>8} {:>10} {:>14.3} {:>16.2} {err:>14}",
                    r.steps_accepted,
                    r.rhs_evaluations,
                    r.wall_seconds / duration,
                    r.wall_seconds * 1e6 / (r.steps_accepted.max(1) * s.model.bodies.len()) as f64
                );
            }
        }
    }
}

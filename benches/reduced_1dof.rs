//! Experiment, not a feature: what reduced coordinates would cost for the 1-DOF hinged-panel
//! example (a hub and two panels, each on a hinge locked in five directions), against the
//! maximal-coordinate right-hand side with those directions locked and with them free.
//!
//! The hinge-law issue asks that a locked direction not make a run slower than the same
//! hinge with it free. In maximal coordinates a lock adds a multiplier solve to every
//! evaluation; reduced coordinates (a hub state plus one angle per hinge, accelerations by
//! the articulated-body algorithm) remove the locked directions from the state instead. This
//! bench times just enough of that to measure it (`tests/aba`, which `tests/locked.rs` checks
//! against the maximal-coordinate locked accelerations), against the maximal-coordinate
//! right-hand side locked and free.
//! Run: `cargo bench --bench reduced_1dof`.

#[path = "../tests/aba/mod.rs"]
mod aba;
use aba::{Reduced, Scratch, compare, example, moving_state};
use foldsim::dynamics::Dynamics;
use foldsim::kinematics::initial_state;
use std::time::Instant;

fn per_eval(mut f: impl FnMut()) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..10 {
        let start = Instant::now();
        for _ in 0..20_000 {
            f();
        }
        best = best.min(start.elapsed().as_secs_f64() / 20_000.0);
    }
    best
}

fn main() {
    if std::env::args().any(|a| a == "--help" || a == "-h") {
        println!(
            "cargo bench --bench reduced_1dof\n\nAn experiment: what reduced coordinates would cost on the 1-DOF hinged-panels example,\nagainst the locked maximal-coordinate right-hand side. No options."
        );
        return;
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("reduced-coordinate experiment, 1-DOF hinged panels (load {})", load.trim());
    let s = example(true);
    let x = moving_state(&s);
    let (y, hub_diff, scale, yaw_diff) = compare(&s, &x);
    println!(
        "check against the locked maximal RHS: hub accelerations {hub_diff:.1e} of {scale:.1e}, yaw accelerations {yaw_diff:.1e}"
    );
    assert!(hub_diff <= 1e-12 * scale.max(1.0) && yaw_diff <= 1e-12, "reduced and maximal disagree");
    let (y0, refs) = initial_state(&s.model, &s.initial);
    let dynamics = Dynamics::new(&s.model, refs.clone());
    dynamics.initialize_memory(&y0);
    let reduced = Reduced { s: &s, refs };
    let mut scratch = Scratch::default();
    let mut dydt = vec![0.0; y.len()];

    let free = example(false);
    let (yf, refs_f) = initial_state(&free.model, &free.initial);
    let dyn_free = Dynamics::new(&free.model, refs_f);
    dyn_free.initialize_memory(&yf);
    let mut d2 = vec![0.0; yf.len()];
    let t_reduced = per_eval(|| {
        std::hint::black_box(reduced.accelerations(std::hint::black_box(&x), &mut scratch));
    });
    let t_locked = per_eval(|| dynamics.rhs(std::hint::black_box(&y), &mut dydt));
    let t_free = per_eval(|| dyn_free.rhs(std::hint::black_box(&yf), &mut d2));
    println!(
        "µs per evaluation (fastest of 10 batches): maximal free {:.3}, maximal locked {:.3}, reduced {:.3}",
        t_free * 1e6,
        t_locked * 1e6,
        t_reduced * 1e6
    );
    println!("state numbers: maximal {}, reduced {}", y.len(), x.len() + s.model.hinges.len());
}

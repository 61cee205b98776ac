//! The flasher at scale (issue: a flasher of at least 200 panels, stiff off-axis hinges, soft
//! folds, 60 s of deployment from stowed in at most 10 s of wall time on one core, momentum
//! conserved to 1e-9): `examples/flasher-starshade.toml` (12 gores, 5 rings: 228 triangular
//! panels and a hub, 336 hinges of which 108 close loops; 1e7 N/m and 1e4 N·m/rad off-axis,
//! 0.2 N·m/rad folds with 1 N·m·s/rad damping; SDIRK4 at rtol = atol = 1e-4).
//!
//! Prints the machine's load, the run's wall time (median of `--repeat` runs, default 3),
//! its steps, Newton iterations, Jacobians and right-hand-side evaluations, the momentum
//! drifts, and where the time goes: the unit cost of one right-hand side, one exact Jacobian
//! with its factorization, one refactorization (new hγ) and one Newton solve, measured at the
//! stowed state, times how many of each the run made (solves: one per Newton iteration and
//! one per accepted step for the error estimate), and the rest (integrator bookkeeping,
//! observations).
//! Run: `cargo bench --bench flasher` (`-- --repeat N`; `-- --scenario FILE` for another
//! scenario, as the 996-panel flasher of docs/architecture.md, *Scale*; `-- --help`).

use foldsim::dynamics::Dynamics;
use foldsim::dynamics::newton::GraphNewton;
use foldsim::integrate::{NewtonMatrix, OdeSystem};
use foldsim::kinematics::initial_state;
use foldsim::scenario::Scenario;
use foldsim::simulate::simulate;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

mod common;
use common::{load, per_call, print_breakdown, repeat_arg};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!(
            "cargo bench --bench flasher [-- --repeat N] [-- --scenario FILE]: the 228-panel flasher example \
             (or FILE), its whole run, with its cost split"
        );
        return;
    }
    let repeat = repeat_arg(&args);
    let path = match args.iter().position(|a| a == "--scenario") {
        Some(i) => PathBuf::from(args.get(i + 1).unwrap_or_else(|| panic!("--scenario needs a file"))),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/flasher-starshade.toml"),
    };
    let s = Scenario::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
    println!("load average before: {}", load());
    println!(
        "{}: {} bodies, {} hinges ({} loop), {} s simulated",
        s.title.as_deref().unwrap_or("flasher"),
        s.model.bodies.len(),
        s.model.hinges.len(),
        s.model.is_tree_hinge.iter().filter(|t| !**t).count(),
        s.settings.duration
    );
    let mut walls = Vec::new();
    let mut report = None;
    for _ in 0..repeat.max(1) {
        let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> { Ok(()) };
        let start = Instant::now();
        let r = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_or_else(|e| panic!("{e}"));
        walls.push(start.elapsed().as_secs_f64());
        report = Some(r);
    }
    walls.sort_by(f64::total_cmp);
    let wall = walls[walls.len() / 2];
    let r = report.expect("ran");
    let d = &r.drift;
    println!("wall time {wall:.3} s (median of {}; all {walls:.3?}), load after: {}", walls.len(), load());
    println!(
        "steps {} accepted, {} rejected; Newton iterations {}; Jacobians {}; rhs evaluations {}",
        r.steps_accepted, r.steps_rejected, r.newton_iterations, r.jacobians, r.rhs_evaluations
    );
    println!(
        "momentum drift: P {:.2e} of Σ m|v|, H {:.2e} of Σ |r×mv|+|Iω| (bound 1e-9); 90 % deployed at {:?} s",
        d.momentum / d.momentum_scale,
        d.angular_momentum / d.angular_momentum_scale,
        r.deployed_90
    );

    // Unit costs at the stowed state.
    let (y, refs) = initial_state(&s.model, &s.initial);
    let dynamics = Dynamics::new(&s.model, refs);
    let mut f = vec![0.0; y.len()];
    let rhs = per_call(|| OdeSystem::rhs(&dynamics, 0.0, black_box(&y), &mut f));
    let mut newton = GraphNewton::new_exact(&dynamics, &s.model, &dynamics);
    let h_gamma = 1e-3;
    let jacobian = per_call(|| assert!(newton.prepare(0.0, &y, h_gamma)));
    let mut flip = false;
    let refactor = per_call(|| {
        flip = !flip;
        assert!(newton.refactor(if flip { 1.1e-3 } else { 1e-3 }));
    });
    let mut b = f.clone();
    let solve = per_call(|| {
        b.copy_from_slice(&f);
        newton.solve(&mut b);
    });
    let parts = [
        ("right-hand sides", rhs * r.rhs_evaluations as f64, format!("{:.1} µs each", rhs * 1e6)),
        ("Jacobians + factorization", jacobian * r.jacobians as f64, format!("{:.2} ms each", jacobian * 1e3)),
        (
            "refactorizations",
            refactor * r.refactorizations as f64,
            format!("{:.2} ms each, {} of them", refactor * 1e3, r.refactorizations),
        ),
        (
            "Newton solves",
            solve * (r.newton_iterations as f64 + r.steps_accepted as f64),
            format!("{:.1} µs each", solve * 1e6),
        ),
    ];
    print_breakdown(&parts, wall, "the stowed state");
}

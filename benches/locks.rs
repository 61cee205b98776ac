//! Cost of locked hinge directions against the same hinges with those directions free
//! (the hinge-law issue: a lock must not make a run slower than leaving the direction free).
//!
//! Cases, built from the shipped examples by changing only the named directions:
//! - `examples/zfold-tape-latch.toml`, 10 s: the z translation (out of plane) locked vs free,
//!   and all three out-of-plane directions (z, rx, ry) locked vs free. The deployment is
//!   planar, so both variants follow the same motion.
//! - `examples/hinged-panels-1dof.toml`, 300 s: five directions locked vs free (free, the
//!   panels drift apart: a different motion, reported for completeness; locked, x and y
//!   carry the load and z, rx, ry none).
//! - the z-fold example with its five off-axis directions at the stiffness
//!   normal for real hinges (1e7 N/m, 1e5 N·m/rad), rtol = atol = 1e-8, with DOP853 and
//!   with SDIRK4 (free, the panels drift apart).
//! - the z-fold example with x and y locked in every variant (loaded locks), and z, rx, ry
//!   locked or free, under DOP853 and SDIRK4 (rtol = atol = 1e-8).
//!
//! For each: the cost of one right-hand-side evaluation at the initial state with every
//! lock engaged (solved for: the most a lock can cost per evaluation), and the whole run's
//! wall time (median of alternating repetitions), with the RHS count and the locks that
//! engaged over the run (a run solves for a lock only once it carries load: see
//! `Dynamics::disengage_locks`); ratios are to the free variant's wall time. A third
//! variant, `stiff`, replaces the lock by the spring a user would otherwise model a rigid
//! direction with (the z-fold example's own off-axis springs, 2e5 N/m and 2e3 N·m/rad,
//! damped; or the stiffer ones of the last cases; one run).
//!
//! Then the scaling of the lock solve with a hub holding N panels on hinges locked in five
//! directions (every lock row couples through the hub: `J M⁻¹ Jᵀ` is dense, so the solve
//! eliminates along the tree of locked hinges instead): cost per RHS and per lock for
//! N = 8 … 512.
//! Prints the machine's load average, since these machines are shared.
//! Run: `cargo bench --bench locks` (add `-- --quick` for a short pass, or
//! `-- --profile CASE free|locked` with CASE 0 … 4 for one RHS loop under a profiler, or
//! `-- --profile-run CASE free|locked|stiff` for three whole runs; `-- --sweep` for the
//! stiffness sweep of [`sweep`] instead of the cases).

use foldsim::dynamics::Dynamics;
use foldsim::kinematics::initial_state;
use foldsim::scenario::Scenario;
use foldsim::simulate::simulate;
use std::path::Path;
use std::time::Instant;

mod common;
use common::load;

/// Springs for the `stiff` variant: (translational, rotational) law entries.
const EXAMPLE_SPRINGS: (&str, &str) = ("k = 2e5, damping = 20.0", "k = 2e3, damping = 0.5");
const DESIGN_SPRINGS: (&str, &str) = ("k = 1e7, damping = 100.0", "k = 1e5, damping = 5.0");

/// One bench case: name, example file, directions changed, directions locked in every
/// variant, duration (s), springs of the `stiff` variant, and other `[run]` settings
/// replaced (key, value).
type Case = (
    &'static str,
    &'static str,
    &'static [&'static str],
    &'static [&'static str],
    f64,
    (&'static str, &'static str),
    &'static [(&'static str, &'static str)],
);

/// The example `file` with every hinge's `directions` set to `response` (`free`, `locked`,
/// or `stiff`: the `springs`) and its `fixed` directions locked, the run cut to `duration`
/// s, with the `[run]` keys of `settings` replaced.
fn variant(
    file: &str,
    directions: &[&str],
    fixed: &[&str],
    response: &str,
    duration: f64,
    springs: (&str, &str),
    settings: &[(&str, &str)],
) -> Scenario {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(examples.join(file)).expect("example exists");
    let mut out = String::new();
    for line in text.lines() {
        let key = line.split('=').next().unwrap_or("").trim();
        if directions.contains(&key) && line.trim_start().starts_with(key) {
            let spring = if key.starts_with('r') { springs.1 } else { springs.0 };
            let r = if response == "stiff" { spring.to_string() } else { format!("{response} = true") };
            out.push_str(&format!("{key} = {{ {r} }}\n"));
        } else if fixed.contains(&key) && line.trim_start().starts_with(key) {
            out.push_str(&format!("{key} = {{ locked = true }}\n"));
        } else if key == "duration" {
            out.push_str(&format!("duration = {duration}\n"));
        } else if let Some((k, v)) = settings.iter().find(|(k, _)| *k == key) {
            out.push_str(&format!("{k} = {v}\n"));
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    Scenario::from_toml_in(&out, file, &examples).expect("variant is valid")
}

/// A 500 kg hub with `n` 2 kg panels around it, each on a hinge locked in five directions
/// with a 1 N·m/rad fold spring, folds 10–29°.
fn star(n: usize) -> Scenario {
    let mut t =
        String::from("[run]\nduration = 1.0\noutput_step = 0.1\nintegrator = \"dop853\"\nrtol = 1e-8\natol = 1e-8\n");
    t += "[[body]]\nname = \"hub\"\nmass = 500.0\ninertia = [300.0, 300.0, 300.0]\n";
    for i in 0..n {
        t += &format!("[[body]]\nname = \"p{i}\"\nmass = 2.0\ninertia = [0.1, 0.2, 0.2]\n");
    }
    for i in 0..n {
        let a = 360.0 * i as f64 / n as f64;
        let (x, y) = (2.0 * a.to_radians().cos(), 2.0 * a.to_radians().sin());
        t += &format!(
            "[[hinge]]\nname = \"h{i}\"\nparent = \"hub\"\nchild = \"p{i}\"\na0 = {{ position = [{x}, {y}, 0.0], yaw_deg = {a} }}\na = {{ child_com = [0.5, 0.0, 0.0] }}\nlaw = {{ type = \"directional\", angles = \"euler\", x = \"locked\", y = \"locked\", z = \"locked\", rx = \"locked\", ry = \"locked\", rz = {{ k = 1.0 }} }}\n"
        );
    }
    for i in 0..n {
        t += &format!("[initial.hinge.h{i}]\nyaw_deg = {}\n", 10 + (i * 7) % 20);
    }
    Scenario::from_toml(&t, "star").expect("star scenario is valid")
}

/// Seconds per right-hand-side evaluation at the scenario's initial state.
fn rhs_cost(s: &Scenario, budget: f64) -> f64 {
    let (y, refs) = initial_state(&s.model, &s.initial);
    let dynamics = Dynamics::new(&s.model, refs);
    dynamics.initialize_memory(&y);
    let mut dydt = vec![0.0; y.len()];
    let (mut evals, start) = (0u64, Instant::now());
    while start.elapsed().as_secs_f64() < budget {
        for _ in 0..64 {
            dynamics.rhs(std::hint::black_box(&y), &mut dydt);
        }
        evals += 64;
    }
    std::hint::black_box(&dydt);
    start.elapsed().as_secs_f64() / evals as f64
}

/// Wall time (s), RHS evaluations, and locks engaged (of all) of one whole run.
fn run(s: &Scenario) -> (f64, u64, (usize, usize)) {
    let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> { Ok(()) };
    let r = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).expect("runs");
    (r.wall_seconds, r.rhs_evaluations, (r.lock_engagements.len(), r.drift.locks))
}

/// Locked against the hinge's own law: the z-fold example with `directions` locked, or held
/// by springs from the example's own (2e5 N/m, 2e3 N·m/rad) up through the normal
/// range for real hinges (1e6–1e9 N/m; rotational stiffness 1/100 of it in N·m/rad), damped
/// in proportion to √k from the example's damping, under DOP853 at the example's tolerance
/// and SDIRK4 at 1e-8. Prints run wall time locked / spring (median of `reps` alternating
/// runs each) and the RHS evaluations.
fn sweep(reps: usize) {
    const STIFFNESS: [f64; 5] = [2e5, 1e6, 1e7, 1e8, 1e9];
    println!("\nlocked vs spring of stiffness k (N/m; k/100 N·m/rad): run wall locked / spring [RHS evals spring]");
    print!("{:<34} {:>10}", "directions, integrator", "locked s");
    for k in STIFFNESS {
        print!(" {:>22}", format!("k = {k:e}"));
    }
    println!();
    let integrators: [(&str, &[(&str, &str)]); 2] =
        [("dop853 1e-10", &[]), ("sdirk4 1e-8", &[("rtol", "1e-8"), ("atol", "1e-8"), ("integrator", "\"sdirk4\"")])];
    let direction_sets: [&[&str]; 3] = [&["z"], &["z", "rx", "ry"], &["x", "y", "z", "rx", "ry"]];
    for (integrator, settings) in integrators {
        for dirs in direction_sets {
            let file = "zfold-tape-latch.toml";
            let locked = variant(file, dirs, &[], "locked", 10.0, EXAMPLE_SPRINGS, settings);
            let (mut wall_locked, mut n_locked) = (Vec::new(), 0);
            let mut row = String::new();
            for k in STIFFNESS {
                let k_r = k / 100.0;
                let translational = format!("k = {k:e}, damping = {:e}", 20.0 * (k / 2e5).sqrt());
                let rotational = format!("k = {k_r:e}, damping = {:e}", 0.5 * (k_r / 2e3).sqrt());
                let spring = variant(file, dirs, &[], "stiff", 10.0, (&translational, &rotational), settings);
                let ((w_locked, n), (wall_spring, n_spring)) = alternate(&locked, &spring, reps);
                wall_locked.extend(w_locked);
                n_locked = n;
                let ratio = median(wall_locked.clone()) / median(wall_spring);
                row += &format!(" {:>22}", format!("{ratio:.2} [{n_spring}]"));
            }
            let name = format!("{}, {integrator}", dirs.join(" "));
            println!("{name:<34} {:>10.4}{row}   (locked: {n_locked} RHS)", median(wall_locked));
        }
    }
}

/// Wall times of `reps` whole runs of `a` and `b`, alternating (the machine's load drifts),
/// and each one's RHS evaluations.
fn alternate(a: &Scenario, b: &Scenario, reps: usize) -> ((Vec<f64>, u64), (Vec<f64>, u64)) {
    let ((mut wall_a, mut n_a), (mut wall_b, mut n_b)) = ((Vec::new(), 0), (Vec::new(), 0));
    for _ in 0..reps {
        let (w, n, _) = run(a);
        wall_a.push(w);
        n_a = n;
        let (w, n, _) = run(b);
        wall_b.push(w);
        n_b = n;
    }
    ((wall_a, n_a), (wall_b, n_b))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

const USAGE: &str = "cargo bench --bench locks [-- OPTIONS]

Locked directions against the same directions free and against stiff springs (z-fold and
1-DOF examples, DOP853 and SDIRK4), median of alternating runs, with the machine load.

  --quick                        short budgets (the default under `cargo test --benches`)
  --sweep                        locks against springs from 2e5 to 1e9 N/m
  --profile CASE free|locked     only case CASE's (0-6) right-hand-side loop, for a profiler
  --profile-run CASE free|locked|stiff   case CASE's whole run, three times
  -h, --help                     this text";

fn main() {
    if std::env::args().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return;
    }
    let quick = std::env::args().any(|a| a == "--quick") || !std::env::args().any(|a| a == "--bench");
    let (budget, reps) = if quick { (0.05, 1) } else { (0.5, 7) };
    println!("foldsim locks bench (load average {})", load());
    println!(
        "{:<36} {:>7} {:>12} {:>10} {:>12} {:>8} {:>9}",
        "case", "variant", "µs/rhs all", "rhs evals", "run wall s", "ratio", "engaged"
    );
    const OFF_AXIS: &[&str] = &["x", "y", "z", "rx", "ry"];
    const TIGHT: &[(&str, &str)] = &[("rtol", "1e-8"), ("atol", "1e-8")];
    const TIGHT_IMPLICIT: &[(&str, &str)] = &[("rtol", "1e-8"), ("atol", "1e-8"), ("integrator", "\"sdirk4\"")];
    const Z: &[&str] = &["z", "rx", "ry"];
    let cases: [Case; 7] = [
        ("zfold-tape-latch, z", "zfold-tape-latch.toml", &["z"], &[], 10.0, EXAMPLE_SPRINGS, &[]),
        ("zfold-tape-latch, z rx ry", "zfold-tape-latch.toml", Z, &[], 10.0, EXAMPLE_SPRINGS, &[]),
        ("zfold, x y locked; z rx ry", "zfold-tape-latch.toml", Z, &["x", "y"], 10.0, EXAMPLE_SPRINGS, &[]),
        (
            "zfold, x y locked; z rx ry, sdirk4",
            "zfold-tape-latch.toml",
            Z,
            &["x", "y"],
            10.0,
            EXAMPLE_SPRINGS,
            TIGHT_IMPLICIT,
        ),
        ("hinged-panels-1dof, x y z rx ry", "hinged-panels-1dof.toml", OFF_AXIS, &[], 300.0, EXAMPLE_SPRINGS, &[]),
        ("zfold 1e7/1e5, x y z rx ry, dop853", "zfold-tape-latch.toml", OFF_AXIS, &[], 10.0, DESIGN_SPRINGS, TIGHT),
        (
            "zfold 1e7/1e5, x y z rx ry, sdirk4",
            "zfold-tape-latch.toml",
            OFF_AXIS,
            &[],
            10.0,
            DESIGN_SPRINGS,
            TIGHT_IMPLICIT,
        ),
    ];
    // `-- --profile CASE_INDEX free|locked`: only that case's RHS loop, for a profiler.
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--profile") {
        let (_, file, dirs, fixed, duration, springs, settings) =
            cases[args[i + 1].parse::<usize>().expect("case index")];
        let s = variant(file, dirs, fixed, &args[i + 2], duration, springs, settings);
        println!("{:.3} µs/rhs", rhs_cost(&s, 3.0) * 1e6);
        return;
    }
    if args.iter().any(|a| a == "--sweep") {
        sweep(reps.min(3));
        return;
    }
    // `-- --profile-run CASE_INDEX free|locked|stiff`: that case's whole run, three times.
    if let Some(i) = args.iter().position(|a| a == "--profile-run") {
        let (_, file, dirs, fixed, duration, springs, settings) =
            cases[args[i + 1].parse::<usize>().expect("case index")];
        let s = variant(file, dirs, fixed, &args[i + 2], duration, springs, settings);
        for _ in 0..3 {
            let (wall, evals, _) = run(&s);
            println!("{wall:.4} s, {evals} rhs");
        }
        return;
    }
    for (name, file, dirs, fixed, duration, springs, settings) in cases {
        let [free, locked, stiff] =
            ["free", "locked", "stiff"].map(|r| variant(file, dirs, fixed, r, duration, springs, settings));
        let [cost_free, cost_locked, cost_stiff] = [&free, &locked, &stiff].map(|s| rhs_cost(s, budget));
        let (wall_stiff, n_stiff, engaged_stiff) = run(&stiff);
        let ((wall_free, n_free), (wall_locked, n_locked)) = alternate(&free, &locked, reps);
        let (wf, wl) = (median(wall_free), median(wall_locked));
        let engaged = |v: &Scenario| {
            let (_, _, (e, all)) = run(v);
            format!("{e}/{all}")
        };
        let rows = [
            ("free", cost_free, n_free, wf, engaged(&free)),
            ("locked", cost_locked, n_locked, wl, engaged(&locked)),
            ("stiff", cost_stiff, n_stiff, wall_stiff, format!("{}/{}", engaged_stiff.0, engaged_stiff.1)),
        ];
        for (k, (variant, cost, n, wall, engaged)) in rows.into_iter().enumerate() {
            let label = if k == 0 { name } else { "" };
            let ratio = if k == 0 { String::new() } else { format!("{:.3}", wall / wf) };
            println!("{label:<36} {variant:>7} {:>12.3} {n:>10} {wall:>12.4} {ratio:>8} {engaged:>9}", cost * 1e6);
        }
    }
    println!("\nhub with N panels, five locked directions per hinge:");
    println!("{:>6} {:>8} {:>12} {:>14}", "N", "locks", "µs/rhs", "ns/lock/rhs");
    for n in [8, 32, 128, 512] {
        let s = star(n);
        let c = rhs_cost(&s, budget);
        println!("{n:>6} {:>8} {:>12.2} {:>14.1}", 5 * n, c * 1e6, c * 1e9 / (5 * n) as f64);
    }
    println!("\nload average after: {}", load());
}

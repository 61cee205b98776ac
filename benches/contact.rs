//! What contact costs (docs/contact.md): the 228-panel starshade (`examples/flasher-starshade.toml`
//! with 1 cm thick panels), starting deployed and flat, its hub set turning about a diameter
//! at 0.05 rad/s so the disc flaps, 10 s under SDIRK4 at rtol 1e-4: the run with `[contact]` and
//! without, alternated, medians of `--repeat` each (default 3), with the machine's load. Also
//! the cost of one right-hand side with and without contact at the start. The bound:
//! with contact enabled and nothing touching, at most 1.5× the run without.
//!
//! Then full contact: the thick flasher example (`examples/flasher-thick.toml`, 5 gores, 2
//! rings, 1-cm panels stowed in nested layers face to face, membrane hinges) over its first 0.05 s, where
//! every layer presses on the next: its steps (and of the rejected, Newton's), pairs and
//! points in contact per accepted step, and where the time goes (unit costs at the run's
//! middle, the right-hand side's at a trial state a mean step ahead, times how many of each the run made: right-hand sides, of which the contact part
//! is the difference to the same state without `[contact]`, Jacobians with factorization,
//! Newton solves).
//! Then stacks of ten and fifty plates at rest (`stacks`).
//! Run: `cargo bench --bench contact` (`-- --repeat N`; `-- --full-only` for the second part
//! and the stacks, `-- --stacks-only` for the stacks alone).

use foldsim::dynamics::Dynamics;
use foldsim::dynamics::newton::GraphNewton;
use foldsim::integrate::NewtonMatrix;
use foldsim::integrate::OdeSystem;
use foldsim::kinematics::initial_state;
use foldsim::scenario::Scenario;
use foldsim::simulate::simulate;
use foldsim::simulate::stepper::Stepper;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

mod common;
use common::{load, per_call, print_breakdown, repeat_arg};

/// The starshade example's flasher (its generator options) with 1-cm panels, as the generator
/// makes thick flashers (corners cut back at the pattern's vertices, so that no two panels
/// overlap in the flat sheet: the example's thin outlines made thick did, tip to tip),
/// deployed and flapping, with `contact` appended.
fn starshade(contact: &str) -> Scenario {
    use foldsim::generate::flasher::FlasherLaws;
    use foldsim::generate::options::FlasherOptions;
    let options = FlasherOptions {
        gores: 12,
        rings: 5,
        hub_radius: 3.0,
        hub_mass: 500.0,
        areal_density: 1.0,
        thickness: 0.01,
        laws: FlasherLaws {
            k_fold: 0.2,
            c_fold: Some(1.0),
            k_bending: 0.2,
            c_bending: 1.0,
            k_translation: 1e7,
            c_translation: 100.0,
            k_rotation: 1e4,
            c_rotation: 1.0,
            // No stops at flat: flapping about flat would hit them in both runs alike, and
            // what is measured here is the contact search's cost; and pins (no membranes), as
            // when its figures were measured.
            k_stop: 0.0,
            membrane_bending: 0.0,
            ..FlasherLaws::default()
        },
        duration: 10.0,
        integrator: Some("sdirk4".into()),
        tolerance: Some(1e-4),
        ..FlasherOptions::default()
    };
    let (text, _) = options.scenario(&|k: &str| k.to_string()).unwrap_or_else(|e| panic!("{e}"));
    // The deployed design: no initial state (and no generated [contact] table, which follows it).
    let body = text.split("\n[initial").next().expect("text");
    let text = format!("{body}\n[initial.hub]\nomega = [0.05, 0.0, 0.0]\n{contact}");
    Scenario::from_toml(&text, "starshade-contact").unwrap_or_else(|e| panic!("{e}"))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!(
            "cargo bench --bench contact [-- --repeat N] [--full-only | --stacks-only]: the starshade with and without contact, nothing touching; the thick flasher's stowed start in full contact; stacks of 10 and 50 plates at rest"
        );
        return;
    }
    let repeat = repeat_arg(&args);
    if args.iter().any(|a| a == "--stacks-only") {
        return stacks();
    }
    if !args.iter().any(|a| a == "--full-only") {
        nothing_touching(repeat);
    }
    full_contact(repeat);
    stacks();
}

/// Ten and fifty 1 m × 1 m plates, 1 cm thick, z-folded flat at zero gap (each fold a hinge
/// on the face the two plates share, as `tests/contact.rs`'s stack of ten), left for 10 s
/// under each method: the largest kinetic energy (the bound: 1e-9 J) and the cost
/// per step.
fn stacks() {
    for n in [10usize, 50] {
        for (method, tol) in [("sdirk4", 1e-6), ("dop853", 1e-8)] {
            let h = 0.01;
            let mut text = format!(
                "[run]\nduration = 10.0\noutput_step = 0.5\nintegrator = \"{method}\"\nrtol = {tol:e}\natol = {tol:e}\n"
            );
            for i in 0..n {
                text += &format!(
                    "\n[[body]]\nname = \"p{i}\"\nshape = {{ polygon = [[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]], thickness = {h} }}\ndensity = 10.0\n"
                );
            }
            for i in 0..n - 1 {
                let s = if i % 2 == 0 { 1.0 } else { -1.0 };
                text += &format!(
                    "\n[[hinge]]\nname = \"f{i}\"\nparent = \"p{i}\"\nchild = \"p{j}\"\na0 = {{ position = [0.5, 0.0, {z}], roll_deg = 90.0 }}\na = {{ child_com = [0.5, {zc}, 0.0], roll_deg = -90.0 }}\nlaw = {{ type = \"directional\", angles = \"euler\", x = {{ k = 1e6 }}, y = {{ k = 1e6 }}, z = {{ k = 1e6 }}, rx = {{ k = 1e4 }}, ry = {{ k = 1e4 }}, rz = \"free\" }}\n[initial.hinge.f{i}]\nyaw_deg = 180.0\n",
                    j = i + 1,
                    z = s * h / 2.0,
                    zc = -s * h / 2.0,
                );
            }
            text += "\n[contact]\nstiffness = 1e8\nrestitution = 0.5\nfriction = 0.3\n";
            let s = Scenario::from_toml(&text, "stack.toml").unwrap_or_else(|e| panic!("{e}"));
            let mut kinetic: f64 = 0.0;
            let mut sink = |o: &foldsim::observe::Observation| -> Result<(), String> {
                kinetic = kinetic.max(o.kinetic_energy);
                Ok(())
            };
            let load_before = load();
            let start = Instant::now();
            let r = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_or_else(|e| panic!("{e}"));
            let wall = start.elapsed().as_secs_f64();
            let steps = r.steps_accepted + r.steps_rejected;
            println!(
                "stack of {n} plates, 1 cm, 10 s, {method} at {tol:e}: kinetic energy at most {kinetic:.1e} J; {wall:.3} s wall, {} steps ({} rejected), {:.1} µs per step; load {load_before} → {}",
                r.steps_accepted,
                r.steps_rejected,
                1e6 * wall / steps.max(1) as f64,
                load()
            );
        }
    }
}

/// The thick flasher's stowed start in full contact (see the module documentation).
fn full_contact(repeat: usize) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(dir.join("flasher-thick.toml")).expect("example");
    // Its [run] duration cut to 0.05 s, whatever the example's is.
    let text: String = text
        .lines()
        .map(|l| if l.starts_with("duration = ") { "duration = 0.05".to_string() } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    assert!(text.contains("\nduration = 0.05"), "flasher-thick.toml has no [run] duration line");
    let s = Scenario::from_toml_in(&text, "flasher-thick-stowed", &dir).unwrap_or_else(|e| panic!("{e}"));
    let bare = Scenario::from_toml_in(text.split("\n[contact]").next().expect("text"), "bare", &dir)
        .unwrap_or_else(|e| panic!("{e}"));
    let samples: usize =
        s.model.contact.as_ref().map_or(0, |c| c.solids.iter().flatten().map(|s| s.samples.len()).sum());
    println!("\nload average before: {}", load());
    println!(
        "full contact: examples/flasher-thick.toml's first 0.05 s ({} bodies, {samples} contact sample points), {}",
        s.model.bodies.len(),
        s.settings.integrator.name()
    );
    let (mut walls, mut report, mut per_row) = (Vec::new(), None, (0usize, 0usize, 0usize));
    for _ in 0..repeat.max(1) {
        let mut rows = (0usize, 0usize, 0usize);
        let mut sink = |o: &foldsim::observe::Observation| -> Result<(), String> {
            let c = o.contact.unwrap_or_default();
            rows = (rows.0 + 1, rows.1 + c.pairs, rows.2 + c.points);
            Ok(())
        };
        let start = Instant::now();
        let r = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_or_else(|e| panic!("{e}"));
        walls.push(start.elapsed().as_secs_f64());
        report = Some(r);
        per_row = rows;
    }
    walls.sort_by(f64::total_cmp);
    let wall = walls[walls.len() / 2];
    let r = report.expect("ran");
    println!("wall time {wall:.3} s (median of {}; all {walls:.3?}), load after: {}", walls.len(), load());
    println!(
        "steps {} accepted, {} rejected ({} for Newton not converging); Newton iterations {}; Jacobians {}; rhs evaluations {}",
        r.steps_accepted, r.steps_rejected, r.newton_failures, r.newton_iterations, r.jacobians, r.rhs_evaluations
    );
    let rows = per_row.0.max(1) as f64;
    println!(
        "in contact, mean over the {} output rows: {:.1} body pairs, {:.0} sample points",
        per_row.0,
        per_row.1 as f64 / rows,
        per_row.2 as f64 / rows
    );
    // Unit costs at the run's middle, as its steps see the package (at t = 0 the layers
    // sit at exactly zero gap, every face sample touching: several times a step's cost).
    let mut stepper = Stepper::start(&s.model, &s.initial, &s.settings).unwrap_or_else(|e| panic!("{e}"));
    stepper.advance(0.5 * s.settings.duration).unwrap_or_else(|e| panic!("{e}"));
    // Most right-hand sides are at a step's trial states (Newton's iterates), not at the
    // accepted state the proximity list was measured at: time them one mean step ahead.
    let (dynamics, y) = (stepper.dynamics(), stepper.state().to_vec());
    let mut f = vec![0.0; y.len()];
    let at_accepted = per_call(|| OdeSystem::rhs(dynamics, 0.0, black_box(&y), &mut f));
    let h = s.settings.duration / r.steps_accepted.max(1) as f64;
    let y_trial: Vec<f64> = y.iter().zip(&f).map(|(y, f)| y + h * f).collect();
    let mut f_trial = vec![0.0; y.len()];
    let rhs = per_call(|| OdeSystem::rhs(dynamics, 0.0, black_box(&y_trial), &mut f_trial));
    let hinges_only = {
        let (_, refs) = initial_state(&bare.model, &bare.initial);
        let d = Dynamics::new(&bare.model, refs);
        d.initialize_memory(&y);
        let mut g = vec![0.0; y.len()];
        per_call(|| OdeSystem::rhs(&d, 0.0, black_box(&y_trial), &mut g))
    };
    let at_start = {
        let (y0, refs) = initial_state(&s.model, &s.initial);
        let d = Dynamics::new(&s.model, refs);
        d.initialize_memory(&y0);
        let mut g = vec![0.0; y0.len()];
        per_call(|| OdeSystem::rhs(&d, 0.0, black_box(&y0), &mut g))
    };
    println!(
        "one right-hand side: {:.1} µs at the start (layers at exactly zero gap, every face sample touching); at the run's middle {:.1} µs at its accepted state, {:.1} µs a mean step ({h:.2e} s) ahead",
        at_start * 1e6,
        at_accepted * 1e6,
        rhs * 1e6
    );
    let mut newton = GraphNewton::new_exact(dynamics, &s.model, dynamics);
    let jacobian = per_call(|| assert!(newton.prepare(0.0, &y, 1e-5)));
    let mut b = f.clone();
    let solve = per_call(|| {
        b.copy_from_slice(&f);
        newton.solve(&mut b);
    });
    let t_mid = stepper.time();
    let accept = per_call(|| dynamics.accept(t_mid, black_box(&y)).unwrap_or_else(|e| panic!("{e}")));
    let n_rhs = r.rhs_evaluations as f64;
    let parts = [
        ("rhs: contact", (rhs - hinges_only) * n_rhs, format!("{:.1} µs each", (rhs - hinges_only) * 1e6)),
        ("rhs: the rest", hinges_only * n_rhs, format!("{:.1} µs each", hinges_only * 1e6)),
        ("Jacobians + factorization", jacobian * r.jacobians as f64, format!("{:.2} ms each", jacobian * 1e3)),
        (
            "Newton solves",
            solve * (r.newton_iterations as f64 + r.steps_accepted as f64),
            format!("{:.1} µs each", solve * 1e6),
        ),
        (
            "accepting a step",
            accept * r.steps_accepted as f64,
            format!("{:.1} µs each: laws' memory, proximity list, contact memory", accept * 1e6),
        ),
    ];
    print_breakdown(&parts, wall, "the run's middle");
}

/// The starshade deployed and flapping with and without contact (see the module
/// documentation).
fn nothing_touching(repeat: usize) {
    let plain = starshade("");
    let with = starshade("\n[contact]\nstiffness = 1e8\nrestitution = 0.5\nfriction = 0.3\n");
    let samples: usize =
        with.model.contact.as_ref().map_or(0, |c| c.solids.iter().flatten().map(|s| s.samples.len()).sum());
    println!("load average before: {}", load());
    println!(
        "starshade, 228 panels 1 cm thick, deployed and flapping, 10 s, sdirk4 rtol 1e-4; {samples} contact sample points"
    );
    let (mut t_plain, mut t_with) = (Vec::new(), Vec::new());
    let mut touched = 0;
    let mut steps = (0, 0);
    for _ in 0..repeat.max(1) {
        for (s, times, contact) in [(&plain, &mut t_plain, false), (&with, &mut t_with, true)] {
            let mut most = 0;
            let mut sink = |o: &foldsim::observe::Observation| -> Result<(), String> {
                most = most.max(o.contact.map_or(0, |c| c.pairs));
                Ok(())
            };
            let start = Instant::now();
            let r = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_or_else(|e| panic!("{e}"));
            times.push(start.elapsed().as_secs_f64());
            if contact {
                touched = touched.max(most);
                steps.1 = r.steps_accepted;
                assert!(r.contact.is_some_and(|c| c.first.is_none()), "something touched: {:?}", r.contact);
            } else {
                steps.0 = r.steps_accepted;
            }
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (a, b) = (median(&mut t_plain), median(&mut t_with));
    println!(
        "without contact {a:.3} s ({} steps), with {b:.3} s ({} steps): ratio {:.2} (bound 1.5); pairs touching at any row: {touched}",
        steps.0,
        steps.1,
        b / a
    );
    println!("all: without {t_plain:.3?}, with {t_with:.3?}; load after: {}", load());
    // One right-hand side at the start.
    for (name, s) in [("without", &plain), ("with", &with)] {
        let (y, refs) = initial_state(&s.model, &s.initial);
        let d = Dynamics::new(&s.model, refs);
        d.initialize_memory(&y);
        let mut f = vec![0.0; y.len()];
        let start = Instant::now();
        let mut n = 0;
        while n < 20 || start.elapsed().as_secs_f64() < 0.5 {
            OdeSystem::rhs(&d, 0.0, black_box(&y), &mut f);
            n += 1;
        }
        println!("one right-hand side {name} contact: {:.1} µs", 1e6 * start.elapsed().as_secs_f64() / n as f64);
    }
}

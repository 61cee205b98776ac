//! What contact costs (docs/contact.md): the 228-panel starshade (`examples/flasher-starshade.toml`
//! with 1 cm thick panels), starting deployed and flat, its hub set turning about a diameter
//! at 0.05 rad/s so the disc flaps, 10 s under SDIRK4 at rtol 1e-4: the run with `[contact]` and
//! without, alternated, medians of `--repeat` each (default 3), with the machine's load. Also
//! the cost of one right-hand side with and without contact at the start. The bound:
//! with contact enabled and nothing touching, at most 1.5× the run without.
//! Run: `cargo bench --bench contact` (`-- --repeat N`).

use foldsim::dynamics::Dynamics;
use foldsim::integrate::OdeSystem;
use foldsim::kinematics::initial_state;
use foldsim::scenario::Scenario;
use foldsim::simulate::simulate;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

mod common;
use common::{load, repeat_arg};

/// The starshade example deployed and flapping, panels 1 cm thick, with `contact` appended.
fn starshade(contact: &str) -> Scenario {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(dir.join("flasher-starshade.toml")).expect("example");
    let body = text.split("\n[initial").next().expect("text").replace("thickness = 0.0", "thickness = 0.01");
    let body = body.replace("duration = 60.0", "duration = 10.0");
    let text = format!("{body}\n[initial.hub]\nomega = [0.05, 0.0, 0.0]\n{contact}");
    Scenario::from_toml_in(&text, "starshade-contact", &dir).unwrap_or_else(|e| panic!("{e}"))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!(
            "cargo bench --bench contact [-- --repeat N]: the starshade with and without contact, nothing touching"
        );
        return;
    }
    let repeat = repeat_arg(&args);
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

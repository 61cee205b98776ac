//! The cost of an FMU's stepping against a run of the same work (issue: ≤ 1.2× at 10 ms
//! communication steps on the three-panel case; docs/interop.md).
//!
//! The paper's three panels (`examples/paper-3panel.toml`, DOP853 at 1e-12, 20 s):
//! - **run**: `foldsim::simulate::simulate` with a row every 10 ms, each row turned into the
//!   numbers of every default column (what `foldsim run` writes, without the text);
//! - **fmu**: the FMU's own functions, as a host calls them: `fmi2DoStep` every 10 ms
//!   (each a piece of the same adaptive integration, restarted at the communication point)
//!   and `fmi2GetReal` of every output (the default columns) after each.
//!
//! `-- --dt 0.05` for another communication step (the run's rows follow it).
//! `-- --switching`: the run with a load switching at every communication point.
//! `-- --one run|fmu`: one side alone, for `valgrind --tool=callgrind` (instruction counts
//! that the machine's load does not change). Eleven rounds, the two alternated within each; medians; the machine's load printed (these
//! machines are shared). Run: `cargo bench -p foldsim-fmu --bench stepping`.

use foldsim::export::fmu::{Request, SCENARIO_FILE, VARIABLES_FILE, variables};
use foldsim::observe::{Selection, row};
use foldsim::scenario::{Scenario, ScenarioText};
use foldsim::simulate::simulate;
use foldsim_fmu::*;
use std::ffi::CString;
use std::path::Path;
use std::time::Instant;

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    // The communication step, s (`-- --dt 0.05`; the case is 10 ms).
    let args: Vec<String> = std::env::args().collect();
    let dt_arg = args.iter().position(|a| a == "--dt").and_then(|i| args.get(i + 1)).and_then(|v| v.parse().ok());
    let dt: f64 = dt_arg.unwrap_or(0.01);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("examples/paper-3panel.toml"))
        .unwrap()
        .replace("output_step = 0.05", &format!("output_step = {dt}"));
    let dir = std::env::temp_dir().join(format!("foldsim-bench-fmu-{}/resources", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(SCENARIO_FILE), &text).unwrap();
    let st = ScenarioText::new(&text, "p3.toml", &dir).unwrap();
    let v = variables(&st, &Request { parameters: Some(Vec::new()), ..Request::default() }).unwrap();
    std::fs::write(dir.join(VARIABLES_FILE), toml::to_string(&v).unwrap()).unwrap();
    let (uri, guid, name) = (
        CString::new(format!("file://{}", dir.display())).unwrap(),
        CString::new(v.guid.clone()).unwrap(),
        CString::new("bench").unwrap(),
    );
    let outputs = v.outputs.len();
    // `-- --switching`: the run also takes a load on the hub that switches at every
    // communication point (1e-9 N·m, on and off every dt), so that its integration too must
    // end a step there, as a host that may change an input at each point makes the FMU's.
    let switching = args.iter().any(|a| a == "--switching");
    let run_text = if switching {
        let windows: Vec<String> = (0..(20.0 / dt / 2.0).round() as usize)
            .map(|k| format!("[{}, {}]", (2 * k) as f64 * dt, (2 * k + 1) as f64 * dt))
            .collect();
        format!(
            "{text}\n[[load]]\nname = \"switch\"\nbody = \"hub\"\ntorque = [0.0, 0.0, 1e-9]\ntorque_frame = \"body\"\non = [{}]\n",
            windows.join(", ")
        )
    } else {
        text.clone()
    };
    let scenario = Scenario::from_toml(&run_text, "p3.toml").unwrap();
    let duration = scenario.settings.duration;
    let steps = (duration / dt).round() as usize;
    println!("three panels, {duration} s, {steps} communication steps of {dt} s, {outputs} outputs; load {}", load());

    let run = || {
        let selection = Selection::default_for(&scenario.model);
        let mut sum = 0.0;
        let mut sink = |o: &foldsim::observe::Observation| -> Result<(), String> {
            let r = row(o);
            sum += selection.indices.iter().map(|&i| r[i]).sum::<f64>();
            Ok(())
        };
        let t0 = Instant::now();
        simulate(&scenario.model, &scenario.initial, &scenario.settings, &mut sink, None).unwrap();
        (t0.elapsed().as_secs_f64(), sum)
    };
    let fmu = || {
        let t0 = Instant::now();
        let vr: Vec<u32> = (0..outputs as u32).collect();
        let mut out = vec![0.0; outputs];
        let mut sum = 0.0;
        // SAFETY: the FMI calls in the order the standard gives, on one live instance.
        unsafe {
            let c = fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), uri.as_ptr(), std::ptr::null(), 0, 0);
            assert!(!c.is_null());
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, duration), OK);
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(fmi2ExitInitializationMode(c), OK);
            for k in 0..=steps {
                assert_eq!(fmi2GetReal(c, vr.as_ptr(), outputs, out.as_mut_ptr()), OK);
                sum += out.iter().sum::<f64>();
                if k < steps {
                    assert_eq!(fmi2DoStep(c, k as f64 * dt, dt, 1), OK);
                }
            }
            fmi2FreeInstance(c);
        }
        (t0.elapsed().as_secs_f64(), sum)
    };
    // `-- --one run` or `-- --one fmu`: one of the two alone, once (for a profiler, or
    // valgrind's instruction count, which the machine's load does not change).
    if let Some(which) = args.iter().position(|a| a == "--one").and_then(|i| args.get(i + 1)) {
        let (t, _) = if which == "fmu" { fmu() } else { run() };
        println!("{which}: {t:.4} s");
        return;
    }
    // The work each does: steps and right-hand sides (one pass each, not timed).
    let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> { Ok(()) };
    let whole = simulate(&scenario.model, &scenario.initial, &scenario.settings, &mut sink, None).unwrap();
    let mut session = foldsim::session::Session::start(Scenario::from_toml(&text, "p3.toml").unwrap()).unwrap();
    for _ in 0..steps {
        session.advance(dt).unwrap();
    }
    let pieces = session.report();
    println!(
        "work: run {} steps ({} rejected), {} right-hand sides; pieces {} steps ({} rejected), {} right-hand sides",
        whole.steps_accepted,
        whole.steps_rejected,
        whole.rhs_evaluations,
        pieces.steps_accepted,
        pieces.steps_rejected,
        pieces.rhs_evaluations
    );
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for round in 0..11 {
        let (ta, sa) = run();
        let (tb, sb) = fmu();
        println!("round {round}: run {ta:.4} s, fmu {tb:.4} s ({:.2}×); sums {sa:.6e} {sb:.6e}", tb / ta);
        a.push(ta);
        b.push(tb);
    }
    let (ma, mb) = (median(a), median(b));
    println!("median: run {ma:.4} s, fmu {mb:.4} s: {:.2}× (load {})", mb / ma, load());
}

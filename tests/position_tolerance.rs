//! `run.position_tolerance` (docs/scenario.md, *A position tolerance*): the error a run
//! delivers in its bodies' positions against what was asked, the estimate it reports, and
//! the refusals.

mod common;

use foldsim::observe::Observation;
use foldsim::scenario::Scenario;
use foldsim::simulate::{RunReport, SimError, simulate};

/// The paper's three-panel case (law 1, a loop) with its tolerances replaced by `run`'s lines.
fn three_panel(run: &str) -> Result<Scenario, String> {
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel.toml")).unwrap();
    let text = text
        .replace("integrator = \"dop853\"\nrtol = 1e-12\natol = 1e-12\n", run)
        .replace("duration = 20.0", "duration = 10.0");
    assert!(text.contains(run), "the example's [run] table changed: update this test");
    Scenario::from_toml(&text, "ptol.toml").map_err(|e| e.to_string())
}

fn rows_of(s: &Scenario) -> Result<(Vec<Observation>, RunReport), SimError> {
    let mut rows = Vec::new();
    let mut sink = |o: &Observation| -> Result<(), String> {
        rows.push(o.clone());
        Ok(())
    };
    let report = simulate(&s.model, &s.initial, &s.settings, &mut sink, None)?;
    Ok((rows, report))
}

/// The largest distance of any body's centre of mass between two runs' rows, m.
fn largest_difference(a: &[Observation], b: &[Observation]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| x.body_r_in_n.iter().zip(&y.body_r_in_n).map(|(p, q)| (p - q).norm()))
        .fold(0.0, f64::max)
}

/// Asked 1e-3 and 1e-5 of the structure's size (about 5 m across its centres of mass), with
/// DOP853 and with adaptive generalized-α, against DOP853 at 1e-12 (its own error ~1e-10 m,
/// far below what is checked): the error delivered is within what was asked (the issue's
/// bound is 3 ×; the estimate's one assumption, the power law's exponent, can make it
/// optimistic only below q = 2/3), and the estimate the run reports is within a factor 2
/// below and 3 above the error (it errs by at most 1/(1 − 4^(−2/3)) = 1.66 where the power law
/// holds; generalized-α at 5e-3 came out 4 % under). A run far within what was asked is
/// loosened.
#[test]
fn delivers_the_asked_position_error() {
    let reference = three_panel("integrator = \"dop853\"\nrtol = 1e-12\natol = 1e-12\n").unwrap();
    let (truth, _) = rows_of(&reference).unwrap();
    for integrator in ["dop853", "generalized-alpha"] {
        for asked in [5e-3, 5e-5] {
            let s = three_panel(&format!("integrator = \"{integrator}\"\nposition_tolerance = {asked:e}\n")).unwrap();
            let (rows, report) = rows_of(&s).unwrap();
            let error = largest_difference(&truth, &rows);
            let a = report.position_accuracy.as_ref().expect("the report says what was estimated");
            println!(
                "{integrator} asked {asked:e} m: error {error:.2e} m, estimated {:.2e} m, {} runs {:?}",
                a.estimated,
                a.runs.len(),
                a.runs
            );
            assert!(error <= asked, "{integrator}: {error:e} m against {asked:e} m asked");
            assert!(
                a.estimated <= asked && a.estimated >= 0.5 * error && a.estimated <= 3.0 * error.max(1e-9),
                "{integrator}: estimated {:e} m against {error:e} m",
                a.estimated
            );
            assert_eq!(rows.len(), report.rows);
            assert!(a.runs.len() >= 2 && a.runs.iter().any(|r| r.0 == a.rtol));
            // An output estimated far within what was asked is one no looser run could
            // replace: a looser one was tried (docs/scenario.md, step 4), or none could be
            // (the runs spent, or the output at the loosest tolerance a run is given).
            assert!(
                3.0 * a.estimated >= asked
                    || a.runs.iter().any(|r| r.0 > a.rtol)
                    || a.runs.len() >= 8
                    || a.rtol >= foldsim::simulate::accuracy::LOOSEST,
                "{integrator}: estimated {:e} m at rtol {:e}, far within {asked:e} m, and no looser run tried: {:?}",
                a.estimated,
                a.rtol,
                a.runs
            );
            assert!(a.check_rtol < a.rtol, "the check is the tighter run");
        }
    }
}

/// A tolerance no run can reach stops with what was estimated, and writes no row.
#[test]
fn an_unreachable_tolerance_writes_nothing() {
    let s = three_panel("position_tolerance = 1e-14\n").unwrap();
    let mut rows = 0;
    let mut sink = |_: &Observation| -> Result<(), String> {
        rows += 1;
        Ok(())
    };
    let e = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_err().to_string();
    assert!(e.contains("run.position_tolerance = 1e-14 m not reached") && e.contains("tightest"), "{e}");
    assert_eq!(rows, 0);
}

/// What is refused, with the key named.
#[test]
fn refuses_what_does_not_fit() {
    for (run, says) in [
        (
            "integrator = \"dop853\"\nposition_tolerance = 1e-3\nrtol = 1e-6\n",
            "'run.rtol' and 'run.position_tolerance' both given",
        ),
        ("position_tolerance = 1e-3\natol = 1e-6\n", "'run.atol' and 'run.position_tolerance' both given"),
        (
            "integrator = \"rk4\"\nstep = 1e-3\nposition_tolerance = 1e-3\n",
            "'run.position_tolerance' needs an adaptive integrator",
        ),
        (
            "integrator = \"generalized-alpha\"\nstep = 1e-3\nrtol = 1e-8\natol = 1e-8\nposition_tolerance = 1e-3\n",
            "needs an adaptive integrator",
        ),
        ("position_tolerance = -1e-3\n", "'run.position_tolerance' must be a finite number > 0 m"),
        ("position_tolerance = 0.0\n", "'run.position_tolerance' must be a finite number > 0 m"),
    ] {
        let e = three_panel(run).map(|_| ()).unwrap_err();
        assert!(e.contains(says) && e.contains("ptol.toml"), "{run}: {e}");
    }
    // A stepped run cannot be made again tighter.
    let s = three_panel("position_tolerance = 1e-3\n").unwrap();
    let e = foldsim::simulate::Stepper::start(&s.model, &s.initial, &s.settings).err().expect("refused").to_string();
    assert!(e.contains("run.position_tolerance") && e.contains("run.rtol"), "{e}");
}

/// A run that fails inside the position tolerance's search is a refusal, said first, with the
/// failed run's tolerance and the runs made; nothing is written. The contact panel-hub
/// example asked 1e-9 m (of its size 1 m) with DOP853 and a step budget (`run.max_steps =
/// 20000`) its tightest candidates cannot finish in: the run at rtol = atol = 4e-12 fails for
/// its budget. (Until 2026-12-01 the example's impact at 0.85 s could not be followed below
/// rtol ~1e-11 whatever the budget: the hub's edge points inside the panel near its edge
/// turned their normal from the face's to the side's at once. With the thin plate's rim
/// rounded (docs/contact.md §1) DOP853 follows it, and the example reaches 3e-10 m.)
#[test]
fn a_run_that_fails_is_a_refusal() {
    let text = std::fs::read_to_string(common::repo("examples/contact-panel-hub.toml")).unwrap();
    let run = "rtol = 1e-9\natol = 1e-11\n";
    assert!(text.contains(run), "the example's [run] table changed: update this test");
    let asked = "1e-9";
    let limited = format!("position_tolerance = {asked}\nmax_steps = 20000\n");
    let s = Scenario::from_toml(&text.replace(run, &limited), "cph.toml").unwrap();
    let mut rows = 0;
    let mut sink = |_: &Observation| -> Result<(), String> {
        rows += 1;
        Ok(())
    };
    let e = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).expect_err("refused").to_string();
    let refusal = format!("run.position_tolerance = {asked} m not reached: ");
    let which = e.strip_prefix(&refusal).unwrap_or_else(|| panic!("said first: {e}"));
    assert!(
        ["the run at rtol = atol = ", "the check of the run at rtol = atol = "].iter().any(|w| which.starts_with(w)),
        "which run failed: {e}"
    );
    assert!(e.contains("failed (integration failed at t = ") && e.contains("run.max_steps"), "the budget: {e}");
    assert!(e.contains("runs at rtol = atol"), "{e}");
    assert_eq!(rows, 0);
}

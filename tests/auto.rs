//! `integrator = "auto"` (the default) and the implicit path's displacement norm: the switch
//! to adaptive generalized-α where DOP853 is held by stability, the same answer as DOP853 to the
//! tolerance, DOP853's run unchanged where it never switches, and a run that cannot finish
//! stopped early with its projection.

mod common;
use common::*;
use foldsim::generate::{Params, grid, zfold};
use foldsim::scenario::Scenario;

/// A stiff loop-heavy grid (1e7 N/m off-axis), 10 s at 1e-6, left without an integrator:
/// auto starts with DOP853, finds it held by stability and finishes with generalized-α in
/// far fewer steps than DOP853 alone (873 against 26,550); every body follows DOP853's run
/// to 1e-4 m (the grid's panels move ~1 m; both runs at rtol 1e-6, so their difference is
/// their errors': measured 3.6e-5 m); the momenta are held to round-off (1e-12 of their
/// scales), and E + D to 3e-4 of the energy: ρ∞ = 0.9 damps the stiff vibrations the steps
/// go over, which the default norm allows (measured 7.2e-5; SDIRK4 with its default
/// error_norm = "state" keeps 1e-5, tests/generated.rs, in 35× the steps).
#[test]
fn auto_switches_to_the_implicit_method_on_a_stiff_grid() {
    let p = Params { duration: 10.0, tolerance: 1e-6, k_translation: 1e7, k_bending: 1e4, ..Params::default() };
    let text = grid(3, 3, &p);
    let explicit = Scenario::from_toml(&text, "explicit").unwrap();
    let auto = Scenario::from_toml(&text.replace("integrator = \"dop853\"\n", ""), "auto").unwrap();
    assert!(matches!(auto.settings.integrator, foldsim::simulate::Integrator::Auto { .. }));
    let (_, obs_e, re) = run(&explicit);
    let (_, obs_a, ra) = run(&auto);
    eprintln!(
        "3x3 grid 1e7 N/m, 10 s: dop853 {} steps, auto {} steps; methods {:?}",
        re.steps_accepted,
        ra.steps_accepted,
        ra.methods.iter().map(|m| (m.method, m.from)).collect::<Vec<_>>()
    );
    assert_eq!(ra.methods[0].method, "dop853");
    assert!(ra.methods.iter().any(|m| m.method == "generalized-alpha"), "auto never switched");
    assert!(ra.steps_accepted * 10 < re.steps_accepted, "auto {} vs dop853 {}", ra.steps_accepted, re.steps_accepted);
    let distance = largest_distance(&obs_e, &obs_a);
    eprintln!("largest position difference to DOP853: {distance:.3e} m");
    assert!(distance < 1e-4, "{distance:e} m");
    let d = &ra.drift;
    assert!(d.momentum <= 1e-12 * d.momentum_scale.max(1.0));
    assert!(d.angular_momentum <= 1e-12 * d.angular_momentum_scale, "ΔH {:e}", d.angular_momentum);
    eprintln!("E + D balance {:.3e} of E0", d.energy / obs_a[0].energy());
    assert!(d.energy <= 3e-4 * obs_a[0].energy());
}

/// Where DOP853 is never held by stability (the paper's three-panel case at 1e-12), auto is
/// DOP853 bit for bit: every accuracy check of the reference cases holds under auto as it
/// does under DOP853.
#[test]
fn auto_is_dop853_where_nothing_is_stiff() {
    let text = std::fs::read_to_string(repo("examples/paper-3panel.toml")).unwrap();
    let dir = repo("examples");
    let explicit = Scenario::from_toml_in(&text, "paper-3panel", &dir).unwrap();
    let auto = Scenario::from_toml_in(&text.replace("integrator = \"dop853\"", "integrator = \"auto\""), "auto", &dir)
        .unwrap();
    let (te, _, re) = run(&explicit);
    let (ta, _, ra) = run(&auto);
    assert_eq!(ra.methods.len(), 1, "no switch: {:?}", ra.methods);
    assert_eq!(ra.steps_accepted, re.steps_accepted);
    assert_eq!(te.rows, ta.rows, "bit for bit");
}

/// A body whose inertia is 1e-12 kg·m² on a 1e6 N/m hinge at rtol 1e-12 (the fuzz suite's
/// extreme, here on the hub): the motion needs ~3e9 steps, beyond the budget of 1e9, so the
/// run stops after its first 10,000 steps with the projection and what holds it back,
/// instead of crawling for hours.
#[test]
fn a_run_that_cannot_finish_stops_early_and_says_why() {
    let p = Params { duration: 1.0, tolerance: 1e-12, ..Params::default() };
    let text = zfold(3, &p)
        .replace("mass = 500.0\ninertia = [400.0, 400.0, 400.0]", "mass = 500.0\ninertia = [1e-12, 1e-12, 1e-12]")
        .replace("integrator = \"dop853\"\n", "");
    assert!(text.contains("inertia = [1e-12"), "the hub's inertia replaced");
    let s = Scenario::from_toml(&text, "hub-inertia").unwrap();
    let start = std::time::Instant::now();
    let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> { Ok(()) };
    let e = foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_err().to_string();
    eprintln!("{e}\n(after {:.2} s)", start.elapsed().as_secs_f64());
    assert!(e.contains("stopped early") && e.contains("wall time") && e.contains("body 'hub'"), "{e}");
}

/// The keys: no integrator means auto; error_norm takes two words and only where implicit
/// steps are taken.
#[test]
fn integrator_and_error_norm_keys() {
    let base = zfold(2, &Params { duration: 0.1, ..Params::default() });
    let auto = Scenario::from_toml(&base.replace("integrator = \"dop853\"\n", ""), "auto").unwrap();
    assert_eq!(auto.settings.integrator.name(), "auto");
    assert_eq!(auto.settings.error_norm, foldsim::integrate::ErrorNorm::Displacement);
    let sdirk4 = base.replace("integrator = \"dop853\"", "integrator = \"sdirk4\"");
    assert_eq!(Scenario::from_toml(&sdirk4, "s").unwrap().settings.error_norm, foldsim::integrate::ErrorNorm::State);
    let displacement =
        sdirk4.replace("integrator = \"sdirk4\"", "integrator = \"sdirk4\"\nerror_norm = \"displacement\"");
    assert_eq!(
        Scenario::from_toml(&displacement, "d").unwrap().settings.error_norm,
        foldsim::integrate::ErrorNorm::Displacement
    );
    let bad = base.replace("integrator = \"dop853\"", "integrator = \"sdirk4\"\nerror_norm = \"velocity\"");
    let e = Scenario::from_toml(&bad, "bad").unwrap_err().to_string();
    assert!(e.contains("error_norm") && e.contains("\"displacement\"") && e.contains("bad:"), "{e}");
    let misplaced = base.replace("integrator = \"dop853\"", "integrator = \"dop853\"\nerror_norm = \"state\"");
    let e = Scenario::from_toml(&misplaced, "m").unwrap_err().to_string();
    assert!(e.contains("applies to the implicit steps"), "{e}");
    let unknown = base.replace("integrator = \"dop853\"", "integrator = \"radau\"");
    let e = Scenario::from_toml(&unknown, "u").unwrap_err().to_string();
    assert!(e.contains("\"auto\" (the default)"), "{e}");
}

//! The flasher generator (docs/flasher.md): its geometry checked against properties the
//! construction does not impose directly, and its deployments against conservation laws.

mod common;
use common::*;
use foldsim::generate::RunText;
use foldsim::generate::flasher::{FlasherLaws, FlasherShape, PanelModel, flasher, flasher_scenario};
use foldsim::generate::sheet::SheetParams;
use foldsim::math::Vec3;
use foldsim::scenario::Scenario;
use std::f64::consts::PI;

fn shape(gores: usize, rings: usize, model: PanelModel) -> FlasherShape {
    FlasherShape { gores, rings, hub_radius: 1.0, model }
}

fn params(run: RunText) -> SheetParams {
    SheetParams {
        title: "flasher test".into(),
        areal_density: 1.0,
        thickness: 0.0,
        hinge_axes: foldsim::generate::sheet::HingeAxes::Shifted,
        hub_mass: 100.0,
        hub_inertia: [25.0, 25.0, 50.0],
        spin_rpm: 0.0,
        run,
    }
}

/// The stored-energy laws of examples/flasher-small.toml, with damping `c` on every direction
/// (scaled per direction as in the example).
fn laws(c: f64) -> FlasherLaws {
    FlasherLaws {
        k_fold: 1.0,
        c_fold: Some(0.05 * c),
        k_bending: 0.1,
        c_bending: 0.05 * c,
        k_translation: 1e6,
        c_translation: 10.0 * c,
        k_rotation: 1e3,
        c_rotation: 0.1 * c,
        k_stop: 1e4,
        ..FlasherLaws::default()
    }
}

/// The corner angle of triangle (a, b, c) at a, rad.
fn corner(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (u, v) = (b - a, c - a);
    u.cross(&v).norm().atan2(u.dot(&v))
}

/// Geometry, for a range of sizes and every panel model: the unfolded disc is flat, N-fold
/// symmetric, closes on itself and tiles without overlap, the stowed nodes lie on the prism,
/// and every triangle keeps its edge lengths (FLASHER.md's checks; bounds 1e-9 relative, the
/// issue's, and 1e-12 where the quantity is exact by construction). Independently of the
/// unfolding, the sector angles round every interior node of the stowed sheet sum to 2π: the
/// stowed state is developable, which is what fixes the heights of the mountain nodes.
#[test]
fn flasher_geometry_is_flat_symmetric_and_developable() {
    for (gores, rings) in [(3, 1), (4, 2), (6, 3), (8, 5), (12, 5), (16, 12), (40, 4)] {
        for model in [PanelModel::Triangles, PanelModel::Quads, PanelModel::RingQuads] {
            let f = flasher(&shape(gores, rings, model)).unwrap();
            let g = &f.geometry;
            let d = g.deployed_diameter;
            let what = format!("{gores} gores, {rings} rings, {model:?}: {g:?}");
            assert!(g.edge_mismatch < 1e-9, "{what}");
            assert!(g.closure < 1e-9 * d && g.symmetry < 1e-9 * d, "{what}");
            assert!(g.flatness < 1e-12 * d && g.off_prism < 1e-12 * d, "{what}");
            assert!(g.overlap.abs() < 1e-9, "{what}");
            assert!(d > 2.0 && g.stowed_diameter == 2.0, "{what}");
            let panels = f.sheet.panels.len() - 1;
            let expected = match model {
                PanelModel::Triangles => gores * (4 * (rings + 1) - 5),
                PanelModel::Quads => gores * (2 * (rings + 1) - 1),
                PanelModel::RingQuads => gores * (2 * (rings + 1) - 2),
            };
            assert_eq!(panels, expected, "{what}");
        }
        // Developable: the triangles' corner angles in the stowed state (the hub's own corner
        // included) sum to 2π round every node that is not on the rim.
        let f = flasher(&shape(gores, rings, PanelModel::Triangles)).unwrap();
        let s = &f.sheet;
        let mut sum = vec![0.0; s.stowed.len()];
        let mut edges = std::collections::BTreeMap::<(usize, usize), usize>::new();
        for p in &s.panels {
            let m = p.len();
            for i in 0..m {
                let (prev, here, next) = (p[(i + m - 1) % m], p[i], p[(i + 1) % m]);
                sum[here] += corner(s.stowed[here], s.stowed[prev], s.stowed[next]);
                *edges.entry((here.min(next), here.max(next))).or_default() += 1;
            }
        }
        let on_rim: std::collections::BTreeSet<usize> =
            edges.iter().filter(|(_, c)| **c == 1).flat_map(|((a, b), _)| [*a, *b]).collect();
        let interior: Vec<usize> = (0..sum.len()).filter(|n| !on_rim.contains(n)).collect();
        assert_eq!(interior.len(), gores * (1 + 2 * (rings - 1)), "hub corners and inner nodes");
        for n in interior {
            assert!((sum[n] - 2.0 * PI).abs() < 1e-12, "{gores}×{rings}: node {n} has {} rad round it", sum[n]);
        }
    }
}

/// Stowed strain: none for the two models whose panels are rigid in both states; the
/// ring-quads model's panels span two walls of the prism when stowed, and the report says
/// by how much its hinges are forced off their fold axes and what that stores.
#[test]
fn ring_quads_report_their_stowed_strain() {
    let run = RunText { duration: 1.0, output_step: 0.1, tolerance: 1e-8, ..Default::default() };
    for model in [PanelModel::Triangles, PanelModel::Quads, PanelModel::RingQuads] {
        let (_, r) = flasher_scenario(&shape(6, 3, model), &laws(0.0), &params(run.clone())).unwrap();
        let off = r.sheet.strains.iter().map(|s| s.off_axis()).fold(0.0, f64::max);
        if model == PanelModel::RingQuads {
            assert!(off > 0.1 && r.strain_energy > 1e3 && r.sheet.panel_strain > 0.1, "{off} {}", r.strain_energy);
            assert!(r.text(false).contains("largest hinge deflection off its fold axis"));
        } else {
            assert!(off < 1e-12 && r.sheet.panel_strain < 1e-12 && r.strain_energy < 1e-15, "{model:?}: {off}");
            assert!(r.text(false).contains("stowed strain: none"));
        }
        // Loops: hinges − panels + 1 (the hub counted), as the report says.
        assert_eq!(r.sheet.loops, r.sheet.hinges + 1 - r.sheet.panels);
    }
}

/// Law 2 without damping conserves E (docs/model.md §5): over the stored-energy deployment of
/// the small flasher (to ~94 % of its radius in 1.5 s) E stays within 1e-9 of its 201 J at
/// rtol = atol = 1e-10 (measured 7e-11), P and H within 1e-10 of their scales. The flasher
/// really opens: the deployed fraction passes 0.9.
#[test]
fn undamped_flasher_deployment_conserves_energy() {
    let run = RunText { duration: 1.5, output_step: 0.01, tolerance: 1e-10, ..Default::default() };
    let (text, _) = flasher_scenario(&shape(6, 3, PanelModel::Triangles), &laws(0.0), &params(run)).unwrap();
    let s = Scenario::from_toml(&text, "flasher").unwrap();
    let (_, obs, report) = common::run(&s);
    let d = &report.drift;
    assert!(report.energy_conserving);
    assert!(d.energy <= 1e-9 * d.energy_initial, "ΔE = {:e} of {} J", d.energy, d.energy_initial);
    assert!(d.momentum <= 1e-10 * d.momentum_scale && d.angular_momentum <= 1e-10 * d.angular_momentum_scale);
    let opened = obs.iter().map(|o| o.deployed_fraction).fold(0.0, f64::max);
    assert!(obs[0].deployed_fraction < 0.3 && opened > 0.9, "deployed fraction reaches {opened}");
    assert!(report.deployed_90.is_some());
}

/// With damping in every direction, E + D is conserved (D the energy the hinges dissipate):
/// to 1e-9 of E(0) (measured 6e-13 at 1e-10), while E itself falls by percents.
#[test]
fn damped_flasher_deployment_balances_energy() {
    let run = RunText { duration: 1.5, output_step: 0.01, tolerance: 1e-10, ..Default::default() };
    let (text, _) = flasher_scenario(&shape(6, 3, PanelModel::Triangles), &laws(1.0), &params(run)).unwrap();
    let s = Scenario::from_toml(&text, "flasher").unwrap();
    let (_, _, report) = common::run(&s);
    let d = &report.drift;
    assert!(!report.energy_conserving);
    assert!(d.dissipated > 1e-2 * d.energy_initial, "damping dissipates: {} J", d.dissipated);
    assert!(
        d.energy_balance <= 1e-9 * d.energy_initial,
        "|Δ(E + D)| = {:e} J of {} J",
        d.energy_balance,
        d.energy_initial
    );
}

/// The spin-deployed example (examples/flasher-spin.toml): held stowed spinning at 20 rpm
/// until 0.5 s, released, it opens under the spin (and light fold springs) and damping settles
/// it. The hub's final spin equals ω0 · I0 / I_final with I_final the final configuration's
/// inertia about the spin axis, to 1e-6 (measured 1.5e-7 at 30 s; the slowest residual
/// oscillation is at that level there), and H holds to 1e-10 of |H|. Independently of the
/// bodies' inertias, I_final is the deployed design's polar moment, summed over the sheet's
/// triangles (J = ρ ∫ r² dA, closed form per triangle) plus the hub's, to 1e-5: the spin
/// stretches the hinges by ~1e-6 of the radius (the deployed fraction ends at 1.0000015).
#[test]
fn spin_deployment_settles_at_the_inertia_ratio() {
    let s = scenario("examples/flasher-spin.toml");
    let (_, obs, report) = common::run(&s);
    let (first, last) = (&obs[0], obs.last().unwrap());
    let expected = first.spin_rate * first.inertia_about_spin_axis / last.inertia_about_spin_axis;
    let off = (last.spin_rate / expected - 1.0).abs();
    assert!(off <= 1e-6, "final spin {} rad/s against ω0 I0 / I_final = {expected} ({off:e})", last.spin_rate);
    let h0 = first.angular_momentum_in_n.norm();
    assert!(report.drift.angular_momentum <= 1e-10 * h0, "|ΔH| = {:e} of {h0}", report.drift.angular_momentum);
    assert!(report.released_at == Some(0.5) && report.deployed_90.is_some_and(|t| t > 0.5 && t < 10.0));
    // The design's polar moment from the triangles (areal density 1 kg/m²): for a triangle,
    // ∫ (x² + y²) dA = A/6 Σ over x and y of (a² + b² + c² + ab + bc + ca).
    let f = flasher(&shape(6, 3, PanelModel::Triangles)).unwrap();
    let mut polar = 50.0; // the hub's I_z, kg·m²
    for p in &f.sheet.panels[1..] {
        let [a, b, c] = [p[0], p[1], p[2]].map(|i| f.sheet.deployed[i]);
        let area = 0.5 * (b - a).cross(&(c - a)).norm();
        let q = |u: f64, v: f64, w: f64| u * u + v * v + w * w + u * v + v * w + w * u;
        polar += area / 6.0 * (q(a.x, b.x, c.x) + q(a.y, b.y, c.y));
    }
    let rel = (last.inertia_about_spin_axis / polar - 1.0).abs();
    assert!(rel < 1e-5, "I_final {} against the design's {polar} ({rel:e})", last.inertia_about_spin_axis);
}

/// The command line: the report's facts, and bad parameters named.
#[test]
fn generate_flasher_reports_and_refuses_nonsense() {
    let out = foldsim()
        .args(["generate", "flasher", "--gores", "6", "--rings", "3", "-o"])
        .arg(tmp("flasher", "cli").join("f.toml"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    for fact in [
        "deployed diameter 7.211103 m",
        "stowed diameter 2.000000 m, height 1.732051 m",
        "panels 67",
        "independent loops 30",
        "stowed fold angles",
    ] {
        assert!(text.contains(fact), "{fact} missing from:\n{text}");
    }
    for (args, says) in [
        (vec!["--gores", "2", "--rings", "3"], "--gores must be 3 to 1000"),
        (vec!["--gores", "6", "--rings", "0"], "--rings must be at least 1"),
        (vec!["--gores", "6", "--rings", "3", "--hub-radius", "-1"], "--hub-radius"),
        (vec!["--gores", "6", "--rings", "3", "--areal-density", "0"], "--areal-density"),
        (vec!["--gores", "6", "--rings", "3", "--c-fold", "-1"], "--c-fold"),
        (vec!["--gores", "6", "--rings", "3", "--panel-mass", "2"], "do not apply to a flasher"),
        (vec!["--gores", "6", "--rings", "3", "--hub-inertia", "1,2"], "hub-inertia"),
    ] {
        let out = foldsim().args(["generate", "flasher"]).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(says), "{args:?}: {err}");
    }
}

/// The implicit integrator under the launch restraint: every tree hinge locked in all six
/// directions, the loops free. The Newton matrix's elimination once took a locked hinge
/// after one of its bodies that another fully locked hinge had already used up, met an
/// exactly zero pivot and failed at the first fresh Jacobian (dynamics/newton/order.rs). Now SDIRK4 runs it and agrees with DOP853:
/// the restraint holds the stowed shape until release (hinge angles unchanged to 1e-6 rad,
/// the locks' drift bound), and the spin rate at the end agrees to 1e-5 of its value (both
/// at rtol 1e-9; measured 1.3e-8; the spin falls from 2.09 to 0.33 rad/s as the flasher
/// opens, so this compares the deployment, not the initial state).
#[test]
fn sdirk4_runs_the_release_restraint_and_agrees_with_dop853() {
    use foldsim::generate::options::FlasherOptions;
    let run = |integrator: &str| {
        let options = FlasherOptions {
            gores: 4,
            rings: 2,
            spin_rpm: 20.0,
            release_at: Some(0.2),
            duration: 3.0,
            output_step: Some(0.01),
            tolerance: Some(1e-9),
            integrator: Some(integrator.into()),
            laws: FlasherLaws {
                k_fold: 0.05,
                c_fold: Some(0.5),
                k_bending: 0.05,
                c_bending: 0.5,
                ..FlasherOptions::default().laws
            },
            ..FlasherOptions::default()
        };
        let (text, _) = options.scenario(&|k: &str| k.to_string()).unwrap();
        let s = Scenario::from_toml(&text, integrator).unwrap();
        common::run(&s)
    };
    let (explicit, _, _) = run("dop853");
    let (implicit, _, report) = run("sdirk4");
    assert_eq!(report.released_at, Some(0.2));
    let yaw = implicit.col("h0_hub_p4_yaw");
    let t = implicit.col("t");
    let (first, before) = (implicit.rows[0][yaw], implicit.rows.iter().find(|r| r[t] >= 0.19).unwrap()[yaw]);
    assert!((first - before).abs() < 1e-6, "held: {first} → {before}");
    let spin = implicit.col("spin_rate");
    let (a, b) = (explicit.rows.last().unwrap()[spin], implicit.rows.last().unwrap()[spin]);
    let start = implicit.rows[0][spin];
    assert!((a - b).abs() < 1e-5 * a.abs(), "spin at the end: dop853 {a}, sdirk4 {b}");
    assert!((start - b).abs() > 0.1 * start, "the structure opened: spin {start} → {b}");
}

/// SDIRK4 at the thick flashers' rtol 1e-4 follows a tight DOP853 run of a thin flasher: the
/// 4 × 2 flasher with the generator's defaults (stiff off-axis hinges, no contact), every
/// body's position at every output row of its first 3 s against DOP853 at rtol 1e-10.
/// Measured 2026-12-01: at most 2.1e-5 m with SDIRK4's stage derivatives evaluated afresh,
/// 1.3e-3 m with them implied by the stage equations (docs/architecture.md, *Implicit
/// integration*: Newton's residual carried into the later stages). The first 3 s only: after
/// 3.5 s the motion turns sensitive, both builds' differences growing tenfold every 0.5 s
/// (fresh 2.5e-2 m at 5 s, implied 0.47 m). The bound, 1e-4 m, leaves five times the measured
/// error for rounding on other machines and stays thirteen times below the implied ones'.
#[test]
fn sdirk4_at_rtol_1e_4_follows_dop853_on_a_thin_flasher() {
    use foldsim::generate::options::FlasherOptions;
    let run = |integrator: &str, tolerance: f64| {
        let options = FlasherOptions {
            gores: 4,
            rings: 2,
            duration: 3.0,
            tolerance: Some(tolerance),
            integrator: Some(integrator.into()),
            ..FlasherOptions::default()
        };
        let (text, _) = options.scenario(&|k: &str| k.to_string()).unwrap();
        let s = Scenario::from_toml(&text, integrator).unwrap();
        common::run(&s).1
    };
    let reference = run("dop853", 1e-10);
    let implicit = run("sdirk4", 1e-4);
    assert_eq!(reference.len(), implicit.len());
    assert!(reference[0].body_r_in_n.len() > 20, "{} bodies", reference[0].body_r_in_n.len());
    let mut worst = (0.0_f64, 0.0, 0);
    for (a, b) in reference.iter().zip(&implicit) {
        for (body, (ra, rb)) in a.body_r_in_n.iter().zip(&b.body_r_in_n).enumerate() {
            let d = (ra - rb).norm();
            if d > worst.0 {
                worst = (d, a.t, body);
            }
        }
    }
    eprintln!("sdirk4 at rtol 1e-4 against dop853 at 1e-10: {:.3e} m (body {} at t = {})", worst.0, worst.2, worst.1);
    assert!(worst.0 < 1e-4, "{:.3e} m off (body {} at t = {})", worst.0, worst.2, worst.1);
}

/// Membrane hinges make a thick flasher a mechanism again (docs/flasher.md, *Membrane hinges*):
/// a 4 × 2 flasher with the starshade's hinges (1e7 N/m, 1e4 N·m/rad off the fold, 0.2 N·m/rad
/// folds) and 1-cm panels, left 3 s from its wrap, opens as its thin twin does with the
/// default membranes, and far less on pins at the same shifted axes. Measured: the thin twin
/// gains 15.8 points of its radius in the 3 s, the membranes 15.6, the pins 5.7 (2.0 before
/// the thin plates' rims were rounded, 2026-12-01: their sharp edges caught each other in
/// the wrap). The bounds: within 15 % of the thin twin's gain (the thick panels' cut-out
/// corners and their contact and friction in the wrap make the two not the same motion),
/// and below half of it on pins.
#[test]
fn membrane_hinges_let_a_stiff_thick_flasher_open_as_its_thin_twin() {
    use foldsim::generate::options::FlasherOptions;
    let laws = starshade_laws();
    let base = FlasherOptions {
        gores: 4,
        rings: 2,
        laws,
        duration: 3.0,
        output_step: Some(0.1),
        integrator: Some("sdirk4".into()),
        tolerance: Some(1e-4),
        ..FlasherOptions::default()
    };
    let gain = |o: FlasherOptions| {
        let (text, _) = o.scenario(&|k: &str| k.to_string()).unwrap();
        let s = Scenario::from_toml(&text, "4x2").unwrap();
        let (_, rows, _) = run(&s);
        rows.last().unwrap().deployed_fraction - rows[0].deployed_fraction
    };
    let thin = gain(base.clone());
    let membranes = gain(FlasherOptions { thickness: 0.01, ..base.clone() });
    let pins = gain(FlasherOptions { thickness: 0.01, laws: FlasherLaws { membrane_bending: 0.0, ..laws }, ..base });
    println!(
        "4 x 2, starshade hinges, 3 s: deployed fraction gained: thin {thin:.4}, membranes {membranes:.4}, pins {pins:.4}"
    );
    assert!(thin > 0.1, "the thin twin opens: {thin}");
    assert!((membranes - thin).abs() < 0.15 * thin, "membranes {membranes} against thin {thin}");
    assert!(pins < 0.5 * thin, "pins {pins} against thin {thin}");
}

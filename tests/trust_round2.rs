//! Trust, round two (issue 33): each defect a fuzzer or a new user met, with the input that
//! showed it. Every test here failed before its fix.

mod common;

use common::{foldsim, repo};
use foldsim::scenario::Scenario;
use std::process::Output;

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// The example `file` with each `(from, to)` replaced once (`from` must be there), loaded from
/// the examples' directory.
fn edited(file: &str, edits: &[(&str, &str)]) -> Result<Scenario, String> {
    let mut t = std::fs::read_to_string(repo(&format!("examples/{file}"))).unwrap();
    for (from, to) in edits {
        assert!(t.contains(from), "{file} lacks '{from}'");
        t = t.replacen(from, to, 1);
    }
    Scenario::from_toml_in(&t, file, &repo("examples")).map_err(|e| e.to_string())
}

/// `s` refused with every word of `words` in the message (and no panic).
fn refused(s: Result<Scenario, String>, words: &[&str]) {
    let e = match s {
        Ok(_) => panic!("accepted; expected a refusal with {words:?}"),
        Err(e) => e,
    };
    for w in words {
        assert!(e.contains(w), "lacks '{w}': {e}");
    }
}

/// Item 1: the flashers' states hold more than the bodies' numbers (hinge memories, the
/// work), and `equilibrium` took the body count from the state's length: a panic. Now it
/// ends in a result or a reason.
#[test]
fn equilibrium_on_a_flasher_does_not_panic() {
    let o = foldsim()
        .args(["equilibrium"])
        .arg(repo("examples/flasher-small.toml"))
        .args(["-o", "/dev/null"])
        .output()
        .unwrap();
    let t = text(&o);
    assert!(!t.contains("panicked"), "{t}");
}

/// Item 2: a control period of 1e-9 s over 0.5 s is 5e8 samples: refused by the bound that
/// holds run.step (at most 1e9 steps), and a period inside the bound no longer makes a list
/// of every sample (the breaks are generated as the run reaches them; `loads::breaks`'s unit
/// tests), so memory stays small and the run stops early by its pace, naming the period.
#[test]
fn a_tiny_control_period_is_bounded() {
    refused(
        edited("zfold-attitude-hold.toml", &[("period = 0.1 ", "period = 1e-15 ")]),
        &["control.period", "samples", "at least"],
    );
    let s = edited(
        "zfold-attitude-hold.toml",
        &[("period = 0.1 ", "period = 1e-9 "), ("duration = 30.0", "duration = 0.5")],
    )
    .unwrap();
    let mut sink = |_: &foldsim::observe::Observation| Ok(());
    let e = foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_err().to_string();
    assert!(e.contains("control.period"), "{e}");
}

/// Item 5: every array of fixed size refuses extra (and missing) elements, located.
#[test]
fn fixed_size_arrays_refuse_other_lengths() {
    for (file, from, to) in [
        ("paper-1panel.toml", "child_com = [1.0, 1.0, 0.0]", "child_com = [1.0, 1.0, 0.0, 2.0]"),
        ("paper-1panel.toml", "delta = [0.01, 0.01, 0.01]", "delta = [0.01, 0.01, 0.01, 0.0]"),
        ("paper-1panel.toml", "omega = [0.0, 0.0, 0.0]", "omega = [0.0, 0.0, 0.0, 1.0]"),
        ("paper-1panel.toml", "velocity = [0.0, 0.0, 0.0]", "velocity = [0.0, 0.0]"),
        ("paper-1panel.toml", "position = [0.0, 0.0, 0.0]", "position = [0.0, 0.0, 0.0, 0.0]"),
        ("paper-1panel.toml", "position = [0.75, 0.433, 0.0]", "position = [0.75, 0.433, 0.0, 1.0]"),
        ("contact-panel-hub.toml", "box = [1.0, 1.0, 0.3]", "box = [1.0, 1.0, 0.3, 9.0]"),
        ("contact-panel-hub.toml", "[-0.5, -0.3, 0.0], [0.5, -0.3, 0.0]", "[-0.5, -0.3, 0.0, 7.0], [0.5, -0.3, 0.0]"),
        ("zfold-attitude-hold.toml", "axis = [1.0, 0.0, 0.0]", "axis = [1.0, 0.0, 0.0, 0.0]"),
    ] {
        let e = edited(file, &[(from, to)]).err().unwrap_or_else(|| panic!("{to} accepted"));
        assert!(
            e.contains("expected a list of 3 numbers [x, y, z], no more") && e.contains(&format!("{file}:")),
            "{to}: {e}"
        );
    }
    let with = |extra: &str| edited("paper-1panel.toml", &[("[initial.hub]", &format!("{extra}\n[initial.hub]"))]);
    for extra in [
        "[[load]]\nname = \"l\"\nbody = \"panel\"\npoint = [0.0, 0.0, 0.0, 1.0]\nforce = [1.0, 0.0, 0.0]\nforce_frame = \"body\"\n",
        "[[load]]\nname = \"l\"\nbody = \"panel\"\nforce = [1.0, 0.0, 0.0]\nforce_frame = \"body\"\non = [[0.1, 0.2, 0.3]]\n",
        "[control]\nlaw = \"spin_hold\"\np = 1.0\nspin_rate = 0.1\nspin_axis = [0.0, 0.0, 1.0, 0.0]\n",
    ] {
        let e = with(extra).err().unwrap_or_else(|| panic!("accepted:\n{extra}"));
        assert!(e.contains("no more, no fewer"), "{extra}: {e}");
    }
    let e = edited("contact-panel-hub.toml", &[("[contact]", "[contact]\nexclude = [[\"hub\", \"panel\", \"hub\"]]")])
        .unwrap_err();
    assert!(e.contains("a list of 2 items, no more"), "{e}");
}

/// Item 6: `on = []` acted for the whole run; now refused. A window wholly outside the run
/// is accepted with a warning (it never acts).
#[test]
fn load_windows_that_never_act() {
    let load = |on: &str| {
        edited(
            "paper-1panel.toml",
            &[(
                "[initial.hub]",
                &format!(
                    "[[load]]\nname = \"l\"\nbody = \"panel\"\nforce = [1.0, 0.0, 0.0]\nforce_frame = \"body\"\non = {on}\n\n[initial.hub]"
                ),
            )],
        )
    };
    refused(load("[]"), &["'on' = []", "leave 'on' out"]);
    let s = load("[[30.0, 40.0]]").unwrap();
    assert!(s.warnings.iter().any(|w| w.contains("outside the run") && w.contains("load 'l'")), "{:?}", s.warnings);
    assert!(load("[[1.0, 2.0]]").unwrap().warnings.is_empty());
}

/// Item 15: requests that cannot mean what they say are refused, located.
#[test]
fn meaningless_requests_are_refused() {
    refused(
        edited(
            "paper-1panel.toml",
            &[("[initial.hub]", "[contact]\nstiffness = 1e6\nrestitution = 0.5\n\n[initial.hub]")],
        ),
        &["[contact]", "no body has one"],
    );
    refused(
        edited("contact-panel-hub.toml", &[("[contact]", "[contact]\nexclude = [[\"hub\", \"hub\"]]")]),
        &["contact.exclude", "names one body twice"],
    );
    let control =
        |body: &str| edited("paper-1panel.toml", &[("[initial.hub]", &format!("[control]\n{body}\n\n[initial.hub]"))]);
    refused(
        control(
            "law = \"spin_hold\"\np = 1.0\nspin_rate = 0.1\nspin_axis = [0.0, 0.0, 1.0]\ntarget = [1.0, 0.0, 0.0, 0.0]",
        ),
        &["'target'", "mrp_pd"],
    );
    refused(control("law = \"rate_damping\"\np = 1.0\nspin_axis = [0.0, 0.0, 1.0]"), &["'spin_axis'", "spin_hold"]);
    for bad in ["\"\"", "\"a,b\"", "\"x y\""] {
        refused(
            control(&format!(
                "law = \"rate_damping\"\np = 1.0\n[[control.wheel]]\nname = {bad}\naxis = [1.0, 0.0, 0.0]\ninertia = 0.1"
            )),
            &["actuator name", "CSV columns"],
        );
    }
    refused(
        edited(
            "paper-1panel.toml",
            &[(
                "[initial.hub]",
                "[[motor]]\nname = \"m,1\"\nhinge = \"h1\"\ndirection = \"rz\"\neffort = 1.0\n\n[initial.hub]",
            )],
        ),
        &["motor name", "CSV columns"],
    );
    let run =
        |lines: &str| edited("paper-1panel.toml", &[("integrator = \"dop853\"\nrtol = 1e-12\natol = 1e-12", lines)]);
    refused(
        run("integrator = \"generalized-alpha\"\nstep = 0.01\nrtol = 2.0\natol = 1e-8"),
        &["run.rtol", "at most 1"],
    );
    refused(
        run("integrator = \"generalized-alpha\"\nstep = 0.01\nrtol = 1e-16\natol = 1e-8"),
        &["run.rtol", "beyond what f64"],
    );
    refused(run("integrator = \"dop853\"\nrtol = 5.0\natol = 1e-8"), &["run.rtol", "at most 1"]);
    refused(run("integrator = \"rk4\"\nstep = 30.0"), &["run.step", "longer than run.duration"]);
    refused(
        run("integrator = \"generalized-alpha\"\nstep = 25.0\nrtol = 1e-8\natol = 1e-8"),
        &["run.step", "longer than"],
    );
}

/// Item 7: a spin the structure's forces overflow at: an error from both commands, no table.
#[test]
fn non_finite_spins_are_errors() {
    let dir = common::tmp("trust2", "spin");
    for (cmd, ext) in [("equilibrium", "toml"), ("modes", "csv")] {
        let out = dir.join(format!("{cmd}.{ext}"));
        let o = foldsim()
            .arg(cmd)
            .arg(repo("examples/radial-spin.toml"))
            .args(["--spin-rate", "1e160", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let t = text(&o);
        assert!(!o.status.success() && t.contains("not finite") && !t.contains("NaN"), "{cmd}: {t}");
        assert!(!out.exists(), "{cmd} wrote {}", out.display());
    }
}

/// Item 12: folds soft against the other directions. Newton's step taken in the bodies' own
/// coordinates stretched the stiff directions by the curvature of each turn (½ |Δφ|² times
/// the arm, times 1e6 N/m) and the search halved it away (no equilibrium after 50
/// iterations). Taken in the tree hinges' coordinates, the generated z-folds from 1°, 10° and
/// 30° off (folds of 1 and 20 N·m/rad against 1e3 and 1e6) converge in a few iterations, to a
/// largest force or torque below 1e-9 (N, N·m): the round-off of 1e6 N/m times a metre is
/// 1e-10. The equilibrium is the deployed chain: every fold's yaw at zero to 1e-9 rad
/// (its rest angle; the other directions carry nothing at rest).
#[test]
fn equilibrium_converges_where_folds_are_soft() {
    let dir = common::tmp("trust2", "soft");
    for (panels, fold, k_fold) in [(3, "1", "1"), (2, "10", "20"), (3, "10", "20"), (8, "30", "1")] {
        let s = dir.join(format!("z{panels}-{fold}.toml"));
        let o = foldsim()
            .args(["generate", "zfold", "--panels", &panels.to_string(), "--fold-deg", fold, "--k-fold", k_fold, "-o"])
            .arg(&s)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o));
        let scenario = Scenario::from_file(&s).unwrap();
        let stepper =
            foldsim::simulate::Stepper::start(&scenario.model, &scenario.initial, &scenario.settings).unwrap();
        let found = foldsim::linear::equilibrium::Equilibrium::near(stepper.dynamics(), stepper.state(), 1e-9, 50)
            .unwrap_or_else(|e| panic!("{panels} panels {fold}°: {e}"));
        let worst_yaw = found.hinges.iter().map(|(_, t)| t.yaw.abs()).fold(0.0, f64::max);
        println!(
            "{panels} panels, {fold}° off, k_fold {k_fold}: {} iterations, residual {:.1e}, largest yaw {worst_yaw:.1e} rad",
            found.iterations, found.residual
        );
        assert!(found.iterations <= 12 && found.residual < 1e-9 && worst_yaw < 1e-9, "{found:?}");
    }
}

/// Item 10: a shape whose inertia overflows no longer passes the check against 'inertia'
/// (NaN compared false); a box of 1e150 m is refused, located.
#[test]
fn shapes_beyond_f64_are_refused() {
    for (from, to) in [
        ("box = [1.0, 1.0, 0.3]", "box = [1e150, 1.0, 0.3]"),
        ("box = [1.0, 1.0, 0.3]", "box = [1e-300, 1e-300, 1e-300]"),
    ] {
        let e = edited("contact-panel-hub.toml", &[(from, to)]).err().unwrap_or_else(|| panic!("{to} accepted"));
        assert!(e.contains("beyond what f64 holds") && e.contains("contact-panel-hub.toml:"), "{e}");
    }
}

/// Item 8: modes of a design state out of balance printed NaN frequencies. Now the
/// equilibrium nearest it is found and the report says so, or the command refuses, naming
/// `foldsim equilibrium`; no NaN is printed and no table is left by a refusal.
#[test]
fn modes_never_print_nan() {
    let dir = common::tmp("trust2", "nan");
    let out = dir.join("m.csv");
    let o = foldsim()
        .arg("modes")
        .arg(repo("examples/paper-3panel.toml"))
        .arg("--deployed")
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let t = text(&o);
    assert!(!t.contains("NaN"), "{t}");
    if o.status.success() {
        assert!(t.contains("static equilibrium nearest it"), "{t}");
        assert!(!std::fs::read_to_string(&out).unwrap().contains("NaN"));
    } else {
        assert!(t.contains("foldsim equilibrium") && !out.exists(), "{t}");
    }
    // A z-fold out of balance at rest (its folds 30° from their rest angle): the modes are
    // taken at the equilibrium, all finite.
    let s = dir.join("z.toml");
    assert!(foldsim().args(["generate", "zfold", "--panels", "3", "-o"]).arg(&s).output().unwrap().status.success());
    let o = foldsim().arg("modes").arg(&s).arg("-o").arg(&out).output().unwrap();
    let t = text(&o);
    assert!(o.status.success() && t.contains("static equilibrium nearest it") && !t.contains("NaN"), "{t}");
}

/// Item 14: every argument checked before the work, and outputs named as what they hold.
#[test]
fn arguments_are_checked_before_any_output() {
    let dir = common::tmp("trust2", "args");
    let out = dir.join("m.csv");
    let o = foldsim()
        .arg("modes")
        .arg(repo("examples/flasher-small.toml"))
        .args(["--deployed", "-q", "--mode", "hub_fixed:100000", "-o"])
        .arg(&out)
        .arg("--view")
        .arg(dir.join("m.html"))
        .output()
        .unwrap();
    assert!(!o.status.success() && text(&o).contains("nothing written") && !out.exists(), "{}", text(&o));
    let o = foldsim()
        .arg("linearize")
        .arg(repo("examples/paper-1panel.toml"))
        .arg("-o")
        .arg(dir.join("model.csv"))
        .output()
        .unwrap();
    assert!(!o.status.success() && text(&o).contains(".npz") && !dir.join("model.csv").exists(), "{}", text(&o));
    let o = foldsim()
        .arg("run")
        .arg(repo("examples/paper-1panel.toml"))
        .arg("--csv")
        .arg(dir.join("r.csv"))
        .arg("--animation")
        .arg(dir.join("a.gltf"))
        .output()
        .unwrap();
    assert!(!o.status.success() && text(&o).contains(".glb") && !dir.join("r.csv").exists(), "{}", text(&o));
}

/// Item 11: a GNC loop steps any scenario at any dt to its end. `advance(dt)` ends spans at
/// t + dt, which lands within round-off of the control samples (every 0.1 s) and the load
/// windows' edges; a span whose end fell a round-off past a break took a step of 1e-16 s
/// there and stopped ("step size fell to 2.2e-16 s" at t = 1.4). Each dt here is checked to
/// reach the end, at the scenario's own integrator.
#[test]
fn stepping_reaches_the_end_at_any_dt() {
    for (file, dts) in
        [("zfold-attitude-hold.toml", &[0.1, 0.05, 0.3, 0.01][..]), ("flasher-spin-hold.toml", &[0.1][..])]
    {
        for &dt in dts {
            let mut s = Scenario::from_file(&repo(&format!("examples/{file}"))).unwrap();
            s.settings.duration = s.settings.duration.min(3.0);
            s.model.commandable = true;
            let mut stepper = foldsim::simulate::Stepper::start(&s.model, &s.initial, &s.settings).unwrap();
            let steps = (s.settings.duration / dt).round() as usize;
            for k in 0..steps {
                stepper
                    .advance(dt)
                    .unwrap_or_else(|e| panic!("{file} dt {dt}: advance {k} from t = {}: {e}", stepper.time()));
            }
            assert!((stepper.time() - s.settings.duration).abs() < 1e-9, "{file} dt {dt}: t = {}", stepper.time());
        }
    }
}

/// Item 9: with a sampled law, the row at a sample instant showed the previous period's
/// torque while the dynamics already used the new one (0.69 N·m apart against Basilisk).
/// Now `L_req` at every sample row is the law of that row's own state, `−K σ − P ω`
/// (docs/gnc.md), to round-off (1e-12 N·m: the law's arithmetic on the row's values); rows
/// between samples hold the last sample's value.
#[test]
fn sampled_control_rows_show_the_torque_that_acts_from_them() {
    let s = edited("zfold-attitude-hold.toml", &[("duration = 30.0", "duration = 2.0")]).unwrap();
    let (table, _, _) = common::run(&s);
    let col = |n: &str| table.col(n);
    let (k, p) = (80.0, 150.0);
    let mut worst: f64 = 0.0;
    let mut samples = 0;
    for r in &table.rows {
        let t = r[col("t")];
        if (t / 0.1 - (t / 0.1).round()).abs() > 1e-6 {
            continue;
        }
        samples += 1;
        for a in ["x", "y", "z"] {
            let law = -(k * r[col(&format!("sigma_B_{a}"))] + p * r[col(&format!("w_B_{a}"))]);
            worst = worst.max((r[col(&format!("L_req_{a}"))] - law).abs());
        }
    }
    println!("{samples} sample rows: largest |L_req − law(row)| {worst:.2e} N·m");
    assert!(samples >= 20 && worst < 1e-12, "{worst:e} over {samples} rows");
}

/// Item 13: `modes --count N` on small structures (Lanczos's basis of 18 vectors failed to
/// converge on 12 coordinates: now every mode densely, the lowest kept), and scenarios with a
/// launch restraint: `--deployed` drops it, a time before the release is refused naming it.
#[test]
fn modes_of_small_and_restrained_structures() {
    let dir = common::tmp("trust2", "count");
    let out = dir.join("m.csv");
    for e in ["paper-1panel", "paper-3panel-euler", "contact-zfold", "contact-panel-hub"] {
        let o = foldsim()
            .arg("modes")
            .arg(repo(&format!("examples/{e}.toml")))
            .args(["--count", "3", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let t = text(&o);
        assert!(o.status.success() && !t.contains("NaN"), "{e}: {t}");
        let rows = std::fs::read_to_string(&out).unwrap();
        assert_eq!(rows.lines().filter(|l| l.starts_with("free,")).count(), 3, "{e}: {rows}");
        assert_eq!(rows.lines().filter(|l| l.starts_with("hub_fixed,")).count(), 3, "{e}: {rows}");
    }
    let s = dir.join("restrained.toml");
    let o = foldsim()
        .args(["generate", "flasher", "--gores", "4", "--rings", "2", "--release-at", "0.5", "-o"])
        .arg(&s)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let o = foldsim().arg("modes").arg(&s).args(["--deployed", "-q", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let o =
        foldsim().arg("linearize").arg(&s).args(["--deployed", "-q", "-o"]).arg(dir.join("m.npz")).output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let o = foldsim().arg("modes").arg(&s).args(["-o"]).arg(&out).output().unwrap();
    let t = text(&o);
    assert!(!o.status.success() && t.contains("release_at = 0.5") && t.contains("--deployed"), "{t}");
}

/// Item 4: the contact z-fold's E + D balance did not converge with the tolerance (4.6e-6
/// relative at rtol 1e-8, 5.8e-7 at 1e-10, 1.4e-6 at 1e-11): steps straddled the instants
/// where contact points enter or leave contact, where the law's `K δⁿ` bends, and the error
/// estimate does not see that error (without damping or friction, e = 1 and μ = 0, it stayed
/// at 1e-7). Below rtol 1e-9 the steps now end there. The first 1.5 s (the closing and its
/// impacts) at rtol 1e-11: ≤ 1e-8 of the larger of |E(0)| and D, the bound docs/contact.md
/// promises; measured 5.6e-9 (the whole 6-s example: 6.4e-9).
#[test]
fn contact_energy_balance_converges_with_the_tolerance() {
    let s = edited(
        "contact-zfold.toml",
        &[("duration = 6.0", "duration = 1.5"), ("rtol = 1e-8", "rtol = 1e-11"), ("atol = 1e-10", "atol = 1e-13")],
    )
    .unwrap();
    let (_, rows, report) = common::run(&s);
    let d = &report.drift;
    let scale = d.energy_initial.abs().max(d.dissipated.abs());
    let relative = d.energy_balance / scale;
    println!(
        "E + D balance {:.3e} J ({relative:.2e} of {scale:.4e} J), {} steps",
        d.energy_balance, report.steps_accepted
    );
    assert!(rows.last().unwrap().dissipated() > 1.0, "the panels closed and struck");
    assert!(relative <= 1e-8, "{relative:e}");
}

/// Item 19: `foldsim plot` drew every column on one axis whatever its unit; now one panel per
/// unit, stacked on a common t axis (the image grows by a panel's height per unit: 540 px for
/// one unit, 920 for two, 1680 for four; before, 700 whatever the columns).
#[cfg(feature = "plot")]
#[test]
fn plot_gives_each_unit_its_panel() {
    let dir = common::tmp("trust2", "plot");
    let csv = dir.join("p.csv");
    let o =
        foldsim().arg("run").arg(repo("examples/paper-1panel.toml")).arg("--csv").arg(&csv).arg("-q").output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let height = |columns: &str| {
        let png = dir.join("p.png");
        let o = foldsim().arg("plot").arg(&csv).args(["--columns", columns, "-o"]).arg(&png).output().unwrap();
        assert!(o.status.success(), "{}", text(&o));
        let b = std::fs::read(&png).unwrap();
        u32::from_be_bytes([b[20], b[21], b[22], b[23]])
    };
    assert_eq!(height("h1_yaw,h1_pitch"), 540);
    assert_eq!(height("h1_yaw,h1_delta_x"), 920);
    assert_eq!(height("h1_yaw,h1_delta_x,E,w_B_z,h1_roll"), 1680);
}

/// Item 17: messages that blamed the wrong thing. A 1e300 N load was blamed on the
/// tolerances (the body's acceleration, 1e299 m/s², is finite but its square is not): now
/// refused at the start, naming the load. A thickness of 1e-300 m was reported as "edges must
/// not cross", and thick ring-quads were refused by foldsim's own overlap check: the
/// generator now says what is wrong with its options.
#[test]
fn messages_blame_the_right_thing() {
    let e = edited(
        "paper-1panel.toml",
        &[("[initial.hub]", "[[load]]\nname = \"big\"\nbody = \"panel\"\nforce = [1e300, 0.0, 0.0]\nforce_frame = \"body\"\n\n[initial.hub]")],
    )
    .map(|s| {
        let mut sink = |_: &foldsim::observe::Observation| Ok(());
        foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_err().to_string()
    })
    .unwrap_or_else(|e| e);
    assert!(e.contains("'big'") && e.contains("too large") && !e.contains("tolerances"), "{e}");
    let dir = common::tmp("trust2", "gen");
    for (args, words) in [
        (&["--thickness", "1e-300"][..], &["--thickness", "millionth", "membrane"][..]),
        (&["--panels", "ring-quads", "--thickness", "0.01"][..], &["ring-quads", "triangles or quads"][..]),
    ] {
        let o = foldsim()
            .args(["generate", "flasher", "--gores", "6", "--rings", "3"])
            .args(args)
            .arg("-o")
            .arg(dir.join("f.toml"))
            .output()
            .unwrap();
        let t = text(&o);
        assert!(!o.status.success() && !t.contains("edges must not cross") && !t.contains("overlap by"), "{t}");
        for w in words {
            assert!(t.contains(w), "lacks '{w}': {t}");
        }
    }
}

/// Item 18 (in part): the contact event log. A panel swinging into the hub strikes it twice
/// (impacts, their speeds the approach speeds at the accepted step they began: the first at
/// 0.85 s near the swing's 1.2 m/s); the thick flasher's stowed wrap rests on itself from
/// t = 0 (resting episodes, told apart from impacts). `foldsim run --contacts` writes every
/// episode, one row each, as the report counts them.
#[test]
fn contact_episodes_tell_resting_from_impacts() {
    let s = common::scenario("examples/contact-panel-hub.toml");
    let (_, _, report) = common::run(&s);
    let impacts: Vec<_> = report.contact_episodes.iter().filter(|e| !e.resting).collect();
    assert_eq!(impacts.len(), report.contact_episodes.len());
    assert!(impacts.len() >= 2, "{impacts:?}");
    let first = impacts[0];
    assert!((first.start - 0.85).abs() < 0.01 && first.impact_speed > 1.0 && first.end.is_some(), "{first:?}");
    assert!(first.deepest.0 > 0.0 && first.peak_force.0 > 0.0 && first.deepest.1 >= first.start);
    let thick = edited("flasher-thick.toml", &[("duration = 1.7", "duration = 0.002")]).unwrap();
    let (_, _, report) = common::run(&thick);
    let resting = report.contact_episodes.iter().filter(|e| e.resting).count();
    assert!(resting > 10 && report.contact_episodes.iter().all(|e| e.resting == (e.start == 0.0)), "{resting}");
    // Each episode says whether a hinge joins its pair (neighbours meeting at their crease)
    // or none does (a strike of the structure on itself): the stowed wrap has both, layers
    // on hinged neighbours and on panels of other gores.
    let hinged: Vec<(usize, usize)> =
        thick.model.hinges.iter().map(|h| (h.parent.min(h.child), h.parent.max(h.child))).collect();
    for e in &report.contact_episodes {
        assert_eq!(e.joined, hinged.contains(&e.bodies), "{e:?}");
    }
    let joined = report.contact_episodes.iter().filter(|e| e.joined).count();
    assert!(joined > 0 && joined < report.contact_episodes.len(), "{joined} of {}", report.contact_episodes.len());
    let dir = common::tmp("trust2", "episodes");
    let out = dir.join("events.csv");
    let o = foldsim()
        .arg("run")
        .arg(repo("examples/contact-panel-hub.toml"))
        .arg("--csv")
        .arg(dir.join("r.csv"))
        .arg("--contacts")
        .arg(&out)
        .arg("-q")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let table = std::fs::read_to_string(&out).unwrap();
    assert!(table.starts_with("body_a,body_b,kind,start_s"), "{table}");
    assert!(table.lines().next().unwrap().ends_with(",peak_force_at_s,joined"), "{table}");
    assert_eq!(table.lines().count(), 1 + impacts.len(), "{table}");
    // The panel strikes the hub it is hinged to.
    assert!(table.lines().skip(1).all(|l| l.starts_with("hub,panel,impact,") && l.ends_with(",true")), "{table}");
    let o = foldsim()
        .arg("run")
        .arg(repo("examples/contact-panel-hub.toml"))
        .args(["--csv", "/dev/null"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let said = text(&o);
    assert!(
        said.contains(" 0 between bodies no hinge joins, ")
            && said.contains("strikes between bodies no hinge joins: none")
            && said.contains("between hinged neighbours (their creases closing or ringing), the fastest:"),
        "{said}"
    );
    let o = foldsim()
        .arg("run")
        .arg(repo("examples/paper-1panel.toml"))
        .args(["--csv", "/dev/null", "--contacts"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!o.status.success() && text(&o).contains("no [contact]"), "{}", text(&o));
}

/// A hinge lever many orders beyond its body's size (the fuzzer's `a.child_com` z of 1e12 m
/// on the thick example, whose SDIRK4 Newton matrix then has a singular pivot block) stops
/// the run with the hinge, the key and the ratio named, not a bare "singular pivot block".
#[test]
fn a_singular_newton_matrix_names_the_far_hinge() {
    let line = "a = { child_com = [0.46011806451532333, 0.0, 0.09249013370148257], yaw = 3.141592653589793, pitch = -0.9424777960769378, roll = 1.5707963267948966 }";
    let far = line.replace("0.09249013370148257", "1e12");
    let s = edited("flasher-thick.toml", &[(line, &far)]).unwrap();
    assert!(s.warnings.iter().any(|w| w.contains("h23_p33_p34") && w.contains("a.child_com")), "{:?}", s.warnings);
    let mut sink = |_: &foldsim::observe::Observation| -> Result<(), String> { Ok(()) };
    let e = foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_err().to_string();
    for w in
        ["Newton matrix", "singular pivot block, body '", "hinge 'h23_p33_p34''s a.child_com", "times its body's size"]
    {
        assert!(e.contains(w), "{w} not in: {e}");
    }
}

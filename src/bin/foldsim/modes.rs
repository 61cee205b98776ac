//! `foldsim modes`: a structure's natural modes at rest (docs/linear.md), as a CSV table and
//! a short report; `foldsim equilibrium`: its static equilibrium as `[initial]` tables.

use foldsim::linear::linearize_at;
use foldsim::linear::modes::{Mode, Modes};
use foldsim::output::paths::{check_outputs, write_atomically};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The table's header: one row per mode.
const HEADER: &str = "kind,index,frequency_hz,omega,omega_squared,damping_ratio,eff_mass_x,eff_mass_y,eff_mass_z,eff_inertia_x,eff_inertia_y,eff_inertia_z";

/// One row of the table.
fn row(out: &mut String, kind: &str, index: usize, m: &Mode) {
    // A rigid-body mode has no frequency to relate a damping to: its ratio is left empty
    // (never "NaN" in a table a person reads).
    let zeta = if m.damping_ratio.is_finite() { m.damping_ratio.to_string() } else { String::new() };
    let _ = write!(out, "{kind},{index},{},{},{},{zeta}", m.frequency_hz(), m.omega, m.eigenvalue);
    for e in m.effective {
        let _ = write!(out, ",{e}");
    }
    out.push('\n');
}

/// Where and how `foldsim modes` takes the modes.
pub(crate) struct Choice {
    /// Run to this time first, s.
    pub at: f64,
    /// The design state instead of the initial one.
    pub deployed: bool,
    /// Only this many lowest flexible modes, by Lanczos.
    pub count: Option<usize>,
}

/// The scenario at `path` with the initial conditions `choice` asks for, and the output it
/// writes (`output`, else `<scenario name><suffix>` here) checked with `extra` outputs
/// against its inputs.
fn open(
    path: &Path,
    output: Option<PathBuf>,
    suffix: &str,
    extra: &[(&str, &Path)],
    choice: &Choice,
) -> Result<(foldsim::scenario::Scenario, PathBuf), String> {
    let mut scenario = foldsim::scenario::Scenario::from_file(path).map_err(|e| e.to_string())?;
    scenario.initial = foldsim::linear::start_for(
        &scenario.model,
        &scenario.initial,
        &mut scenario.settings,
        choice.at,
        choice.deployed,
    )
    .map_err(|e| format!("--at {e}"))?;
    let target = output.unwrap_or_else(|| {
        let stem = path.file_stem().map_or_else(|| "foldsim".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}{suffix}"))
    });
    let ext = Path::new(suffix).extension().map_or(String::new(), |e| e.to_string_lossy().into_owned());
    let format = match ext.as_str() {
        "npz" => "a NumPy archive (.npz)",
        "csv" => "a CSV table",
        _ => "TOML",
    };
    foldsim::output::paths::check_extension("-o", &target, &ext, format)?;
    for (flag, p) in extra {
        foldsim::output::paths::check_extension(flag, p, "html", "a viewer page (HTML)")?;
    }
    let mut outputs: Vec<(&str, &Path)> = vec![("-o", &target)];
    outputs.extend_from_slice(extra);
    check_outputs(&scenario.inputs, &outputs)?;
    Ok((scenario, target))
}

/// Bodies above which `foldsim modes` takes the 20 lowest modes by Lanczos unless told.
const DENSE_BODIES: usize = 200;

/// `foldsim modes`: linearises the scenario at time `at` of its run, writes the modes' table.
pub(crate) fn modes(
    path: &Path,
    output: Option<PathBuf>,
    choice: Choice,
    (view, shown): (Option<PathBuf>, &str),
    quiet: bool,
) -> Result<(), String> {
    if choice.count == Some(0) {
        return Err("--count 0: ask for at least one mode".into());
    }
    let extra: Vec<(&str, &Path)> = view.iter().map(|v| ("--view", v.as_path())).collect();
    let (scenario, target) = open(path, output, "-modes.csv", &extra, &choice)?;
    let Choice { at, count, .. } = choice;
    let shown = match shown.split_once(':') {
        Some((kind @ ("free" | "hub_fixed"), k)) => {
            (kind == "hub_fixed", k.parse::<usize>().map_err(|_| format!("--mode {shown}: K must be a whole number"))?)
        }
        _ => return Err(format!("--mode {shown}: give free:K or hub_fixed:K, K the table's index")),
    };
    let (lin, here) = linearize_at(&scenario.model, &scenario.initial, &scenario.settings, at)?;
    if let (Some(why), true) = (&here.unbalanced, choice.deployed) {
        return Err(format!(
            "--deployed: {why}. Modes are vibrations about an equilibrium: find one (`foldsim equilibrium`, from a state nearer it) and start the scenario there"
        ));
    }
    let count = count.or((lin.bodies > DENSE_BODIES).then_some(20));
    let started = std::time::Instant::now();
    let modes = match count {
        Some(c) => Modes::lowest(&lin, &here.positions, &here.dcm_n_b, c)?,
        None => Modes::of(&lin, &here.positions, &here.dcm_n_b)?,
    };
    let solve_seconds = started.elapsed().as_secs_f64();
    let unstable: Vec<f64> =
        modes.free.iter().chain(&modes.hub_fixed).filter(|m| !m.omega.is_finite()).map(|m| m.eigenvalue).collect();
    if !unstable.is_empty() {
        return Err(format!(
            "{} modes have no real frequency (ω² down to {:.3e} s⁻²): the state is no stable equilibrium (a buckling load, or a moving state whose stiffness is not a vibration's); take the modes at an equilibrium (`foldsim equilibrium`, or --deployed)",
            unstable.len(),
            unstable.iter().copied().fold(f64::INFINITY, f64::min)
        ));
    }
    let mut table = String::from(HEADER);
    table.push('\n');
    for (i, m) in modes.free.iter().enumerate() {
        row(&mut table, if m.rigid { "rigid" } else { "free" }, i, m);
    }
    for (i, m) in modes.hub_fixed.iter().enumerate() {
        row(&mut table, "hub_fixed", i, m);
    }
    // The mode to show is checked before anything is written: a refusal leaves no table.
    let page_mode = match &view {
        Some(page) => {
            let set = if shown.0 { &modes.hub_fixed } else { &modes.free };
            let m = set.get(shown.1).ok_or_else(|| {
                format!(
                    "--mode {}:{}: the table has {} {} modes (index 0 to {}); nothing written",
                    if shown.0 { "hub_fixed" } else { "free" },
                    shown.1,
                    set.len(),
                    if shown.0 { "hub_fixed" } else { "free" },
                    set.len().saturating_sub(1)
                )
            })?;
            Some((page, m))
        }
        None => None,
    };
    write_atomically(&target, table.as_bytes())?;
    if let Some((page, m)) = page_mode {
        mode_page(path, &scenario, &here.state, m, shown.0, page)?;
        if !quiet {
            outln!(
                "  mode page ({} at {:.6} Hz, two periods) -> {}",
                if shown.0 { "hub-fixed" } else { "free-free" },
                m.frequency_hz(),
                page.display()
            );
        }
    }
    if quiet {
        return Ok(());
    }
    let name = scenario.title.as_deref().unwrap_or("");
    outln!("foldsim modes: {name}");
    outln!(
        "  at t = {} s: {} bodies, {} coordinates; residual acceleration {:.3e} (0 at an equilibrium)",
        here.t,
        lin.bodies,
        6 * lin.bodies,
        lin.residual
    );
    if let Some((iterations, moved, residual)) = here.balanced {
        outln!(
            "  note: that state is at rest but out of balance (largest acceleration {residual:.3e}): the modes are taken at the static equilibrium nearest it ({iterations} Newton iterations, bodies moved up to {moved:.3e} m; `foldsim equilibrium` writes it)"
        );
    }
    if here.unbalanced.is_some() {
        outln!(
            "  note: that state is at rest but out of balance, with no equilibrium found near it: these are the modes of its configuration (`foldsim equilibrium` looks for one)"
        );
    }
    let (w, v) = here.largest_rates;
    if w > 0.0 || v > 0.0 {
        outln!(
            "  note: the bodies move there (up to {w:.3e} rad/s, {v:.3e} m/s): these are the modes of the configuration, the rates left out"
        );
    }
    if modes.asymmetry.is_finite() && modes.asymmetry > 1e-12 {
        outln!(
            "  note: the stiffness is not symmetric ({:.2e} relative: law 1, or a loaded state away from equilibrium): the modes use its symmetric part (docs/linear.md)",
            modes.asymmetry
        );
    }
    let rigid = modes.free.iter().filter(|m| m.rigid).map(|m| m.eigenvalue.abs()).fold(0.0, f64::max);
    let flexible: Vec<&Mode> = modes.free.iter().filter(|m| !m.rigid).collect();
    if let Some(first) = flexible.first() {
        outln!(
            "  free-free: 6 rigid-body modes (ω² up to {rigid:.2e} s⁻², {:.1e} of the first flexible)",
            rigid / first.eigenvalue
        );
    }
    outln!("    mode  frequency Hz   damping ratio");
    for (i, m) in flexible.iter().take(10).enumerate() {
        outln!("    {:>4}  {:>12.6}   {:>13.4e}", i + 1, m.frequency_hz(), m.damping_ratio);
    }
    let total = modes.appendage_total;
    outln!(
        "  hub fixed: appendages' mass {:.4} kg, inertia about the hub's axes {:.4} {:.4} {:.4} kg·m²",
        total[0],
        total[3],
        total[4],
        total[5]
    );
    outln!("    mode  frequency Hz   effective mass x/y/z (fraction)   effective inertia x/y/z (fraction)");
    for (i, m) in modes.hub_fixed.iter().take(10).enumerate() {
        let f = |a: usize| m.effective[a] / total[a].max(f64::MIN_POSITIVE);
        outln!(
            "    {:>4}  {:>12.6}   {:.3} {:.3} {:.3}                 {:.3} {:.3} {:.3}",
            i + 1,
            m.frequency_hz(),
            f(0),
            f(1),
            f(2),
            f(3),
            f(4),
            f(5)
        );
    }
    let solver = match count {
        Some(c) if lin.bodies <= foldsim::linear::modes::DENSE_FOR_LOWEST => format!("the {c} lowest, dense"),
        Some(c) => format!("the {c} lowest by shift-invert Lanczos"),
        None => "all, dense".into(),
    };
    outln!(
        "  {} modes ({solver}, {solve_seconds:.2} s) -> {}",
        modes.free.len() + modes.hub_fixed.len(),
        target.display()
    );
    Ok(())
}

/// `foldsim equilibrium`: Newton from the scenario's initial state to a static equilibrium,
/// written as `[initial]` tables.
pub(crate) fn equilibrium(
    path: &Path,
    output: Option<PathBuf>,
    tolerance: f64,
    spin_rate: f64,
    quiet: bool,
) -> Result<(), String> {
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(format!("--tolerance {tolerance}: give a force or torque > 0 (N, N·m)"));
    }
    if !spin_rate.is_finite() {
        return Err(format!("--spin-rate {spin_rate}: give a rate in rad/s"));
    }
    let scenario = foldsim::scenario::Scenario::from_file(path).map_err(|e| e.to_string())?;
    let target = output.unwrap_or_else(|| {
        let stem = path.file_stem().map_or_else(|| "foldsim".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}-equilibrium.toml"))
    });
    check_outputs(&scenario.inputs, &[("-o", &target)])?;
    let stepper = foldsim::simulate::Stepper::start(&scenario.model, &scenario.initial, &scenario.settings)
        .map_err(|e| e.to_string())?;
    let hub = foldsim::state::BodyMotion::from_state(stepper.state(), 0);
    let spin = hub.dcm_n_b.column(2) * spin_rate;
    let found =
        foldsim::linear::equilibrium::Equilibrium::spinning(stepper.dynamics(), stepper.state(), spin, tolerance, 50)?;
    let ic = &scenario.initial;
    let text = format!(
        "# The {} equilibrium of {} nearest its initial state (foldsim equilibrium):\n# replace the scenario's [initial] tables with these.\n\n{}",
        if spin_rate == 0.0 {
            "static".to_string()
        } else {
            format!("relative (spinning at {spin_rate} rad/s about the hub's z)")
        },
        path.display(),
        found.initial_tables(&scenario.model, (ic.hub_position_in_n, ic.hub_attitude))
    );
    write_atomically(&target, text.as_bytes())?;
    if !quiet {
        outln!("foldsim equilibrium: {}", scenario.title.as_deref().unwrap_or(""));
        outln!(
            "  {} Newton iterations: largest force or torque on a body {:.3e} -> {:.3e}; bodies moved up to {:.4e} m",
            found.iterations,
            found.start_residual,
            found.residual,
            found.moved
        );
        outln!("  [initial] tables -> {}", target.display());
    }
    Ok(())
}

/// `foldsim linearize`: the state-space model at a state, written as `.npz`.
pub(crate) fn linearize(
    path: &Path,
    output: Option<PathBuf>,
    choice: Choice,
    (inputs, outputs): (Option<Vec<String>>, Option<Vec<String>>),
    hub_held: bool,
    quiet: bool,
) -> Result<(), String> {
    use foldsim::linear::statespace::{default_outputs, outputs_matching, state_space};
    use foldsim::output::npz::{Array, npz_bytes};
    let (mut scenario, target) = open(path, output, "-linear.npz", &[], &choice)?;
    let at = choice.at;
    let model = &mut scenario.model;
    model.commandable = true;
    let bodies: Vec<usize> = match inputs {
        None => vec![0],
        Some(names) => names
            .iter()
            .map(|b| {
                model.bodies.iter().position(|x| &x.name == b).ok_or_else(|| {
                    let known: Vec<&str> = model.bodies.iter().take(8).map(|x| x.name.as_str()).collect();
                    format!("--inputs: no body '{b}' (bodies: {}, …)", known.join(", "))
                })
            })
            .collect::<Result<_, _>>()?,
    };
    let outputs = match outputs {
        None => default_outputs(),
        Some(p) => outputs_matching(model, &p).map_err(|e| format!("--outputs: {e}"))?,
    };
    let ss = match choice.count {
        None => state_space(&scenario.model, &scenario.initial, &scenario.settings, at, &bodies, &outputs)?,
        Some(count) => {
            use foldsim::linear::reduced::{Reduction, reduced_state_space};
            let kind = if hub_held { Reduction::HubHeld } else { Reduction::FreeFree };
            let (m, ic, set) = (&scenario.model, &scenario.initial, &scenario.settings);
            reduced_state_space(m, ic, set, at, &bodies, &outputs, count, kind).map_err(|e| format!("--modes: {e}"))?
        }
    };
    let bytes = npz_bytes(&[
        ("A", Array::Matrix(&ss.a)),
        ("B", Array::Matrix(&ss.b)),
        ("C", Array::Matrix(&ss.c)),
        ("D", Array::Matrix(&ss.d)),
        ("y0", Array::Vector(ss.y0.as_slice())),
        ("t", Array::Vector(&[ss.t])),
        ("states", Array::Strings(&ss.states)),
        ("inputs", Array::Strings(&ss.inputs)),
        ("outputs", Array::Strings(&ss.outputs)),
    ])?;
    write_atomically(&target, &bytes)?;
    if !quiet {
        outln!("foldsim linearize: {}", scenario.title.as_deref().unwrap_or(""));
        outln!(
            "  at t = {} s: {} states, {} inputs, {} outputs; residual acceleration {:.3e} with the inputs at zero (0 at an equilibrium)",
            ss.t,
            ss.states.len(),
            ss.inputs.len(),
            ss.outputs.len(),
            ss.residual
        );
        outln!("  inputs: {}", ss.inputs.join(", "));
        outln!("  outputs: {}", ss.outputs.join(", "));
        outln!("  A, B, C, D, y0, t, states, inputs, outputs -> {}", target.display());
    }
    Ok(())
}

/// The viewer page of one mode: the structure displaced along it, `sin(ω t)` over two periods
/// (one second a period for a rigid mode), its largest motion a twentieth of the structure's
/// size.
#[cfg(feature = "animation")]
fn mode_page(
    path: &Path,
    scenario: &foldsim::scenario::Scenario,
    y: &[f64],
    mode: &Mode,
    hub_fixed: bool,
    page: &Path,
) -> Result<(), String> {
    use foldsim::observe::{Observer, catalogue, row};
    use foldsim::output::animation::{Table, frames_from_table};
    // Displaced about `y`, the state the modes were taken at (the equilibrium when one was
    // found); the dynamics only lends the angle references the rows are read with.
    let stepper = foldsim::simulate::Stepper::start(&scenario.model, &scenario.initial, &scenario.settings)
        .map_err(|e| e.to_string())?;
    let d = stepper.dynamics();
    let y = y.to_vec();
    let n = scenario.model.bodies.len();
    let centres: Vec<foldsim::math::Vec3> =
        (0..n).map(|i| foldsim::state::BodyMotion::from_state(&y, i).r_in_n).collect();
    let size = centres.iter().map(|r| (r - centres[0]).norm()).fold(0.0, f64::max).max(1e-3);
    let period = if mode.omega > 0.0 { 2.0 * std::f64::consts::PI / mode.omega } else { 1.0 };
    let frames = 60;
    let mut observer = Observer::new(&scenario.model, scenario.initial.hub_attitude, &foldsim::math::Vec3::zeros());
    let mut rows = Vec::with_capacity(frames + 1);
    for k in 0..=frames {
        let t = 2.0 * period * k as f64 / frames as f64;
        let amplitude = 0.05 * size * (2.0 * std::f64::consts::PI * t / period).sin();
        let z = foldsim::linear::modes::displaced(&y, &mode.shape, hub_fixed, amplitude, size / (n as f64).sqrt());
        let o = observer.observe(&scenario.model, t, &z, &d.theta_refs(), &d.memories(), None);
        rows.push(row(&o));
    }
    let width = rows.first().map_or(0, Vec::len);
    let header: Vec<String> = catalogue(&scenario.model).into_iter().map(|c| c.name).take(width).collect();
    let table = Table { header, rows };
    let (frames, kept, _) = frames_from_table(&scenario.model, &table, None)?;
    let title = format!(
        "{}: {} mode at {:.6} Hz (displacement exaggerated)",
        scenario.title.clone().unwrap_or_else(|| path.display().to_string()),
        if hub_fixed { "hub-fixed" } else { "free-free" },
        mode.frequency_hz()
    );
    // Plot the hinge angle the mode moves most.
    let range = |c: usize| {
        let v = table.rows.iter().map(|r| r[c]);
        v.clone().fold(f64::NEG_INFINITY, f64::max) - v.fold(f64::INFINITY, f64::min)
    };
    let angle = (0..table.header.len())
        .filter(|&c| {
            let h = &table.header[c];
            scenario.model.hinges.iter().any(|x| h.starts_with(&x.name))
                && (h.ends_with("_yaw") || h.ends_with("_pitch") || h.ends_with("_roll"))
        })
        .max_by(|&a, &b| range(a).total_cmp(&range(b)));
    let columns: Vec<String> = angle.map(|c| table.header[c].clone()).into_iter().collect();
    let html = foldsim::output::viewer::page(&title, &scenario.model, &table, &frames, &kept, &columns)?;
    write_atomically(page, html.as_bytes())?;
    Ok(())
}

#[cfg(not(feature = "animation"))]
fn mode_page(_: &Path, _: &foldsim::scenario::Scenario, _: &[f64], _: &Mode, _: bool, _: &Path) -> Result<(), String> {
    Err("--view needs foldsim built with the `animation` feature".into())
}

/// `foldsim modes --spin-rate W`: the relative equilibrium of a steady spin near the state,
/// then the modes there in the turning frame, as a table of `spinning` rows.
pub(crate) fn spinning_modes(
    path: &Path,
    output: Option<PathBuf>,
    choice: Choice,
    spin_rate: f64,
    quiet: bool,
) -> Result<(), String> {
    if !spin_rate.is_finite() {
        return Err(format!("--spin-rate {spin_rate}: give a rate in rad/s"));
    }
    let (scenario, target) = open(path, output, "-modes.csv", &[], &choice)?;
    let at = choice.at;
    let mut stepper = foldsim::simulate::Stepper::start(&scenario.model, &scenario.initial, &scenario.settings)
        .map_err(|e| e.to_string())?;
    if at > 0.0 {
        stepper.advance(at).map_err(|e| e.to_string())?;
    }
    let hub = foldsim::state::BodyMotion::from_state(stepper.state(), 0);
    let spin = hub.dcm_n_b.column(2) * spin_rate;
    // Forces left below 1e-7 of the largest centripetal force (or 1e-10 N at rest): above the
    // round-off of stiff hinges (1e-16 of k_f times a size, 5e-8 N at 1e9 N/m and 2 m).
    let n = scenario.model.bodies.len();
    let scale = (0..n)
        .map(|i| {
            let r = foldsim::state::BodyMotion::from_state(stepper.state(), i).r_in_n - hub.r_in_n;
            scenario.model.bodies[i].mass * spin_rate * spin_rate * r.norm()
        })
        .fold(0.0, f64::max);
    let d = stepper.dynamics();
    let found =
        foldsim::linear::equilibrium::Equilibrium::spinning(d, stepper.state(), spin, 1e-7 * scale + 1e-10, 50)?;
    d.accept(stepper.time(), &found.y)?;
    let modes = foldsim::linear::modes::spinning(d, &found.y, spin)?;
    let mut table = String::from(HEADER);
    table.push('\n');
    for (i, m) in modes.iter().enumerate() {
        let _ = writeln!(
            table,
            "spinning,{i},{},{},{},{},0,0,0,0,0,0",
            m.damped / (2.0 * std::f64::consts::PI),
            m.damped,
            m.omega * m.omega,
            m.damping_ratio
        );
    }
    write_atomically(&target, table.as_bytes())?;
    if !quiet {
        let name = scenario.title.clone().unwrap_or_else(|| path.display().to_string());
        outln!("foldsim modes: {name}, spinning at {spin_rate} rad/s about the hub's z axis");
        outln!(
            "  relative equilibrium: {} Newton iterations, largest force or torque {:.3e} -> {:.3e}; bodies moved up to {:.4e} m",
            found.iterations,
            found.start_residual,
            found.residual,
            found.moved
        );
        outln!("    mode  frequency Hz (turning frame)   damping ratio");
        for (i, m) in modes.iter().take(10).enumerate() {
            outln!(
                "    {:>4}  {:>12.6}                 {:>13.4e}",
                i + 1,
                m.damped / (2.0 * std::f64::consts::PI),
                m.damping_ratio
            );
        }
        outln!("  {} modes -> {}", modes.len(), target.display());
    }
    Ok(())
}

//! The report printed at the end of a run.

use foldsim::law::EventKind;
use foldsim::law::directional::DIRECTION_NAMES;
use foldsim::scenario::Scenario;
use foldsim::simulate::RunReport;
use std::path::Path;

/// How many located hinge events the report lists; the rest go to `--events`.
const EVENTS_LISTED: usize = 20;

/// Prints a finished run's report: what ran, the drift of its invariants, contact,
/// deployment and its first hinge events (all of them in `events`, the `--events` table,
/// when given).
pub(crate) fn print_report(scenario: &Scenario, r: &RunReport, csv: &Path, events: Option<&Path>) {
    let d = &r.drift;
    let rel = |x: f64, scale: f64| if scale > 0.0 { x / scale } else { x };
    outln!("foldsim run: {}", scenario.title.as_deref().unwrap_or("(untitled)"));
    outln!(
        "  bodies {}, hinges {} ({} loop), integrator {}",
        scenario.model.bodies.len(),
        scenario.model.hinges.len(),
        scenario.model.is_tree_hinge.iter().filter(|t| !**t).count(),
        scenario.settings.integrator.name()
    );
    outln!("  simulated time   {:.6} s", r.simulated);
    outln!("  wall time        {:.3} s", r.wall_seconds);
    if r.newton_failures > 0 {
        outln!(
            "  steps            {} accepted, {} rejected ({} for Newton not converging)",
            r.steps_accepted,
            r.steps_rejected,
            r.newton_failures
        );
    } else {
        outln!("  steps            {} accepted, {} rejected", r.steps_accepted, r.steps_rejected);
    }
    if r.drift.locks > 0 {
        outln!("  rhs evaluations  {} ({} solving for engaged locks)", r.rhs_evaluations, r.constrained_evaluations);
    } else {
        outln!("  rhs evaluations  {}", r.rhs_evaluations);
    }
    if r.jacobians > 0 {
        let how = if r.differenced_jacobians > 0 {
            "by finite differences: a hinge law without a dual form"
        } else {
            "exact, by dual numbers"
        };
        outln!(
            "  newton           {} iterations, {} Jacobians ({how}), {} refactorizations for a new step",
            r.newton_iterations,
            r.jacobians,
            r.refactorizations
        );
    }
    if !r.methods.is_empty() {
        // integrator = "auto": which method ran when, and why it took over.
        let switches = r.methods.len() - 1;
        let shown = 6;
        for (k, m) in r.methods.iter().enumerate().take(shown) {
            let head = if k == 0 { "  auto             " } else { "                   " };
            outln!("{head}{} from t = {:.4} s ({})", m.method, m.from, m.why);
        }
        if switches + 1 > shown {
            outln!("                   ... {} switches in all", switches);
        }
    } else if let Some(t) = r.stiff_from {
        outln!(
            "  note: from t = {t:.4} s the explicit steps were limited by stability, not accuracy: stiff hinges; integrator = \"sdirk4\" (implicit) suits this run better"
        );
    }
    if let Some(a) = &r.position_accuracy {
        let tolerances: Vec<String> = a.runs.iter().map(|(t, w)| format!("{t:.1e} ({w:.2} s)")).collect();
        outln!(
            "  position error   estimated {:.2e} m in any body's centre of mass over the rows (run.position_tolerance = {:.2e} m)",
            a.estimated,
            a.asked
        );
        outln!(
            "                   the output's rtol = atol = {:.1e}; it differs by {:.2e} m from its check at {:.1e}; {} runs: {}",
            a.rtol,
            a.difference,
            a.check_rtol,
            a.runs.len(),
            tolerances.join(", ")
        );
    }
    outln!("  output rows      {} -> {}", r.rows, csv.display());
    outln!("  drift over the run (max |x(t) - x(0)|):");
    outln!("    linear momentum P   {:.3e} kg·m/s  ({:.3e} of Σ m|v|)", d.momentum, rel(d.momentum, d.momentum_scale));
    outln!(
        "    angular momentum H  {:.3e} kg·m²/s ({:.3e} of Σ |r×mv|+|Iω|)",
        d.angular_momentum,
        rel(d.angular_momentum, d.angular_momentum_scale)
    );
    outln!("    barycenter          {:.3e} m (from Rc(0) + P(0) t / M)", d.barycenter);
    if d.locks > 0 {
        outln!(
            "    locked directions   {} held within {:.3e} m and {:.3e} rad of their initial values",
            d.locks,
            d.locked_translation,
            d.locked_rotation
        );
        // Engaged locks, a hinge's at one instant on one line: "h1 x, y, rz at t = 0.1 s".
        let engaged: Vec<String> = r
            .lock_engagements
            .chunk_by(|a, b| a.0.hinge == b.0.hinge && a.1 == b.1)
            .map(|g| {
                let dirs: Vec<&str> = g.iter().map(|(l, _)| DIRECTION_NAMES[l.direction]).collect();
                format!("{} {} at t = {:.6} s", scenario.model.hinges[g[0].0.hinge].name, dirs.join(", "), g[0].1)
            })
            .collect();
        let (n, all) = (r.lock_engagements.len(), d.locks);
        let rest = if n < all {
            format!("; the other {} carried none and were never solved for", all - n)
        } else {
            String::new()
        };
        if n == 0 {
            outln!("    locks engaged       none of {all}: no lock carried load, none was solved for");
        } else {
            let more = if engaged.len() > 4 { format!("; and {} more", engaged.len() - 4) } else { String::new() };
            outln!(
                "    locks engaged       {n} of {all} (carrying load{rest}): {}{more}",
                engaged[..engaged.len().min(4)].join("; ")
            );
        }
    }
    let e_rel = rel(d.energy, d.energy_initial.abs());
    let scale = d.energy_initial.abs().max(d.dissipated.abs());
    // With work done from outside (loads, motors, control) E changes by W: the balance line.
    if r.energy_conserving && r.loads.is_none() {
        outln!("    energy E = T + V    {:.3e} J ({:.3e} relative; conserved by these laws)", d.energy, e_rel);
    } else {
        outln!(
            "    energy E = T + V    {:.3e} J max change ({:.3e} relative), {:+.3e} J at the end: not conserved {}",
            d.energy,
            e_rel,
            d.energy_final_change,
            if r.loads.is_some() {
                "(work from outside: loads, motors or control)"
            } else {
                "by these laws (damping, hysteresis, stops, a 2-D table, or the paper-linear law of docs/model.md §4)"
            }
        );
        outln!(
            "    dissipated D            {:.6e} J by the end (hinge damping, hysteresis, stops, contact; for the paper-linear law the work of its non-potential torque)",
            d.dissipated
        );
        let label = if r.loads.is_some() { "balance |Δ(E + D − W)|" } else { "balance |Δ(E + D)|    " };
        outln!("    {label}  {:.3e} J ({:.3e} relative)", d.energy_balance, rel(d.energy_balance, scale));
    }
    if let Some(l) = &r.loads {
        let v = |x: &foldsim::math::Vec3| format!("[{:.6e}, {:.6e}, {:.6e}]", x.x, x.y, x.z);
        let model = &scenario.model;
        if model.has_external() {
            outln!(
                "  external loads   work W {:.6e} J (loads, torque sources, motors, wheels; E + D − W is the constant)",
                l.work
            );
            outln!(
                "    impulse          ΔP = {} N·s, ΔH = {} N·m·s (about N's origin; the drifts above are net of these)",
                v(&l.impulse_in_n),
                v(&l.angular_impulse_in_n)
            );
        } else {
            outln!(
                "  motors, wheels   work W {:.6e} J (E + D − W is the constant; internal: P and H are kept)",
                l.work
            );
        }
    }
    if let Some(c) = &scenario.model.control {
        let wheels = c.wheels();
        outln!(
            "  control          {} actuator(s){}",
            c.actuator_count(),
            if wheels.is_empty() {
                ": torque sources (external: in W and ΔH)"
            } else {
                ": reaction wheels (internal: their momentum is in H)"
            }
        );
        for ((name, rec), k) in c.actuator_names().iter().zip(&r.actuators).zip(0..) {
            let mut line = format!("    {name:<14} |torque| up to {:.3e} N·m", rec.effort_max);
            if let Some(w) = wheels.get(k) {
                line += &format!(", |J_s Ω| up to {:.3e} N·m·s", rec.momentum_max);
                if w.max_momentum.is_finite() {
                    line += &format!(" ({:.0} % of its limit)", 100.0 * rec.momentum_max / w.max_momentum);
                }
            }
            match rec.torque_first {
                Some(t) => line += &format!("; torque limit from t = {t:.6} s, {:.4} s in all", rec.torque_time),
                None => line += "; torque limit never reached",
            }
            if let Some(t) = rec.momentum_first {
                line += &format!("; SATURATED (momentum limit) from t = {t:.6} s, {:.4} s in all", rec.momentum_time);
            }
            outln!("{line}");
        }
    }
    if let Some(c) = &r.contact {
        let name = |i: usize| scenario.model.bodies[i].name.as_str();
        match c.first {
            None => outln!("  contact          none: no two bodies touched"),
            Some((t, a, b)) => {
                outln!("  contact          first at t = {t:.6} s: {} and {} (at the accepted steps)", name(a), name(b));
                let (d, td, da, db) = c.deepest;
                outln!("    deepest penetration  {d:.3e} m at t = {td:.6} s: {} into {}", name(da), name(db));
                let (f, tf, fa, fb) = c.force_max;
                outln!("    largest force        {f:.4e} N at t = {tf:.6} s: between {} and {}", name(fa), name(fb));
                outln!("    dissipated           {:.6e} J (damping and friction)", r.contact_dissipated);
                let episodes = &r.contact_episodes;
                let resting = episodes.iter().filter(|e| e.resting).count();
                let mut impacts: Vec<_> = episodes.iter().filter(|e| !e.resting).collect();
                impacts.sort_by(|x, y| y.impact_speed.total_cmp(&x.impact_speed));
                // Strikes of the structure on itself (bodies no hinge joins) apart from
                // neighbours meeting at their creases: the first is what a deployment is
                // checked for.
                let (joined, strikes): (Vec<&foldsim::contact::episodes::Episode>, Vec<_>) =
                    impacts.into_iter().partition(|e| e.joined);
                outln!(
                    "    episodes             {} ({resting} resting from the start: the stowed package; {} impacts after: {} between bodies no hinge joins, {} between hinged neighbours)",
                    episodes.len(),
                    strikes.len() + joined.len(),
                    strikes.len(),
                    joined.len()
                );
                let line = |e: &foldsim::contact::episodes::Episode| {
                    format!(
                        "{} / {} at t = {:.6} s: {:.3e} m/s, deepest {:.3e} m, peak {:.4e} N",
                        name(e.bodies.0),
                        name(e.bodies.1),
                        e.start,
                        e.impact_speed,
                        e.deepest.0,
                        e.peak_force.0
                    )
                };
                if strikes.is_empty() {
                    outln!("      strikes between bodies no hinge joins: none");
                } else {
                    outln!("      strikes between bodies no hinge joins, the fastest:");
                    for e in strikes.iter().take(3) {
                        outln!("        {}", line(e));
                    }
                }
                if !joined.is_empty() {
                    outln!("      between hinged neighbours (their creases closing or ringing), the fastest:");
                    for e in joined.iter().take(2) {
                        outln!("        {}", line(e));
                    }
                }
                outln!(
                    "    independent check    foldsim overlaps SCENARIO --csv {} (the rows' poses by GJK/EPA, apart from the contact code; docs/contact.md §3)",
                    csv.display()
                );
            }
        }
    }
    if let Some(t) = r.released_at {
        outln!("  restraint        released at t = {t:.4} s");
    }
    if let Some(t) = r.deployed_90 {
        outln!("  deployment       90 % of the design radius at t = {t:.4} s");
    } else if r.deployed_start < 0.9 && r.deployed_max < 0.9 {
        outln!(
            "  deployment       NOT DEPLOYED: it reached at most {:.0} % of its design radius ({:.0} % at the start; 90 % counts as deployed). Give it more time (run.duration), more stored fold energy or spin, or softer panel bending, or damp less",
            100.0 * r.deployed_max,
            100.0 * r.deployed_start
        );
    }
    if !r.events.is_empty() || r.branch_events > 0 {
        outln!(
            "  hinge events: {} located ({} stop or latch, {} hysteresis branch changes or table points)",
            r.events.len() + r.branch_events,
            r.events.len(),
            r.branch_events
        );
    }
    for e in r.events.iter().take(EVENTS_LISTED) {
        let h = &scenario.model.hinges[e.hinge];
        outln!("    t = {:.9} s  {}: {}", e.t, h.name, e.description);
    }
    if r.events.len() > EVENTS_LISTED {
        let rest = r.events.len() - EVENTS_LISTED;
        let last = r.events.last().map_or(0.0, |e| e.t);
        match events {
            Some(path) => outln!("    ... {rest} more to t = {last:.6} s: every one in {}", path.display()),
            None => outln!("    ... {rest} more to t = {last:.6} s (--events FILE.csv writes every one)"),
        }
    }
    for (i, e) in r.events.iter().enumerate() {
        let first_latch = r.events[..i].iter().all(|p| p.hinge != e.hinge || p.kind != EventKind::Latch);
        if e.kind == EventKind::Latch && first_latch {
            let total = r.hinge_dissipated.get(e.hinge).copied().unwrap_or(0.0);
            outln!(
                "    energy lost at and after latching, hinge {}: {:.6e} J (dissipated from t = {:.6} s to the end)",
                scenario.model.hinges[e.hinge].name,
                total - e.hinge_dissipated,
                e.t
            );
        }
    }
}

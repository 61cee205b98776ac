//! External loads (`[[load]]`, docs/loads.md): the momentum they add and the work they do.

mod common;

use foldsim::math::Vec3;

/// The paper's three-panel case (law 2) with `loads` appended, run to `duration` s with output every
/// `step` s at rtol = atol = 1e-12.
fn loaded(loads: &str, duration: f64, step: f64) -> foldsim::scenario::Scenario {
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    let text = text
        .replace("duration = 20.0", &format!("duration = {duration:?}"))
        .replace("output_step = 0.05", &format!("output_step = {step:?}"));
    foldsim::scenario::Scenario::from_toml(&format!("{text}\n{loads}"), "loaded.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The largest |Δ(E + D − W)| over the rows from the first, J.
fn largest_imbalance(rows: &[foldsim::observe::Observation]) -> f64 {
    let budget = |o: &foldsim::observe::Observation| o.energy() + o.dissipated() - o.work();
    rows.iter().map(|o| (budget(o) - budget(&rows[0])).abs()).fold(0.0, f64::max)
}

/// A constant force at the hub's centre of mass and a constant torque, both fixed in space,
/// on the three-panel case (whose hinges move): P(t) − P(0) = F t exactly, and
/// H(t) − H(0) = ∫ R_hub × F dt + τ t, the integral taken from the output rows' hub positions
/// by Simpson's rule (an independent computation from the load history; with 2,000 intervals
/// over 2 s its error is ~h⁴ R⁗ ≈ 1e-12 of the result). Bounds: 1e-10 relative, the issue's.
/// E + D − W, with W the column the run integrates, stays at its start value to 1e-9 of the
/// energy that moves (DOP853 at 1e-12).
#[test]
fn momentum_and_work_of_space_fixed_loads() {
    let f = Vec3::new(3.0, -2.0, 1.0);
    let tau = Vec3::new(0.5, 0.2, -0.4);
    let s = loaded(
        "[[load]]\nname = \"push\"\nbody = \"hub\"\nforce = [3.0, -2.0, 1.0]\nforce_frame = \"inertial\"\ntorque = [0.5, 0.2, -0.4]\ntorque_frame = \"inertial\"\n",
        2.0,
        0.001,
    );
    let (_, rows, report) = common::run(&s);
    let first = &rows[0];
    let last = rows.last().unwrap();
    let t = last.t - first.t;
    let dp = last.momentum_in_n - first.momentum_in_n;
    let p_err = (dp - f * t).norm() / (f * t).norm();
    // Simpson over the rows (an even number of equal intervals).
    let n = rows.len() - 1;
    assert!(n % 2 == 0, "{n} intervals");
    let h = t / n as f64;
    let mut integral = Vec3::zeros();
    for (k, o) in rows.iter().enumerate() {
        let w = if k == 0 || k == n {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        };
        integral += o.hub_r_in_n.cross(&f) * w;
    }
    let expected = integral * (h / 3.0) + tau * t;
    let dh = last.angular_momentum_in_n - first.angular_momentum_in_n;
    let h_err = (dh - expected).norm() / expected.norm();
    let work = last.work();
    let balance = largest_imbalance(&rows);
    println!(
        "P: {p_err:.2e}, H: {h_err:.2e} (relative); W = {work:.6e} J, |Δ(E + D − W)| {balance:.2e} J ({:.2e} of W); report balance {:.2e}",
        balance / work.abs(),
        report.drift.energy_balance
    );
    assert!(p_err < 1e-10 && h_err < 1e-10, "P {p_err:e}, H {h_err:e}");
    // Relative to the energy that moves: the stored and kinetic energy at the start plus the
    // work (the unloaded case balances to the same 1.2e-9 J: that is its integration error).
    let scale = first.energy().abs() + work.abs();
    println!("energy scale {scale:.4e} J: balance {:.2e} relative", balance / scale);
    assert!(balance < 1e-9 * scale, "{balance:e} of {scale:e}");
    // The report's totals: the impulse the run integrated against F t and the independent
    // angular impulse; its drifts are net of them (and of the barycenter's push).
    let given = report.loads.expect("loads in the report");
    let ip = (given.impulse_in_n - f * t).norm() / (f * t).norm();
    let ih = (given.angular_impulse_in_n - expected).norm() / expected.norm();
    let d = &report.drift;
    println!(
        "report: impulse {ip:.2e}, angular impulse {ih:.2e}; drifts net of them: P {:.2e}, H {:.2e}, barycenter {:.2e} m",
        d.momentum, d.angular_momentum, d.barycenter
    );
    assert!(ip < 1e-10 && ih < 1e-10, "{ip:e} {ih:e}");
    assert!(
        d.momentum < 1e-10 * (f * t).norm() && d.angular_momentum < 1e-10 * expected.norm() && d.barycenter < 1e-10
    );
}

/// A torque fixed in the hub's frame and a force at an off-centre point fixed in a panel's
/// frame, switched on and off: the work column balances E + D to 1e-9 of the energy, and
/// with the loads off again the momentum stays what they left (P, H constant after 1.5 s).
#[test]
fn body_fixed_switched_loads_balance_energy() {
    let s = loaded(
        "[[load]]\nname = \"spin-up\"\nbody = \"hub\"\ntorque = [0.0, 0.0, 2.0]\ntorque_frame = \"body\"\non = [[0.2, 0.7]]\n\n[[load]]\nname = \"kick\"\nbody = \"p1\"\npoint = [0.5, 0.2, 0.0]\nforce = [0.0, 1.0, 0.5]\nforce_frame = \"body\"\non = [[0.5, 1.5]]\n",
        2.0,
        0.001,
    );
    let (_, rows, _) = common::run(&s);
    let first = &rows[0];
    let last = rows.last().unwrap();
    let work = last.work();
    let balance = largest_imbalance(&rows);
    let after: Vec<_> = rows.iter().filter(|o| o.t >= 1.5 + 1e-9).collect();
    let (p0, h0) = (after[0].momentum_in_n, after[0].angular_momentum_in_n);
    let drift = after
        .iter()
        .map(|o| ((o.momentum_in_n - p0).norm() / p0.norm()).max((o.angular_momentum_in_n - h0).norm() / h0.norm()))
        .fold(0.0_f64, f64::max);
    println!(
        "W = {work:.6e} J, |Δ(E + D − W)| {balance:.2e} J ({:.2e} of W); P, H after the loads: {drift:.2e}",
        balance / work.abs()
    );
    assert!(work.abs() > 1e-3, "the loads did work");
    // Relative to the energy that moves: the stored and kinetic energy at the start plus the
    // work (the unloaded case balances to the same 1.2e-9 J: that is its integration error).
    let scale = first.energy().abs() + work.abs();
    println!("energy scale {scale:.4e} J: balance {:.2e} relative", balance / scale);
    assert!(balance < 1e-9 * scale, "{balance:e} of {scale:e}");
    assert!(drift < 1e-10, "{drift:e}");
}

/// The same loads under SDIRK4 (rtol = atol = 1e-10): P(t) − P(0) = F t (a linear invariant,
/// which a Runge–Kutta method keeps up to its Newton tolerance), and E + D − W to the
/// method's tolerance; with loads the implicit path does not restore the initial momenta.
#[test]
fn sdirk4_keeps_the_load_impulse() {
    let f = Vec3::new(3.0, -2.0, 1.0);
    let mut s = loaded(
        "[[load]]\nname = \"push\"\nbody = \"hub\"\nforce = [3.0, -2.0, 1.0]\nforce_frame = \"inertial\"\non = [[0.25, 1.25]]\n",
        2.0,
        0.01,
    );
    s.settings.integrator = foldsim::simulate::Integrator::Sdirk4 { rtol: 1e-10, atol: 1e-10 };
    let (_, rows, report) = common::run(&s);
    let first = &rows[0];
    let last = rows.last().unwrap();
    let dp = last.momentum_in_n - first.momentum_in_n;
    let p_err = (dp - f).norm() / f.norm();
    let scale = first.energy().abs() + last.work().abs();
    let balance = report.drift.energy_balance / scale;
    println!(
        "SDIRK4: P {p_err:.2e} relative (impulse 1 s × F); E + D − W {balance:.2e} of the energy; {} steps",
        report.steps_accepted
    );
    assert!(p_err < 1e-8, "{p_err:e}");
    assert!(balance < 1e-6, "{balance:e}");
}

/// SDIRK4's exact Jacobian (dual numbers) covers loads that turn with their body: against
/// central differences of the right-hand side on the three-panel case with a body-fixed
/// force off a panel's centre and a body-fixed torque on the hub, at a state with the bodies
/// turned and spinning. Bound 1e-8 (the differences' own error at step 1e-7 is ~1e-9).
#[test]
fn exact_jacobian_covers_body_fixed_loads() {
    let s = loaded(
        "[[load]]\nname = \"kick\"\nbody = \"p1\"\npoint = [0.5, 0.2, 0.1]\nforce = [0.3, 1.0, 0.5]\nforce_frame = \"body\"\ntorque = [0.1, 0.0, -0.2]\ntorque_frame = \"body\"\n\n[[load]]\nname = \"hub\"\nbody = \"hub\"\ntorque = [0.0, 0.4, 2.0]\ntorque_frame = \"body\"\n",
        1.0,
        0.1,
    );
    let (mut y, refs) = foldsim::kinematics::initial_state(&s.model, &s.initial);
    const B: usize = 13;
    for b in 0..s.model.bodies.len() {
        y[B * b + 10] += 0.3;
        y[B * b + 11] -= 0.2 * b as f64;
    }
    let dynamics = foldsim::dynamics::Dynamics::new(&s.model, refs);
    dynamics.initialize_memory(&y);
    dynamics.accept(0.0, &y).unwrap();
    let m = common::jacobian_mismatch_at(&dynamics, &y, 1e-7);
    println!("loads: dual Jacobian vs central differences {m:e}");
    assert!(m <= 1e-8, "{m:e}");
}

/// RK4 at a fixed step with a load switched by windows whose edges its grid reaches only to
/// round-off (0.1 and 0.3 are not multiples of 1e-3 in binary): each step that ends at a
/// switch must integrate the load that was on during it. Before the fix the grid's point a
/// round-off past the switch took its last stage after the jump, losing F·h/6 per switch
/// (ΔP = 2.9995 N·s for 3 N over 1 s at h = 1e-3). P(t) − P(0) = F × (time on) is a linear
/// invariant RK4 keeps to round-off: bound 1e-12 relative, and the report's impulse the same.
#[test]
fn rk4_keeps_the_impulse_of_a_switched_load() {
    for (step, windows, time_on) in [(1e-3, "[[0.1, 0.3], [0.7, 1.7]]", 1.2), (1e-3 / 3.0, "[[0.1, 1.1]]", 1.0)] {
        let mut s = loaded(
            &format!(
                "[[load]]\nname = \"push\"\nbody = \"hub\"\nforce = [3.0, 0.0, 0.0]\nforce_frame = \"inertial\"\non = {windows}\n"
            ),
            2.0,
            0.01,
        );
        s.settings.integrator = foldsim::simulate::Integrator::Rk4 { step };
        let (_, rows, report) = common::run(&s);
        let dp = rows.last().unwrap().momentum_in_n - rows[0].momentum_in_n;
        let want = Vec3::new(3.0 * time_on, 0.0, 0.0);
        let err = (dp - want).norm() / want.norm();
        let impulse = report.loads.expect("loads").impulse_in_n;
        let report_err = (impulse - want).norm() / want.norm();
        println!("RK4 h = {step:e}, on = {windows}: ΔP = {:.15} N·s, error {err:.2e}; report {report_err:.2e}", dp.x);
        assert!(err < 1e-12 && report_err < 1e-12, "{err:e} {report_err:e}");
    }
}

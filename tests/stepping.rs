//! A run advanced piece by piece (`Stepper`, docs/gnc.md): the same trajectory as one call,
//! and a controller outside foldsim that implements the built-in law gives the built-in's
//! trajectory.

mod common;

use foldsim::loads::LoadFrame;
use foldsim::math::Vec3;
use foldsim::scenario::Scenario;
use foldsim::simulate::Stepper;

/// The paper's three-panel case (law 2), the hub spinning, with `extra` appended; DOP853 at
/// rtol = atol = `tol`, 2 s, rows every 0.01 s.
fn three_panel(extra: &str, tol: f64) -> Scenario {
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    let text = text
        .replace("duration = 20.0", "duration = 2.0")
        .replace("output_step = 0.05", "output_step = 0.01")
        .replace("rtol = 1e-12", &format!("rtol = {tol:e}"))
        .replace("atol = 1e-12", &format!("atol = {tol:e}"));
    let text = format!("{text}\n[initial.hub]\nomega = [0.05, -0.1, 0.3]\n{extra}");
    Scenario::from_toml(&text, "stepped.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The largest difference of the hub's quaternion and every hinge's angles between two runs'
/// rows at the same times.
fn largest_difference(a: &[foldsim::observe::Observation], b: &[foldsim::observe::Observation]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            assert!((x.t - y.t).abs() < 1e-12);
            let q = x.hub_quat.iter().zip(&y.hub_quat).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
            let h = x
                .hinge_theta
                .iter()
                .zip(&y.hinge_theta)
                .map(|(p, q)| (p.as_vector() - q.as_vector()).amax())
                .fold(0.0, f64::max);
            q.max(h)
        })
        .fold(0.0, f64::max)
}

/// 1,000 calls of `advance(2 ms)` give the rows of one call to within the integrator's
/// tolerance (DOP853 at 1e-12: the global error of either is ~1e-10; bound 1e-9), and the
/// same report figures of conservation.
#[test]
fn thousand_pieces_agree_with_one_call() {
    let s = three_panel("", 1e-12);
    let (_, whole, whole_report) = common::run(&s);
    let mut stepper = Stepper::start(&s.model, &s.initial, &s.settings).unwrap();
    for _ in 0..1000 {
        stepper.advance(0.002).unwrap();
    }
    assert!((stepper.time() - 2.0).abs() < 1e-12);
    let d = largest_difference(&whole, stepper.rows());
    let r = stepper.report();
    println!(
        "1,000 pieces vs one call: largest difference {d:.2e}; steps {} vs {}; energy drift {:.2e} vs {:.2e} J",
        r.steps_accepted, whole_report.steps_accepted, r.drift.energy, whole_report.drift.energy
    );
    assert!(d < 1e-9, "{d:e}");
    assert!(r.drift.energy < 1e-8 && r.drift.angular_momentum < 1e-8);
    // Past the horizon: a clear error, not a silent stop.
    let e = stepper.advance(0.5).unwrap_err().to_string();
    assert!(e.contains("run.duration"), "{e}");
}

/// The MRP PD law written outside (here, in the test: σ from the hub's quaternion, the torque
/// set on the hub every 10 ms) gives the trajectory of the built-in law sampled at the same
/// 10 ms with an ideal torque: the same zero-order hold, so the runs differ by integration
/// error alone (DOP853 at 1e-11; bound 1e-8).
#[test]
fn outside_controller_equals_the_built_in_one() {
    let (k, p) = (30.0, 80.0);
    let built_in = three_panel(
        &format!("[control]\nlaw = \"mrp_pd\"\nk = {k:?}\np = {p:?}\ntarget = [1.0, 0.0, 0.0, 0.0]\nperiod = 0.01\n"),
        1e-11,
    );
    let (_, reference, _) = common::run(&built_in);
    let mut s = three_panel("", 1e-11);
    s.model.commandable = true;
    let mut stepper = Stepper::start(&s.model, &s.initial, &s.settings).unwrap();
    for _ in 0..200 {
        let o = stepper.current();
        let q = o.hub_quat;
        // σ = q_v / (1 + q_w), the short way round (Schaub & Junkins §3.7).
        let sign = if q[0] < 0.0 { -1.0 } else { 1.0 };
        let sigma = Vec3::new(q[1], q[2], q[3]) * (sign / (1.0 + sign * q[0]));
        let torque = -(sigma * k + o.hub_omega_in_hub * p);
        stepper.set_torque(0, torque, LoadFrame::Body).unwrap();
        stepper.advance(0.01).unwrap();
    }
    let d = largest_difference(&reference, stepper.rows());
    println!("outside MRP PD vs built-in (10 ms hold): largest difference {d:.2e}");
    assert!(d < 1e-8, "{d:e}");
    // The hub did turn under the law: the comparison is not of two idle runs.
    let spin = reference.last().unwrap().hub_omega_in_hub.norm();
    assert!(spin < 0.5 * 0.33, "{spin}");
}

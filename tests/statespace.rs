//! The state-space model for control design (`foldsim::linear::statespace`, `foldsim
//! linearize`): B's columns against the inputs' analytic effect, C's rows against central
//! differences of the run's own output columns, the `.npz` file as NumPy lays it out.

use foldsim::linear::statespace::{outputs_matching, state_space};
use foldsim::math::Vec3;
use foldsim::observe::{Observer, catalogue, row};
use foldsim::scenario::Scenario;
use foldsim::simulate::Stepper;
use foldsim::state::{BODY_STATE_LEN as B, BodyMotion};

mod common;

/// The three-panel case (law 2) with a motor on h1's fold and a torque-source control (law
/// "none": the inputs drive it), its hub turning.
fn driven() -> Scenario {
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    let text = format!(
        "{text}\n[[motor]]\nname = \"drive1\"\nhinge = \"h1\"\ndirection = \"rz\"\neffort = 0.5\n\n[control]\nlaw = \"none\"\n\n[[control.thruster]]\nname = \"jet\"\naxis = [0.0, 0.6, 0.8]\nmax_torque = 5.0\n"
    );
    let mut s = Scenario::from_toml(&text, "driven.toml").unwrap_or_else(|e| panic!("{e}"));
    s.initial.hub_omega_in_hub = Vec3::new(0.05, -0.02, 0.1);
    s.model.commandable = true;
    s
}

/// B: a force on the hub moves it by `[N B] F/m` and nothing else; a torque turns it by
/// `I⁻¹ τ` (Euler's equations: τ enters linearly); the motor's pair and the torque source
/// keep the structure's momentum (the motor's) or add `τ` about the axis (the source's):
/// `Σ m R̈` zero to 1e-12 for the pair, and `Σ (I ω̇)` against the source's axis. Exact up
/// to rounding (the inputs enter the accelerations affinely), hence 1e-12.
#[test]
fn input_columns_are_the_inputs_effect() {
    let s = driven();
    let ss = state_space(&s.model, &s.initial, &s.settings, 0.3, &[0, 2], &["w_B_x".into()]).unwrap();
    let n = s.model.bodies.len();
    assert_eq!(ss.inputs.len(), 6 * 2 + 1 + 1);
    assert_eq!(ss.inputs[12], "drive1_effort");
    assert_eq!(ss.inputs[13], "jet_torque");
    let motions: Vec<BodyMotion> = (0..n).map(|i| BodyMotion::from_state(&ss.state, i)).collect();
    let mut worst = 0.0f64;
    for (slot, &body) in [0usize, 2].iter().enumerate() {
        let (mass, inertia) = (s.model.bodies[body].mass, s.model.bodies[body].inertia_in_body);
        for a in 0..3 {
            let force = ss.b.column(6 * slot + a);
            let expected = motions[body].dcm_n_b.column(a) / mass;
            let torque = ss.b.column(6 * slot + 3 + a);
            let expected_turn = inertia.try_inverse().unwrap().column(a).into_owned();
            for k in 0..12 * n {
                let (i, r) = ((k % (6 * n)) / 6, k % 6);
                let (f, t) = if k < 6 * n || i != body {
                    (0.0, 0.0)
                } else if r < 3 {
                    (expected[r], 0.0)
                } else {
                    (0.0, expected_turn[r - 3])
                };
                worst = worst.max((force[k] - f).abs()).max((torque[k] - t).abs());
            }
        }
    }
    // The motor: an internal pair, Σ m R̈ = 0 and Σ d/dt(angular momentum) = 0 at the state's
    // rates (the pair's moment about the barycenter vanishes).
    let momentum = |col: usize| {
        (0..n).fold(Vec3::zeros(), |acc, i| {
            let v =
                Vec3::new(ss.b[(6 * n + 6 * i, col)], ss.b[(6 * n + 6 * i + 1, col)], ss.b[(6 * n + 6 * i + 2, col)]);
            acc + v * s.model.bodies[i].mass
        })
    };
    let moment = |col: usize| {
        (0..n).fold(Vec3::zeros(), |acc, i| {
            let v =
                Vec3::new(ss.b[(6 * n + 6 * i, col)], ss.b[(6 * n + 6 * i + 1, col)], ss.b[(6 * n + 6 * i + 2, col)]);
            let w = Vec3::new(
                ss.b[(6 * n + 6 * i + 3, col)],
                ss.b[(6 * n + 6 * i + 4, col)],
                ss.b[(6 * n + 6 * i + 5, col)],
            );
            let m = &motions[i];
            acc + m.r_in_n.cross(&(v * s.model.bodies[i].mass)) + m.dcm_n_b * (s.model.bodies[i].inertia_in_body * w)
        })
    };
    let pair = momentum(12).norm().max(moment(12).norm());
    let turning = moment(12 + 1).norm();
    let jet_axis = motions[0].dcm_n_b * Vec3::new(0.0, 0.6, 0.8);
    let jet = (moment(13) - jet_axis).norm().max(momentum(13).norm());
    println!(
        "B against the inputs' analytic effect {worst:.2e}; motor pair's momentum and moment {pair:.2e} (it turns p1: {turning:.2e}); torque source against its axis {jet:.2e}"
    );
    assert!(worst < 1e-12 && pair < 1e-12 && jet < 1e-12, "{worst:e} {pair:e} {jet:e}");
    assert!(turning > 0.1);
}

/// C against central differences of the run's own output columns (the observer, which knows
/// nothing of the linear model) in the minimal coordinates, at a moving, turned state of the
/// driven three-panel case, every output the linear model offers. Bound 1e-7 of the largest
/// entry (the differences' own error at h = 1e-6 is ~1e-10 here).
#[test]
fn output_rows_match_differences() {
    let s = driven();
    let all = outputs_matching(&s.model, &["*".to_string()]).unwrap();
    let ss = state_space(&s.model, &s.initial, &s.settings, 0.3, &[0], &all).unwrap();
    let n = s.model.bodies.len();
    // The run's memories and angle references at the same state (the same run).
    let mut stepper = Stepper::start(&s.model, &s.initial, &s.settings).unwrap();
    stepper.advance(0.3).unwrap();
    assert_eq!(stepper.state(), &ss.state[..]);
    let names: Vec<String> = catalogue(&s.model).into_iter().map(|c| c.name).collect();
    // The MRPs come from the run's control part of a row, which the observer alone leaves
    // out: they are taken from its quaternion (σ = q_v/(1 + q_w), the short way round).
    let index: Vec<Option<usize>> =
        all.iter().map(|o| if o.starts_with("sigma_B_") { None } else { names.iter().position(|c| c == o) }).collect();
    assert!(index.iter().zip(&all).all(|(k, o)| k.is_some() || o.starts_with("sigma_B_")));
    let values = |z: &[f64]| {
        let d = stepper.dynamics();
        let mut observer = Observer::new(&s.model, s.initial.hub_attitude, &Vec3::zeros());
        let o = observer.observe(&s.model, 0.3, z, &d.theta_refs(), &d.memories(), None);
        let r = row(&o);
        let q = if o.hub_quat[0] < 0.0 { o.hub_quat.map(|x| -x) } else { o.hub_quat };
        index
            .iter()
            .zip(&all)
            .map(|(k, name)| match k {
                Some(k) => r[*k],
                None => q[1 + ["x", "y", "z"].iter().position(|a| name.ends_with(a)).unwrap()] / (1.0 + q[0]),
            })
            .collect::<Vec<f64>>()
    };
    let at = values(&ss.state);
    let y0_error = at.iter().zip(ss.y0.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let h = 1e-6;
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for j in 0..n {
        for c in 0..12 {
            let shift = |sign: f64| {
                let mut z = ss.state.clone();
                let o = B * j;
                match c {
                    0..3 => z[o + c] += sign * h,
                    3..6 => {
                        let q = [z[o + 3], z[o + 4], z[o + 5], z[o + 6]];
                        let (half, e) = (sign * h / 2.0, c - 3);
                        let (cs, sn) = (half.cos(), half.sin());
                        let mut v = [0.0; 3];
                        v[e] = sn;
                        let r = [
                            q[0] * cs - q[1] * v[0] - q[2] * v[1] - q[3] * v[2],
                            q[1] * cs + q[0] * v[0] + q[2] * v[2] - q[3] * v[1],
                            q[2] * cs + q[0] * v[1] - q[1] * v[2] + q[3] * v[0],
                            q[3] * cs + q[0] * v[2] + q[1] * v[1] - q[2] * v[0],
                        ];
                        z[o + 3..o + 7].copy_from_slice(&r);
                    }
                    _ => z[o + 7 + (c - 6)] += sign * h,
                }
                z
            };
            let (p, m) = (values(&shift(1.0)), values(&shift(-1.0)));
            let column = if c < 6 { 6 * j + c } else { 6 * n + 6 * j + c - 6 };
            for r in 0..all.len() {
                let fd = (p[r] - m[r]) / (2.0 * h);
                worst = worst.max((fd - ss.c[(r, column)]).abs());
                scale = scale.max(fd.abs());
            }
        }
    }
    println!(
        "C against differences of the output columns: {:.2e} of the largest entry ({} outputs); y0 against the observer {y0_error:.1e}",
        worst / scale,
        all.len()
    );
    assert!(worst < 1e-7 * scale, "{worst:e} of {scale:e}");
    assert!(y0_error < 1e-12);
}

/// `foldsim linearize` writes A, B, C, D, y0, t and the names as `.npy` members of a zip,
/// each with NumPy's header and C-ordered little-endian float64 data; bad outputs and
/// bodies are refused with what is offered.
#[test]
fn linearize_command_writes_npz() {
    let dir = common::tmp("statespace", "cli");
    let out = dir.join("m.npz");
    let scenario = common::repo("examples/paper-3panel.toml");
    let run = common::foldsim()
        .args(["linearize", "-q", "--outputs", "q_B_*,h1_yaw", "-o"])
        .arg(&out)
        .arg(&scenario)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let bytes = std::fs::read(&out).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    for member in ["A.npy", "B.npy", "C.npy", "D.npy", "y0.npy", "states.npy", "inputs.npy", "outputs.npy"] {
        assert!(text.contains(member), "{member}");
    }
    assert!(
        text.contains("'shape': (48, 48)") && text.contains("'shape': (5, 48)") && text.contains("'shape': (48, 6)")
    );
    let bad = common::foldsim().args(["linearize", "--outputs", "nonsense"]).arg(&scenario).output().unwrap();
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success() && err.contains("--outputs") && err.contains("sigma_B_x"), "{err}");
    let bad = common::foldsim().args(["linearize", "--inputs", "nobody"]).arg(&scenario).output().unwrap();
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("no body 'nobody'"));
}

/// Reaction wheels: their spin momenta join the state after the bodies' coordinates. A
/// wheel's motor torque u is its momentum's rate (`ḣ = u`, B's wheel row) and turns the hub
/// by `−I_hub⁻¹ g u` (I_hub without the wheels' spin inertias, docs/gnc.md), so the total
/// angular momentum holds: `I_hub δω̇ + g ḣ = 0`; a wheel's momentum turns a spinning hub
/// by its gyroscopic reaction, `∂ω̇/∂h = −I_hub⁻¹ (ω × g)` (A's wheel column). Bound 1e-12
/// (exact up to rounding: both enter affinely).
#[test]
fn wheels_join_the_state() {
    let text = std::fs::read_to_string(common::repo("examples/paper-3panel-euler.toml")).unwrap();
    let wheels = "\n[control]\nlaw = \"none\"\n\n[[control.wheel]]\nname = \"rw1\"\naxis = [0.0, 0.6, 0.8]\ninertia = 0.05\nspeed = 30.0\n\n[[control.wheel]]\nname = \"rw2\"\naxis = [1.0, 0.0, 0.0]\ninertia = 0.05\n";
    let mut s = Scenario::from_toml(&format!("{text}{wheels}"), "wheels.toml").unwrap_or_else(|e| panic!("{e}"));
    s.initial.hub_omega_in_hub = Vec3::new(0.05, -0.02, 0.1);
    s.model.commandable = true;
    let outputs = vec!["w_B_x".to_string(), "rw1_h".to_string()];
    let ss = state_space(&s.model, &s.initial, &s.settings, 0.2, &[0], &outputs).unwrap();
    let n = s.model.bodies.len();
    assert_eq!(ss.a.nrows(), 12 * n + 2);
    assert_eq!(ss.states[12 * n], "rw1_h (N·m·s, about its axis)");
    assert_eq!(&ss.inputs[6..], ["rw1_torque", "rw2_torque"]);
    let hub = BodyMotion::from_state(&ss.state, 0);
    let omega = hub.dcm_n_b.transpose() * hub.omega_in_n;
    let inertia = s.model.bodies[0].inertia_in_body;
    let axes = [Vec3::new(0.0, 0.6, 0.8), Vec3::new(1.0, 0.0, 0.0)];
    let mut worst = 0.0f64;
    for (k, g) in axes.iter().enumerate() {
        let turn = Vec3::new(ss.b[(6 * n + 3, 6 + k)], ss.b[(6 * n + 4, 6 + k)], ss.b[(6 * n + 5, 6 + k)]);
        worst = worst.max((inertia * turn + g * ss.b[(12 * n + k, 6 + k)]).norm());
        worst = worst.max((ss.b[(12 * n + k, 6 + k)] - 1.0).abs());
        let gyro =
            Vec3::new(ss.a[(6 * n + 3, 12 * n + k)], ss.a[(6 * n + 4, 12 * n + k)], ss.a[(6 * n + 5, 12 * n + k)]);
        worst = worst.max((inertia * gyro + omega.cross(g)).norm());
    }
    // The output rw1_h reads the state's wheel momentum.
    assert_eq!(ss.c[(1, 12 * n)], 1.0);
    assert!((ss.y0[1] - ss.state[foldsim::state::wheel_index(&s.model)]).abs() == 0.0);
    println!("wheels: ḣ = u, I δω̇ + g ḣ = 0 and the gyroscopic column to {worst:.2e}");
    assert!(worst < 1e-12, "{worst:e}");
}

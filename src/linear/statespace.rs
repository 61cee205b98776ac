//! The state-space model for control design (docs/linear.md): `ẋ = A x + B u`, `y = C x + D u`
//! about a state of a run, with x the minimal coordinates of [`super::Linearization`], u the
//! inputs a controller drives (forces and torques on chosen bodies, the motors' efforts, the
//! control's wheels' motor torques and torque sources), and with reaction wheels their spin
//! momenta after the bodies' coordinates in x, y the output columns the user names (deviations from their
//! values at the state, which come with the model as `y0`).
//!
//! The model is the open-loop plant: motors' drives and the control's law are replaced by
//! their inputs (at zero), so A has no servo or controller in it.
//!
//! - **A** from the exact Jacobian ([`super::Linearization::state_matrix`]).
//! - **B**: each input enters the accelerations affinely (a force or torque on a body, a
//!   motor's equal and opposite pair, a torque source on the hub), so its column is the
//!   accelerations with that input at one unit less those with every input at zero: exact,
//!   not a difference quotient (no truncation; the check against the analytic `I⁻¹` and
//!   `1/m` columns is in tests/linear.rs).
//! - **C**: analytic rows for every output offered (quaternions through `∂q/∂δφ`, MRPs by the
//!   chain rule, hinge angles through `δθ = B(θ)⁻¹ δα` with `δα = [A c] δφ_c − [A p] δφ_p`
//!   the small rotation of A relative to A0, docs/model.md §1), checked against central
//!   differences of the run's own output columns. **D** is zero: no output offered reads an
//!   input.

use super::{Linearization, quaternion_tangent};
use crate::dynamics::Dynamics;
use crate::kinematics::{InitialConditions, hinge_kinematics};
use crate::loads::LoadFrame;
use crate::math::{EulerTrig, Mat3, Vec3, skew};
use crate::model::Model;
use crate::simulate::{RunSettings, Stepper};
use crate::state::{BODY_STATE_LEN as B, BodyMotion, OMEGA, VEL};
use nalgebra::{DMatrix, DVector, SMatrix};

/// A linear time-invariant model with named states, inputs and outputs.
#[derive(Clone, Debug)]
pub struct StateSpace {
    /// State matrix, (12n + w) × (12n + w) (1/s and 1/s²; docs/linear.md for the
    /// coordinates; w reaction wheels' momenta last).
    pub a: DMatrix<f64>,
    /// Input matrix, (12n + w) × m.
    pub b: DMatrix<f64>,
    /// Output matrix, p × (12n + w).
    pub c: DMatrix<f64>,
    /// Feedthrough, p × m (zero).
    pub d: DMatrix<f64>,
    /// State names with units.
    pub states: Vec<String>,
    /// Input names (units in docs/linear.md).
    pub inputs: Vec<String>,
    /// Output names: output columns of docs/outputs.md.
    pub outputs: Vec<String>,
    /// The outputs' values at the state (y is the deviation from these).
    pub y0: DVector<f64>,
    /// The time of the state, s.
    pub t: f64,
    /// The state linearised about (crate::state's layout: per body R, q, Ṙ, ω).
    pub state: Vec<f64>,
    /// The largest acceleration at the state with every input at zero (m/s², rad/s²): zero
    /// at an equilibrium of the open-loop plant.
    pub residual: f64,
}

/// The outputs offered, as column patterns (docs/outputs.md): `<b>` a body's name, `<h>` a
/// hinge's.
pub const OUTPUTS_OFFERED: &str = "q_B_w/_x/_y/_z, sigma_B_x/_y/_z, w_B_x/_y/_z, R_B_x/_y/_z, <b>_q_w/_x/_y/_z, <b>_w_x/_y/_z, <b>_R_x/_y/_z, <b>_v_x/_y/_z, <h>_yaw/_pitch/_roll, <h>_wrel_x/_y/_z, <wheel>_h";

/// One output's row of C (12n) and its value at the state.
fn output_row(model: &Model, y: &[f64], motions: &[BodyMotion], name: &str) -> Result<(DVector<f64>, f64), String> {
    let n = model.bodies.len();
    let mut row = DVector::zeros(12 * n);
    let axis = |s: &str| match s {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    };
    let body_index = |b: &str| {
        if b == "B" { Some(0) } else { model.bodies.iter().position(|x| x.name == b) }
    };
    let unknown = || {
        format!("output '{name}': not an output of the linear model; choose from {OUTPUTS_OFFERED} (docs/linear.md)")
    };
    // Body outputs: `<b>_<kind>_<axis>` or the hub's `<kind>_B_<axis>`.
    let parts: Vec<&str> = name.rsplitn(3, '_').collect();
    if parts.len() == 3 {
        let (comp, kind, who) = (parts[0], parts[1], parts[2]);
        let hub_form = |k: &str| {
            let (kind_hub, b) = (who, kind);
            (kind_hub == k && b == "B").then_some(0)
        };
        // Quaternion: `q_B_w` (hub) or `<b>_q_w`.
        let body = hub_form("q").or_else(|| (kind == "q").then(|| body_index(who)).flatten());
        if let Some(i) = body {
            let k = match comp {
                "w" => 0,
                c => 1 + axis(c).ok_or_else(unknown)?,
            };
            let q = &y[B * i + crate::state::QUAT..B * i + crate::state::QUAT + 4];
            let tangent = quaternion_tangent(q);
            for c in 0..3 {
                row[6 * i + 3 + c] = tangent[(k, c)];
            }
            return Ok((row, q[k]));
        }
        if hub_form("sigma").is_some() {
            let a = axis(comp).ok_or_else(unknown)?;
            let q = &y[crate::state::QUAT..crate::state::QUAT + 4];
            // σ = q_v/(1 + q_w), the short way round (q → −q for q_w < 0): Schaub & Junkins
            // eq. 3.154; ∂σ/∂q by the quotient rule, then ∂q/∂δφ.
            let sign = if q[0] < 0.0 { -1.0 } else { 1.0 };
            let (w, v) = (sign * q[0], sign * q[1 + a]);
            let mut d_sigma_d_q = SMatrix::<f64, 1, 4>::zeros();
            d_sigma_d_q[0] = -v / (1.0 + w).powi(2) * sign;
            d_sigma_d_q[1 + a] = sign / (1.0 + w);
            let d = d_sigma_d_q * quaternion_tangent(q);
            for c in 0..3 {
                row[3 + c] = d[c];
            }
            return Ok((row, v / (1.0 + w)));
        }
        let a = axis(comp);
        let linear = |i: usize, offset: usize, value: f64| -> Result<(DVector<f64>, f64), String> {
            let mut row = DVector::zeros(12 * n);
            row[offset + 6 * i + a.ok_or_else(unknown)?] = 1.0;
            Ok((row, value))
        };
        let hub_kind = hub_form("w").map(|_| "w").or(hub_form("R").map(|_| "R"));
        let (kind, body) = match hub_kind {
            Some(k) => (k, Some(0)),
            None => (kind, body_index(who)),
        };
        if let (Some(i), Some(c)) = (body, a) {
            let m = &motions[i];
            match kind {
                "w" => return linear(i, 6 * n + 3, m.omega_in_n.dot(&m.dcm_n_b.column(c))),
                "R" => return linear(i, 0, m.r_in_n[c]),
                "v" => return linear(i, 6 * n, m.v_in_n[c]),
                _ => {}
            }
        }
    }
    // Hinge outputs: `<h>_yaw`, `<h>_wrel_x`, ….
    for h in &model.hinges {
        let Some(rest) = name.strip_prefix(h.name.as_str()).and_then(|r| r.strip_prefix('_')) else { continue };
        let (p, c) = (h.parent, h.child);
        let k = hinge_kinematics(h, &motions[p], &motions[c], &crate::math::Euler321::default());
        let dcm_n_a = motions[c].dcm_n_b * h.dcm_child_a;
        let (a_c, a_p) = (dcm_n_a.transpose() * motions[c].dcm_n_b, dcm_n_a.transpose() * motions[p].dcm_n_b);
        let angle = match rest {
            "yaw" => Some(0),
            "pitch" => Some(1),
            "roll" => Some(2),
            _ => None,
        };
        if let Some(j) = angle {
            // δθ = B(θ)⁻¹ (A_c δφ_c − A_p δφ_p): the rates' law applied to the small rotation.
            let trig = EulerTrig::from_dcm(&k.state.dcm_a_a0);
            let b_inv = Mat3::from_columns(&[0, 1, 2].map(|e| trig.rates_from_omega(&Vec3::ith(e, 1.0))));
            let (dc, dp) = (b_inv * a_c, -(b_inv * a_p));
            for e in 0..3 {
                row[6 * c + 3 + e] += dc[(j, e)];
                row[6 * p + 3 + e] += dp[(j, e)];
            }
            let theta = [k.state.theta.yaw, k.state.theta.pitch, k.state.theta.roll];
            return Ok((row, theta[j]));
        }
        if let Some(j) = rest.strip_prefix("wrel_").and_then(axis) {
            // ω_rel = A_c ω_c − A_c [c p] ω_p (body components): its variation in δω and,
            // through [c p], in δφ (zero at rest).
            let c_p = motions[c].dcm_n_b.transpose() * motions[p].dcm_n_b;
            let (w_c, w_p) = (
                motions[c].dcm_n_b.transpose() * motions[c].omega_in_n,
                motions[p].dcm_n_b.transpose() * motions[p].omega_in_n,
            );
            let d_phi_c = -(a_c * skew(&(c_p * w_p)));
            let d_phi_p = a_c * c_p * skew(&w_p);
            let d_w_p = -(a_c * c_p);
            for e in 0..3 {
                row[6 * n + 6 * c + 3 + e] += a_c[(j, e)];
                row[6 * n + 6 * p + 3 + e] += d_w_p[(j, e)];
                row[6 * c + 3 + e] += d_phi_c[(j, e)];
                row[6 * p + 3 + e] += d_phi_p[(j, e)];
            }
            let value = (a_c * w_c - a_c * c_p * w_p)[j];
            return Ok((row, value));
        }
    }
    Err(unknown())
}

/// What the inputs of a state-space model are: forces and torques on bodies (by index, in
/// their own frames at their centres of mass), every motor, every torque source
/// ([`crate::model::inputs::inputs`], the names every face uses).
fn input_names(model: &Model, bodies: &[usize]) -> Vec<String> {
    crate::model::inputs::inputs(model, bodies).into_iter().map(|i| i.name).collect()
}

/// Sets input `k` (of [`input_names`]' order) to `value`, every other to zero.
fn set_inputs(d: &Dynamics<'_>, model: &Model, bodies: &[usize], k: Option<usize>, value: f64) -> Result<(), String> {
    let unit = |j: usize| if k == Some(j) { value } else { 0.0 };
    for (slot, &i) in bodies.iter().enumerate() {
        let o = 6 * slot;
        d.command_force(i, Vec3::new(unit(o), unit(o + 1), unit(o + 2)), Vec3::zeros(), LoadFrame::Body)?;
        d.command_torque(i, Vec3::new(unit(o + 3), unit(o + 4), unit(o + 5)), LoadFrame::Body)?;
    }
    let base = 6 * bodies.len();
    for m in 0..model.motors.len() {
        d.command_motor(m, Some(unit(base + m)))?;
    }
    if let Some(c) = &model.control {
        let base = base + model.motors.len();
        d.command_actuators(Some((0..c.actuator_count()).map(|j| unit(base + j)).collect()))?;
    }
    Ok(())
}

/// The bodies' accelerations `(R̈ in N, ω̇ in body)` per body, 6n.
fn accelerations(d: &Dynamics<'_>, y: &[f64]) -> DVector<f64> {
    let mut dydt = vec![0.0; y.len()];
    d.rhs(y, &mut dydt);
    let n = d.model().bodies.len();
    DVector::from_fn(6 * n, |k, _| {
        let (i, r) = (k / 6, k % 6);
        if r < 3 { dydt[B * i + VEL + r] } else { dydt[B * i + OMEGA + r - 3] }
    })
}

/// The state-space model of `model` (made [`Model::commandable`]) at time `at` (s) of its run from `ic` (the design state
/// or any other), with force and torque inputs on `input_bodies` (indices; the hub is 0) and
/// the outputs `outputs` (column names, [`OUTPUTS_OFFERED`]).
pub fn state_space(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    at: f64,
    input_bodies: &[usize],
    outputs: &[String],
) -> Result<StateSpace, String> {
    if let Some(&i) = input_bodies.iter().find(|&&i| i >= model.bodies.len()) {
        return Err(format!("input body {i}: the model has {} bodies", model.bodies.len()));
    }
    if !model.commandable {
        return Err(
            "the state-space model needs a model made to take commands: set Model::commandable before building it"
                .into(),
        );
    }
    let mut stepper = Stepper::start(model, ic, settings).map_err(|e| e.to_string())?;
    if at > 0.0 {
        stepper.advance(at).map_err(|e| e.to_string())?;
    }
    let y = stepper.state().to_vec();
    let d = stepper.dynamics();
    set_inputs(d, model, input_bodies, None, 0.0)?;
    let lin = Linearization::at(d, &y, Vec3::zeros())?;
    let n = model.bodies.len();
    let wheels = model.wheel_count();
    let size = 12 * n + wheels;
    // The bodies' part from the exact Jacobian, the wheels' momenta held; then the wheels'
    // columns: the hub's acceleration per unit of a wheel's momentum (its gyroscopic
    // reaction −ω × g h enters affinely: exact by superposition), and their rows `ḣ = u`.
    let mut a = DMatrix::zeros(size, size);
    a.view_mut((0, 0), (12 * n, 12 * n)).copy_from(&lin.state_matrix());
    let base = accelerations(d, &y);
    let w0 = crate::state::wheel_index(model);
    for k in 0..wheels {
        let mut z = y.clone();
        z[w0 + k] += 1.0;
        let column = accelerations(d, &z) - &base;
        a.view_mut((6 * n, 12 * n + k), (6 * n, 1)).copy_from(&column);
    }
    let inputs = input_names(model, input_bodies);
    let mut b = DMatrix::zeros(size, inputs.len());
    let first_actuator = 6 * input_bodies.len() + model.motors.len();
    for k in 0..inputs.len() {
        set_inputs(d, model, input_bodies, Some(k), 1.0)?;
        let column = accelerations(d, &y) - &base;
        b.view_mut((6 * n, k), (6 * n, 1)).copy_from(&column);
        // A wheel's motor torque is its momentum's rate (docs/gnc.md).
        if (first_actuator..first_actuator + wheels).contains(&k) {
            b[(12 * n + k - first_actuator, k)] = 1.0;
        }
    }
    set_inputs(d, model, input_bodies, None, 0.0)?;
    let motions: Vec<BodyMotion> = (0..n).map(|i| BodyMotion::from_state(&y, i)).collect();
    let residual = base.amax();
    let mut c = DMatrix::zeros(outputs.len(), size);
    let mut y0 = DVector::zeros(outputs.len());
    let wheel_names: Vec<&str> =
        model.control.as_ref().map_or_else(Vec::new, |c| c.wheels().iter().map(|w| w.name.as_str()).collect());
    for (r, name) in outputs.iter().enumerate() {
        if let Some(k) = wheel_names.iter().position(|w| name.strip_suffix("_h") == Some(*w)) {
            c[(r, 12 * n + k)] = 1.0;
            y0[r] = y[w0 + k];
            continue;
        }
        let (row, value) = output_row(model, &y, &motions, name)?;
        c.view_mut((r, 0), (1, 12 * n)).copy_from(&row.transpose());
        y0[r] = value;
    }
    let mut states = Vec::with_capacity(12 * n);
    for (prefix, frame) in [(["dR", "dphi"], ["m, N", "rad, body"]), (["dv", "dw"], ["m/s, N", "rad/s, body"])] {
        for body in &model.bodies {
            for (p, f) in prefix.iter().zip(frame) {
                states.extend(["x", "y", "z"].map(|a| format!("{}_{p}_{a} ({f})", body.name)));
            }
        }
    }
    states.extend(wheel_names.iter().map(|w| format!("{w}_h (N·m·s, about its axis)")));
    Ok(StateSpace {
        d: DMatrix::zeros(outputs.len(), inputs.len()),
        a,
        b,
        c,
        states,
        inputs,
        outputs: outputs.to_vec(),
        y0,
        t: stepper.time(),
        residual,
        state: y,
    })
}

/// The default outputs: the hub's MRPs and rates.
pub fn default_outputs() -> Vec<String> {
    ["sigma_B_x", "sigma_B_y", "sigma_B_z", "w_B_x", "w_B_y", "w_B_z"].map(String::from).to_vec()
}

/// Every output name a pattern list (commas; `*` any run of characters, as `--columns`)
/// matches among the outputs offered for `model`, in the order offered.
pub fn outputs_matching(model: &Model, patterns: &[String]) -> Result<Vec<String>, String> {
    let mut offered: Vec<String> = Vec::new();
    let xyz = ["x", "y", "z"];
    offered.extend(["w", "x", "y", "z"].map(|a| format!("q_B_{a}")));
    offered.extend(xyz.map(|a| format!("sigma_B_{a}")));
    offered.extend(xyz.map(|a| format!("w_B_{a}")));
    offered.extend(xyz.map(|a| format!("R_B_{a}")));
    for b in &model.bodies {
        offered.extend(["w", "x", "y", "z"].map(|a| format!("{}_q_{a}", b.name)));
        for k in ["w", "R", "v"] {
            offered.extend(xyz.map(|a| format!("{}_{k}_{a}", b.name)));
        }
    }
    if let Some(c) = &model.control {
        offered.extend(c.wheels().iter().map(|w| format!("{}_h", w.name)));
    }
    for h in &model.hinges {
        offered.extend(["yaw", "pitch", "roll"].map(|a| format!("{}_{a}", h.name)));
        offered.extend(xyz.map(|a| format!("{}_wrel_{a}", h.name)));
    }
    let mut out = Vec::new();
    for p in patterns {
        let found: Vec<&String> = offered.iter().filter(|o| crate::observe::glob(p, o)).collect();
        if found.is_empty() {
            return Err(format!(
                "output '{p}' matches nothing the linear model offers: {OUTPUTS_OFFERED} (docs/linear.md)"
            ));
        }
        for f in found {
            if !out.contains(f) {
                out.push(f.clone());
            }
        }
    }
    Ok(out)
}

//! The `[[motor]]` tables and the `[control]` table (docs/gnc.md): hinge motors, and the
//! hub's attitude or spin control with its wheels or torque sources, each value checked and
//! located.

use super::error::{Ctx, ScenarioError};
use super::values::Exact;
use crate::law::directional::DIRECTION_NAMES;
use crate::loads::Profile;
use crate::loads::control::{Actuators, Control, Law, Thruster, Wheel};
use crate::loads::motor::{Drive, Motor};
use crate::math::Vec3;
use crate::model::Model;
use crate::simulate::settings::{MAX_DEFAULT_STEP_BUDGET, MIN_STEP_OF_DURATION};
use serde::Deserialize;
use toml::Spanned;

/// One `[[motor]]` table as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMotor {
    name: Spanned<String>,
    hinge: Spanned<String>,
    direction: Spanned<String>,
    effort: Option<Spanned<toml::Value>>,
    target: Option<Spanned<toml::Value>>,
    target_deg: Option<Spanned<toml::Value>>,
    times: Option<Spanned<Vec<f64>>>,
    kp: Option<Spanned<f64>>,
    kd: Option<Spanned<f64>>,
    limit: Option<Spanned<f64>>,
    on: Option<Spanned<Vec<Exact<f64, 2>>>>,
}

/// `[control]` as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawControl {
    law: Spanned<String>,
    k: Option<Spanned<f64>>,
    p: Option<Spanned<f64>>,
    target: Option<Spanned<toml::Value>>,
    spin_axis: Option<Spanned<Exact<f64, 3>>>,
    spin_rate: Option<Spanned<f64>>,
    spin_rate_rpm: Option<Spanned<f64>>,
    period: Option<Spanned<f64>>,
    max_torque: Option<Spanned<f64>>,
    #[serde(rename = "wheel", default)]
    wheels: Vec<RawWheel>,
    #[serde(rename = "thruster", default)]
    thrusters: Vec<RawThruster>,
}

/// One `[[control.wheel]]` table as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWheel {
    name: Spanned<String>,
    axis: Spanned<Exact<f64, 3>>,
    inertia: Spanned<f64>,
    max_torque: Option<Spanned<f64>>,
    max_momentum: Option<Spanned<f64>>,
    speed: Option<Spanned<f64>>,
    speed_rpm: Option<Spanned<f64>>,
}

/// One `[[control.thruster]]` table as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawThruster {
    name: Spanned<String>,
    axis: Spanned<Exact<f64, 3>>,
    max_torque: Option<Spanned<f64>>,
}

/// A positive limit, or none (infinite) when absent.
fn limit(ctx: &Ctx<'_>, v: &Option<Spanned<f64>>, key: &str, unit: &str) -> Result<f64, ScenarioError> {
    v.as_ref().map_or(Ok(f64::INFINITY), |v| super::values::positive(ctx, v, key, unit))
}

/// A unit axis from a nonzero vector.
fn axis(ctx: &Ctx<'_>, v: &Spanned<Exact<f64, 3>>, what: &str) -> Result<Vec3, ScenarioError> {
    let a = Vec3::from(*v.get_ref());
    if !(a.norm() > 0.0 && a.norm().is_finite()) {
        return Err(ctx.span(v, format!("{what}: 'axis' must be a nonzero vector [x, y, z] in the hub's frame")));
    }
    Ok(a.normalize())
}

/// A scalar profile: a number, or with `times` one number per time.
fn scalar_profile(
    ctx: &Ctx<'_>,
    value: &Spanned<toml::Value>,
    times: &Option<Spanned<Vec<f64>>>,
    scale: f64,
    message: &str,
) -> Result<Profile<f64>, ScenarioError> {
    let bad = || ctx.span(value, message.to_string());
    match times {
        None => {
            let x = super::values::number(value.get_ref()).filter(|x| x.is_finite()).ok_or_else(bad)?;
            Ok(Profile::Constant(x * scale))
        }
        Some(t) => {
            let v = t.get_ref();
            if v.is_empty() || v.iter().any(|x| !x.is_finite()) || v.windows(2).any(|w| w[1] <= w[0]) {
                return Err(ctx.span(t, "'times' must be finite and strictly increasing, s"));
            }
            let values: Option<Vec<f64>> = value
                .get_ref()
                .as_array()
                .map(|a| {
                    a.iter().map(|x| super::values::number(x).filter(|x| x.is_finite()).map(|x| x * scale)).collect()
                })
                .unwrap_or(None);
            let values = values.filter(|x| x.len() == v.len()).ok_or_else(bad)?;
            Ok(Profile::Table { times: v.clone(), values })
        }
    }
}

/// The motors of `raw`, added to `model`.
pub(super) fn add_motors(
    ctx: &Ctx<'_>,
    raw: &[RawMotor],
    model: &mut Model,
    duration: f64,
) -> Result<(), ScenarioError> {
    let mut names = std::collections::HashSet::new();
    for r in raw {
        super::values::check_name(ctx, &r.name, "motor")?;
        let name = r.name.get_ref().clone();
        let what = format!("motor '{name}'");
        if !names.insert(name.clone()) {
            return Err(ctx.span(&r.name, format!("a second motor named '{name}': motor names must be unique")));
        }
        let hinge = model.hinge_index(r.hinge.get_ref()).ok_or_else(|| {
            let list = model.hinges.iter().map(|h| format!("'{}'", h.name)).collect::<Vec<_>>().join(", ");
            ctx.span(&r.hinge, format!("{what}: no hinge '{}' (the hinges are {list})", r.hinge.get_ref()))
        })?;
        let direction = DIRECTION_NAMES.iter().position(|d| *d == r.direction.get_ref()).ok_or_else(|| {
            ctx.span(
                &r.direction,
                format!(
                    "{what}: 'direction' is one of \"x\", \"y\", \"z\" (a force along δ's A0 axis, N) or \"rx\", \"ry\", \"rz\" (a torque on roll, pitch or yaw, N·m), got \"{}\"",
                    r.direction.get_ref()
                ),
            )
        })?;
        let (unit, per) = if direction < 3 { ("N", "m") } else { ("N·m", "rad") };
        let drive = match (&r.effort, &r.target, &r.target_deg) {
            (Some(effort), None, None) => {
                for (k, v) in [("kp", &r.kp), ("kd", &r.kd), ("limit", &r.limit)] {
                    if let Some(v) = v {
                        return Err(
                            ctx.span(v, format!("{what}: '{k}' belongs to a servo ('target'), not to an 'effort'"))
                        );
                    }
                }
                let message = format!("{what}: 'effort' is a number in {unit} (or with 'times', one number per time)");
                Drive::Effort(scalar_profile(ctx, effort, &r.times, 1.0, &message)?)
            }
            (None, target, target_deg) if target.is_some() != target_deg.is_some() => {
                let (value, scale) = match (target, target_deg) {
                    (Some(t), _) => (t, 1.0),
                    (_, Some(t)) if direction >= 3 => (t, 1f64.to_radians()),
                    (_, Some(t)) => {
                        return Err(ctx.span(t, format!("{what}: 'target_deg' is for angles; give 'target' in m")));
                    }
                    _ => unreachable!("one of them is given"),
                };
                let message = format!("{what}: 'target' is a number in {per} (or with 'times', one number per time)");
                let target = scalar_profile(ctx, value, &r.times, scale, &message)?;
                let gain = |v: &Option<Spanned<f64>>, key: &str, unit: &str| match v {
                    Some(v) if *v.get_ref() >= 0.0 && v.get_ref().is_finite() => Ok(*v.get_ref()),
                    Some(v) => Err(ctx.span(v, format!("{what}: '{key}' must be a finite number ≥ 0, {unit}"))),
                    None => Err(ctx.span(&r.name, format!("{what}: a servo needs '{key}' ({unit})"))),
                };
                Drive::Servo {
                    target,
                    kp: gain(&r.kp, "kp", &format!("{unit}/{per}"))?,
                    kd: gain(&r.kd, "kd", &format!("{unit}·s/{per}"))?,
                    limit: limit(ctx, &r.limit, "limit", unit)?,
                }
            }
            _ => {
                return Err(ctx.span(
                    &r.name,
                    format!("{what}: give either 'effort' ({unit}) or a servo's 'target' ({per}, or 'target_deg') with 'kp' and 'kd'"),
                ));
            }
        };
        model.motors.push(Motor {
            name,
            hinge,
            direction,
            drive,
            windows: super::values::windows(ctx, &r.on, &what, duration)?,
        });
    }
    Ok(())
}

/// The hub's control of `raw`, added to `model` (the hub's inertia less the wheels' spin
/// inertias).
pub(super) fn add_control(
    ctx: &Ctx<'_>,
    raw: &Spanned<RawControl>,
    model: &mut Model,
    duration: f64,
) -> Result<(), ScenarioError> {
    let r = raw.get_ref();
    let p = || match &r.p {
        Some(p) => super::values::positive(ctx, p, "control.p", "N·m·s"),
        None => Err(ctx.span(&r.law, format!("control: law \"{}\" needs 'p' (N·m·s)", r.law.get_ref()))),
    };
    let gain_k = || match &r.k {
        Some(k) => super::values::positive(ctx, k, "control.k", "N·m"),
        None => Err(ctx.span(&r.law, format!("control: law \"{}\" needs 'k' (N·m)", r.law.get_ref()))),
    };
    let target = match &r.target {
        None => None,
        Some(t) => {
            let q: Option<Vec<f64>> =
                t.get_ref().as_array().map(|a| a.iter().filter_map(super::values::number).collect());
            match q {
                Some(q) if q.len() == 4 && q.iter().all(|x| x.is_finite()) => {
                    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if (n - 1.0).abs() > 1e-6 {
                        return Err(
                            ctx.span(t, format!("control: 'target' must be a unit quaternion (its norm is {n})"))
                        );
                    }
                    Some([q[0] / n, q[1] / n, q[2] / n, q[3] / n])
                }
                _ => {
                    return Err(ctx.span(
                        t,
                        "control: 'target' is the attitude quaternion [w, x, y, z], scalar first, N to the target frame",
                    ));
                }
            }
        }
    };
    let needs_target = || {
        target.ok_or_else(|| {
            ctx.span(
                &r.law,
                "control: an attitude law needs 'target', the quaternion [w, x, y, z] to hold (N to target)",
            )
        })
    };
    let (law, target) = match r.law.get_ref().as_str() {
        "mrp_pd" => (Law::MrpPd { k: gain_k()?, p: p()? }, needs_target()?),
        "quaternion_pd" => (Law::QuaternionPd { k: gain_k()?, p: p()? }, needs_target()?),
        "none" => {
            for (key, v) in [("k", r.k.as_ref().map(|v| v.span())), ("p", r.p.as_ref().map(|v| v.span()))] {
                if let Some(span) = v {
                    return Err(ctx.at(Some(span), format!("control: law \"none\" has no gains ('{key}'): its actuators act on commands from a stepped run only")));
                }
            }
            if let Some(t) = &r.target {
                return Err(ctx.span(t, "control: law \"none\" has no target"));
            }
            (Law::None, [1.0, 0.0, 0.0, 0.0])
        }
        "spin_hold" | "rate_damping" => {
            let damping = r.law.get_ref() == "rate_damping";
            let rate = match (&r.spin_rate, &r.spin_rate_rpm) {
                (Some(w), None) => *w.get_ref(),
                (None, Some(w)) => w.get_ref() * std::f64::consts::PI / 30.0,
                (None, None) if damping => 0.0,
                _ => {
                    return Err(
                        ctx.span(&r.law, "control: spin_hold needs one of 'spin_rate' (rad/s) and 'spin_rate_rpm'")
                    );
                }
            };
            if damping && rate != 0.0 {
                return Err(ctx.span(
                    &r.law,
                    "control: rate_damping drives every rate to zero; for a spin give law = \"spin_hold\"",
                ));
            }
            if let Some(t) = &r.target {
                return Err(ctx.span(
                    t,
                    format!("control: law \"{}\" holds rates, not an attitude: 'target' belongs to \"mrp_pd\" or \"quaternion_pd\"", r.law.get_ref()),
                ));
            }
            let axis = match &r.spin_axis {
                Some(a) if damping => {
                    return Err(ctx.span(
                        a,
                        "control: rate_damping drives every rate to zero about every axis: 'spin_axis' belongs to \"spin_hold\"",
                    ));
                }
                Some(a) => axis(ctx, a, "control")?,
                None if damping => Vec3::z(),
                None => {
                    return Err(ctx.span(&r.law, "control: spin_hold needs 'spin_axis', [x, y, z] in the hub's frame"));
                }
            };
            if let Some(k) = &r.k {
                return Err(ctx.span(k, "control: 'k' is an attitude gain; spin_hold and rate_damping take 'p' only"));
            }
            (Law::SpinHold { axis_in_hub: axis, rate, p: p()? }, [1.0, 0.0, 0.0, 0.0])
        }
        other => {
            return Err(ctx.span(
                &r.law,
                format!("control: 'law' is \"mrp_pd\", \"quaternion_pd\", \"spin_hold\", \"rate_damping\" or \"none\", got \"{other}\""),
            ));
        }
    };
    let mut names = std::collections::HashSet::new();
    let mut unique = |n: &Spanned<String>| {
        super::values::check_name(ctx, n, "actuator")?;
        if names.insert(n.get_ref().clone()) {
            Ok(n.get_ref().clone())
        } else {
            Err(ctx.span(n, format!("a second actuator named '{}': names must be unique", n.get_ref())))
        }
    };
    let actuators = match (r.wheels.is_empty(), r.thrusters.is_empty()) {
        (false, false) => {
            return Err(ctx.span(
                raw,
                "control: give wheels or thrusters, not both (momentum management with thrusters is not supported)",
            ));
        }
        (false, true) => {
            let mut wheels = Vec::new();
            for w in &r.wheels {
                let name = unique(&w.name)?;
                let what = format!("wheel '{name}'");
                let speed = match (&w.speed, &w.speed_rpm) {
                    (Some(s), None) => *s.get_ref(),
                    (None, Some(s)) => s.get_ref() * std::f64::consts::PI / 30.0,
                    (None, None) => 0.0,
                    (Some(s), Some(_)) => {
                        return Err(ctx.span(s, format!("{what}: give one of 'speed' and 'speed_rpm'")));
                    }
                };
                wheels.push(Wheel {
                    axis_in_hub: axis(ctx, &w.axis, &what)?,
                    inertia: super::values::positive(ctx, &w.inertia, "inertia", "kg·m²")?,
                    max_torque: limit(ctx, &w.max_torque, "max_torque", "N·m")?,
                    max_momentum: limit(ctx, &w.max_momentum, "max_momentum", "N·m·s")?,
                    speed,
                    name,
                });
            }
            Actuators::Wheels(wheels)
        }
        (true, false) => {
            let mut thrusters = Vec::new();
            for t in &r.thrusters {
                let name = unique(&t.name)?;
                let what = format!("thruster '{name}'");
                thrusters.push(Thruster {
                    axis_in_hub: axis(ctx, &t.axis, &what)?,
                    max_torque: limit(ctx, &t.max_torque, "max_torque", "N·m")?,
                    name,
                });
            }
            Actuators::Thrusters(thrusters)
        }
        (true, true) => {
            // An ideal torque about the hub's axes.
            let max_torque = limit(ctx, &r.max_torque, "control.max_torque", "N·m")?;
            Actuators::Thrusters(
                ["torque_x", "torque_y", "torque_z"]
                    .iter()
                    .zip([Vec3::x(), Vec3::y(), Vec3::z()])
                    .map(|(n, a)| Thruster { name: n.to_string(), axis_in_hub: a, max_torque })
                    .collect(),
            )
        }
    };
    if let (Some(m), false) = (&r.max_torque, r.wheels.is_empty() && r.thrusters.is_empty()) {
        return Err(
            ctx.span(m, "control: 'max_torque' is the ideal torque's limit; give wheels and thrusters their own")
        );
    }
    let period = match &r.period {
        Some(v) => {
            let period = super::values::positive(ctx, v, "control.period", "s")?;
            // Bounded as run.step is: each sample ends a step.
            let samples = duration / period;
            if period < MIN_STEP_OF_DURATION * duration || samples > MAX_DEFAULT_STEP_BUDGET {
                return Err(ctx.span(
                    v,
                    format!(
                        "'control.period' = {period:e} s would take {samples:.3e} samples over run.duration = {duration} s, each ending a step; give a period of at least {:.3e} s ({MAX_DEFAULT_STEP_BUDGET:e} samples)",
                        (duration / MAX_DEFAULT_STEP_BUDGET).max(MIN_STEP_OF_DURATION * duration)
                    ),
                ));
            }
            Some(period)
        }
        None => None,
    };
    let control = Control::new(law, target, actuators, period).map_err(|m| ctx.span(raw, format!("control: {m}")))?;
    model.bodies[0].remove_spin_inertia(&control.wheel_spin_inertia()).map_err(|m| ctx.span(raw, m))?;
    model.control = Some(control);
    Ok(())
}

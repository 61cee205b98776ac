//! Reading values: angles in radians or degrees, vectors, matrices, positive numbers, and
//! the rejection of non-finite numbers anywhere in a file.

use super::error::{Ctx, ScenarioError};
use crate::math::{Euler321, Mat3, Vec3};
use toml::Spanned;

/// One angle from its rad or `_deg` key; both given is an error.
pub(super) fn one_angle(key: &str, rad: Option<f64>, deg: Option<f64>) -> Result<Option<f64>, String> {
    let angle = match (rad, deg) {
        (Some(_), Some(_)) => return Err(format!("both '{key}' and '{key}_deg' are given; give one")),
        (Some(r), None) => r,
        (None, Some(d)) => d.to_radians(),
        (None, None) => return Ok(None),
    };
    // Beyond a thousand turns f64 keeps too few digits of the angle's fraction of a turn for
    // the angle bookkeeping (and no structure is stowed a thousand turns round).
    if angle.abs() > MAX_ANGLE {
        return Err(format!(
            "'{key}' is {angle:e} rad ({:e}°): angles are limited to ±1000 turns; give it modulo 360°",
            angle.to_degrees()
        ));
    }
    Ok(Some(angle))
}

/// The largest angle accepted, rad: 1000 turns.
const MAX_ANGLE: f64 = 2000.0 * std::f64::consts::PI;

/// 3-2-1 angles from the six optional keys; `None` when none is given (missing ones are 0).
pub(super) fn angles(
    yaw: Option<f64>,
    yaw_deg: Option<f64>,
    pitch: Option<f64>,
    pitch_deg: Option<f64>,
    roll: Option<f64>,
    roll_deg: Option<f64>,
) -> Result<Option<Euler321>, String> {
    let y = one_angle("yaw", yaw, yaw_deg)?;
    let p = one_angle("pitch", pitch, pitch_deg)?;
    let r = one_angle("roll", roll, roll_deg)?;
    if y.is_none() && p.is_none() && r.is_none() {
        return Ok(None);
    }
    Ok(Some(Euler321::new(y.unwrap_or(0.0), p.unwrap_or(0.0), r.unwrap_or(0.0))))
}

pub(super) fn vec3(a: Option<[f64; 3]>) -> Vec3 {
    a.map_or_else(Vec3::zeros, |v| Vec3::new(v[0], v[1], v[2]))
}

/// An angular velocity from its rad/s key or its `_deg_s` (°/s) or `_rpm` (turns per
/// minute) variant, rad/s; at most one may be given; zero if none is.
pub(super) fn angular_rate(
    key: &str,
    rad_s: Option<[f64; 3]>,
    deg_s: Option<[f64; 3]>,
    rpm: Option<[f64; 3]>,
) -> Result<Vec3, String> {
    match (rad_s, deg_s, rpm) {
        (w, None, None) => Ok(vec3(w)),
        (None, Some(w), None) => Ok(vec3(Some(w)).map(f64::to_radians)),
        (None, None, Some(w)) => Ok(vec3(Some(w)) * (2.0 * std::f64::consts::PI / 60.0)),
        _ => Err(format!("give one of '{key}' (rad/s), '{key}_deg_s' (°/s) and '{key}_rpm' (rev/min)")),
    }
}

pub(super) fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// A 3×3 matrix from a scalar (times identity), 3 numbers (diagonal) or 3 rows of 3.
pub(super) fn matrix(v: &toml::Value) -> Option<Mat3> {
    if let Some(x) = number(v) {
        return Some(Mat3::identity() * x);
    }
    let arr = v.as_array()?;
    if arr.len() != 3 {
        return None;
    }
    if let Some(d) = arr.iter().map(number).collect::<Option<Vec<f64>>>() {
        return Some(Mat3::from_diagonal(&Vec3::new(d[0], d[1], d[2])));
    }
    let mut m = Mat3::zeros();
    for (i, row) in arr.iter().enumerate() {
        let row = row.as_array()?;
        if row.len() != 3 {
            return None;
        }
        for (j, x) in row.iter().enumerate() {
            m[(i, j)] = number(x)?;
        }
    }
    Some(m)
}

/// Rejects `nan` and `inf` anywhere in the file, naming the key.
/// Warns of an angle key in radians (no `_deg`) whose value exceeds a turn: most likely
/// degrees given to a radian key (`yaw = 30` for `yaw_deg = 30`).
fn warn_large_radians(ctx: &Ctx<'_>, path: &str, x: f64, span: std::ops::Range<usize>) {
    let key = path.rsplit('.').next().unwrap_or(path);
    let rotational_direction = [".rx.", ".ry.", ".rz."].iter().any(|d| path.contains(d));
    let angle = matches!(key, "yaw" | "pitch" | "roll") || (rotational_direction && matches!(key, "rest" | "at"));
    if angle && x.abs() > 2.0 * std::f64::consts::PI {
        ctx.warn(
            span,
            format!(
                "'{path}' = {x} rad is more than a turn ({:.1}°): if degrees were meant, write '{key}_deg = {x}'",
                x.to_degrees()
            ),
        );
    }
}

pub(super) fn check_finite(ctx: &Ctx<'_>) -> Result<(), ScenarioError> {
    use toml::de::{DeTable, DeValue};
    fn walk(ctx: &Ctx<'_>, path: &str, v: &Spanned<DeValue<'_>>) -> Result<(), ScenarioError> {
        match v.get_ref() {
            DeValue::Float(f) => {
                let x: f64 = f.as_str().replace('_', "").parse().unwrap_or(f64::NAN);
                if !x.is_finite() {
                    return Err(
                        ctx.at(Some(v.span()), format!("'{path}' is {}; every number must be finite", f.as_str()))
                    );
                }
                warn_large_radians(ctx, path, x, v.span());
            }
            DeValue::Integer(i) => {
                if let Ok(x) = i.as_str().replace('_', "").parse::<f64>() {
                    warn_large_radians(ctx, path, x, v.span());
                }
            }
            DeValue::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(ctx, &format!("{path}[{i}]"), x)?;
                }
            }
            DeValue::Table(t) => {
                for (k, x) in t.iter() {
                    let key = if path.is_empty() { k.get_ref().to_string() } else { format!("{path}.{}", k.get_ref()) };
                    walk(ctx, &key, x)?;
                }
            }
            _ => {}
        }
        Ok(())
    }
    match DeTable::parse(ctx.text) {
        Ok(t) => {
            let root = Spanned::new(t.span(), DeValue::Table(t.into_inner()));
            walk(ctx, "", &root)
        }
        // Syntax errors are reported by the typed parse, with its message.
        Err(_) => Ok(()),
    }
}

pub(super) fn positive(ctx: &Ctx<'_>, v: &Spanned<f64>, key: &str, unit: &str) -> Result<f64, ScenarioError> {
    let x = *v.get_ref();
    if x > 0.0 && x.is_finite() {
        Ok(x)
    } else {
        Err(ctx.span(v, format!("'{key}' must be a finite number > 0 {unit}, got {}", crate::math::short(x))))
    }
}

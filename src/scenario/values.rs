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

pub(super) fn vec3(a: Option<Exact<f64, 3>>) -> Vec3 {
    a.map_or_else(Vec3::zeros, |v| Vec3::new(v[0], v[1], v[2]))
}

/// An angular velocity from its rad/s key or its `_deg_s` (°/s) or `_rpm` (turns per
/// minute) variant, rad/s; at most one may be given; zero if none is.
pub(super) fn angular_rate(
    key: &str,
    rad_s: Option<Exact<f64, 3>>,
    deg_s: Option<Exact<f64, 3>>,
    rpm: Option<Exact<f64, 3>>,
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

/// Time windows `on = [[on, off], …]` (s), each on < off, of `what` (a load, a motor): absent
/// means always on; an empty list is refused (it would read as "never" but act always), and a
/// window wholly outside `[0, duration]` draws a warning (it never acts).
pub(super) fn windows(
    ctx: &Ctx<'_>,
    on: &Option<Spanned<Vec<Exact<f64, 2>>>>,
    what: &str,
    duration: f64,
) -> Result<Vec<(f64, f64)>, ScenarioError> {
    let Some(w) = on else { return Ok(Vec::new()) };
    let v = w.get_ref();
    if v.is_empty() {
        return Err(ctx.span(
            w,
            format!("{what}: 'on' = [] lists no window; give [[on, off], …] times in s, or leave 'on' out to act for the whole run"),
        ));
    }
    if v.iter().any(|Exact([a, b])| !(a.is_finite() && b.is_finite() && a < b)) {
        return Err(ctx.span(w, format!("{what}: 'on' is a list of [on, off] times, s, each on < off")));
    }
    for Exact([a, b]) in v {
        if *b <= 0.0 || *a >= duration {
            ctx.warn(
                w.span(),
                format!("{what}: the window [{a}, {b}] s lies outside the run (0 to {duration} s) and never acts"),
            );
        }
    }
    Ok(crate::loads::union(v.iter().map(|Exact([a, b])| (*a, *b)).collect()))
}

/// A list of exactly `N` items (`[x, y, z]`, an `on` pair, …): serde's fixed arrays take the
/// first `N` of a longer TOML array and drop the rest without a word; this refuses any other
/// length, located by the reader ("got a list of length 4, expected a list of 3 numbers [x, y, z], no more, no fewer").
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Exact<T, const N: usize>(pub(super) [T; N]);

impl<T, const N: usize> std::ops::Deref for Exact<T, N> {
    type Target = [T; N];
    fn deref(&self) -> &[T; N] {
        &self.0
    }
}

impl From<Exact<f64, 3>> for Vec3 {
    fn from(a: Exact<f64, 3>) -> Vec3 {
        Vec3::from(a.0)
    }
}

impl<'de, T: serde::Deserialize<'de>, const N: usize> serde::Deserialize<'de> for Exact<T, N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Items<T, const N: usize>(std::marker::PhantomData<T>);
        impl<'de, T: serde::Deserialize<'de>, const N: usize> serde::de::Visitor<'de> for Items<T, N> {
            type Value = Exact<T, N>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                match N {
                    3 => f.write_str("a list of 3 numbers [x, y, z], no more, no fewer"),
                    _ => write!(f, "a list of {N} items, no more, no fewer"),
                }
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Exact<T, N>, A::Error> {
                // On the stack: a scenario holds many of these, and a sweep reads it per run.
                let mut items: [Option<T>; N] = std::array::from_fn(|_| None);
                for (k, slot) in items.iter_mut().enumerate() {
                    match seq.next_element::<T>()? {
                        Some(x) => *slot = Some(x),
                        None => return Err(serde::de::Error::invalid_length(k, &self)),
                    }
                }
                // Count the rest for the message, without keeping them.
                let mut len = N;
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    len += 1;
                }
                if len > N {
                    return Err(serde::de::Error::invalid_length(len, &self));
                }
                Ok(Exact(items.map(|x| x.expect("filled above"))))
            }
        }
        d.deserialize_seq(Items(std::marker::PhantomData))
    }
}

/// A name that becomes part of CSV column names (a body, hinge, load, motor, wheel, thruster):
/// non-empty, letters, digits, '_' and '-' only.
pub(super) fn check_name(ctx: &Ctx<'_>, name: &Spanned<String>, what: &str) -> Result<(), ScenarioError> {
    let n = name.get_ref();
    if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        return Err(ctx.span(
            name,
            format!(
                "{what} name '{n}' must be non-empty and use only letters, digits, '_' and '-' (it names CSV columns)"
            ),
        ));
    }
    Ok(())
}

//! Scenario files (TOML): bodies, hinges, laws, initial state and run settings.
//!
//! Every key, its unit and its frame are documented in `docs/scenario.md`. Errors name the
//! file, the line and column, and the key, and say what would be valid.

use crate::init::{HingeInitial, InitialConditions, RelativeTwist};
use crate::law::directional::{Angles, DIRECTION_NAMES, Direction, DirectionalLaw, Response, Stop, Table2, TapeSpring};
use crate::law::table::{Interpolation, Outside, Table};
use crate::law::{EulerPotential, HingeLaw, LinearGains, PaperLinear, RotationVectorLinear};
use crate::math::{Euler321, Mat3, Vec3};
use crate::model::{Body, HingeSpec, Model, ModelError, ParentFrame};
use crate::simulate::{Integrator, RunSettings};
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// A scenario ready to run.
#[derive(Debug)]
pub struct Scenario {
    /// Optional title from the file.
    pub title: Option<String>,
    /// The structure.
    pub model: Model,
    /// Initial conditions (relative coordinates).
    pub initial: InitialConditions,
    /// Duration, output step and integrator.
    pub settings: RunSettings,
    /// Output CSV path from `run.csv`, resolved against the scenario file's directory.
    pub csv: Option<PathBuf>,
}

/// An error in a scenario file, located by line and column where possible.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenarioError {
    /// The file (or a label for text not read from a file).
    pub file: String,
    /// 1-based line and column of the offending value, if known.
    pub location: Option<(usize, usize)>,
    /// What is wrong and what would be valid.
    pub message: String,
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.location {
            Some((line, col)) => write!(f, "{}:{line}:{col}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for ScenarioError {}

// ---------------------------------------------------------------------------------------
// Raw file structure (serde).

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScenario {
    title: Option<String>,
    run: Spanned<RawRun>,
    #[serde(rename = "body", default)]
    bodies: Vec<RawBody>,
    #[serde(rename = "hinge", default)]
    hinges: Vec<RawHinge>,
    #[serde(default)]
    initial: RawInitial,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRun {
    duration: Spanned<f64>,
    output_step: Spanned<f64>,
    integrator: Spanned<String>,
    rtol: Option<Spanned<f64>>,
    atol: Option<Spanned<f64>>,
    step: Option<Spanned<f64>>,
    csv: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBody {
    name: Spanned<String>,
    mass: Spanned<f64>,
    inertia: Spanned<toml::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawHinge {
    name: Spanned<String>,
    parent: Spanned<String>,
    child: Spanned<String>,
    a0: Spanned<toml::Value>,
    a: Spanned<RawChildFrame>,
    law: Spanned<RawLaw>,
}

/// Angle keys shared by every table that holds an orientation.
#[derive(Deserialize, Default, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawFrame {
    position: Option<[f64; 3]>,
    yaw: Option<f64>,
    yaw_deg: Option<f64>,
    pitch: Option<f64>,
    pitch_deg: Option<f64>,
    roll: Option<f64>,
    roll_deg: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawChildFrame {
    child_com: [f64; 3],
    yaw: Option<f64>,
    yaw_deg: Option<f64>,
    pitch: Option<f64>,
    pitch_deg: Option<f64>,
    roll: Option<f64>,
    roll_deg: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLaw {
    #[serde(rename = "type")]
    kind: Spanned<String>,
    k_f: Option<Spanned<toml::Value>>,
    k_theta: Option<Spanned<toml::Value>>,
    c_f: Option<Spanned<toml::Value>>,
    c_theta: Option<Spanned<toml::Value>>,
    angles: Option<Spanned<String>>,
    x: Option<Spanned<DirectionEntry>>,
    y: Option<Spanned<DirectionEntry>>,
    z: Option<Spanned<DirectionEntry>>,
    rx: Option<Spanned<DirectionEntry>>,
    ry: Option<Spanned<DirectionEntry>>,
    rz: Option<Spanned<DirectionEntry>>,
}

/// One direction of a directional law: a table of keys, or the shorthand word `"free"` or
/// `"locked"`.
struct DirectionEntry(RawDirection);

impl<'de> Deserialize<'de> for DirectionEntry {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Entry;
        impl<'de> serde::de::Visitor<'de> for Entry {
            type Value = DirectionEntry;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "\"free\", \"locked\" or a table of response keys such as { k = 100.0 } (docs/hinge-laws.md)",
                )
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<DirectionEntry, E> {
                match v {
                    "free" => Ok(DirectionEntry(RawDirection { free: Some(true), ..Default::default() })),
                    "locked" => Ok(DirectionEntry(RawDirection { locked: Some(true), ..Default::default() })),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(v), &self)),
                }
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<DirectionEntry, A::Error> {
                RawDirection::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(DirectionEntry)
            }
        }
        d.deserialize_any(Entry)
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawDirection {
    free: Option<bool>,
    locked: Option<bool>,
    k: Option<f64>,
    table: Option<Spanned<RawTable>>,
    table2d: Option<Spanned<RawTable2>>,
    tape_spring: Option<Spanned<RawTapeSpring>>,
    rest: Option<f64>,
    rest_deg: Option<f64>,
    damping: Option<f64>,
    stop: Option<Spanned<RawStop>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTable {
    file: Option<String>,
    points: Option<Vec<[f64; 2]>>,
    interpolation: Spanned<String>,
    outside: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTable2 {
    file: String,
    other: Spanned<String>,
    interpolation: Spanned<String>,
    outside: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTapeSpring {
    increasing: Spanned<RawTable>,
    decreasing: Spanned<RawTable>,
    transition_stiffness: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStop {
    at: Option<f64>,
    at_deg: Option<f64>,
    free: Spanned<String>,
    stiffness: Spanned<f64>,
    damping: Spanned<f64>,
    #[serde(default)]
    lock: bool,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawInitial {
    hub: Option<Spanned<RawHubInitial>>,
    #[serde(default)]
    hinge: BTreeMap<Spanned<String>, Spanned<RawHingeInitial>>,
    #[serde(default)]
    body: BTreeMap<Spanned<String>, Spanned<RawAngles>>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawHubInitial {
    position: Option<[f64; 3]>,
    velocity: Option<[f64; 3]>,
    omega: Option<[f64; 3]>,
    yaw: Option<f64>,
    yaw_deg: Option<f64>,
    pitch: Option<f64>,
    pitch_deg: Option<f64>,
    roll: Option<f64>,
    roll_deg: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawHingeInitial {
    delta: Option<[f64; 3]>,
    delta_rate: Option<[f64; 3]>,
    omega_rel: Option<[f64; 3]>,
    yaw: Option<f64>,
    yaw_deg: Option<f64>,
    pitch: Option<f64>,
    pitch_deg: Option<f64>,
    roll: Option<f64>,
    roll_deg: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawAngles {
    yaw: Option<f64>,
    yaw_deg: Option<f64>,
    pitch: Option<f64>,
    pitch_deg: Option<f64>,
    roll: Option<f64>,
    roll_deg: Option<f64>,
}

// ---------------------------------------------------------------------------------------
// Location helpers.

struct Ctx<'a> {
    file: &'a str,
    text: &'a str,
    /// Directory that relative paths in the file are resolved against.
    base: &'a Path,
}

impl Ctx<'_> {
    fn at(&self, span: Option<Range<usize>>, message: impl Into<String>) -> ScenarioError {
        ScenarioError {
            file: self.file.to_string(),
            location: span.map(|s| line_col(self.text, s.start)),
            message: message.into(),
        }
    }
    fn span<T>(&self, s: &Spanned<T>, message: impl Into<String>) -> ScenarioError {
        self.at(Some(s.span()), message)
    }
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rfind('\n').map_or(before.chars().count(), |i| before[i + 1..].chars().count()) + 1;
    (line, col)
}

/// One angle from its rad or `_deg` key; both given is an error.
fn one_angle(key: &str, rad: Option<f64>, deg: Option<f64>) -> Result<Option<f64>, String> {
    match (rad, deg) {
        (Some(_), Some(_)) => Err(format!("both '{key}' and '{key}_deg' are given; give one")),
        (Some(r), None) => Ok(Some(r)),
        (None, Some(d)) => Ok(Some(d.to_radians())),
        (None, None) => Ok(None),
    }
}

/// 3-2-1 angles from the six optional keys; `None` when none is given (missing ones are 0).
fn angles(
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

fn vec3(a: Option<[f64; 3]>) -> Vec3 {
    a.map_or_else(Vec3::zeros, |v| Vec3::new(v[0], v[1], v[2]))
}

fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// A 3×3 matrix from a scalar (times identity), 3 numbers (diagonal) or 3 rows of 3.
fn matrix(v: &toml::Value) -> Option<Mat3> {
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
fn check_finite(ctx: &Ctx<'_>) -> Result<(), ScenarioError> {
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

// ---------------------------------------------------------------------------------------

impl Scenario {
    /// Reads and checks a scenario file.
    pub fn from_file(path: &Path) -> Result<Self, ScenarioError> {
        let label = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ScenarioError {
            file: label.clone(),
            location: None,
            message: format!("cannot read the scenario file: {e}"),
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        let mut s = Self::from_toml_in(&text, &label, base)?;
        if let Some(csv) = &s.csv {
            s.csv = Some(base.join(csv));
        }
        Ok(s)
    }

    /// Parses and checks scenario text; `file` labels error messages; relative table paths
    /// are resolved against the current directory.
    pub fn from_toml(text: &str, file: &str) -> Result<Self, ScenarioError> {
        Self::from_toml_in(text, file, Path::new(""))
    }

    /// As [`Scenario::from_toml`], resolving relative table paths against `base`.
    pub fn from_toml_in(text: &str, file: &str, base: &Path) -> Result<Self, ScenarioError> {
        let ctx = Ctx { file, text, base };
        let raw: RawScenario = toml::from_str(text).map_err(|e| {
            let message = e.message().trim().to_string();
            let message = match e.span().and_then(|span| enclosing_item(text, span.start)) {
                Some(item) => format!("{item}: {message}"),
                None => message,
            };
            ctx.at(e.span(), message)
        })?;
        check_finite(&ctx)?;
        build(&ctx, raw)
    }
}

/// The `[[hinge]]` or `[[body]]` entry (as "hinge 'h1'") whose text contains byte `offset`,
/// if any: parse errors inside one then name it, not only its line.
fn enclosing_item(text: &str, offset: usize) -> Option<String> {
    // Lines with their byte offsets; an item runs from its `[[…]]` header to the next header
    // that is not one of its own sub-tables.
    let mut lines = Vec::new();
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        lines.push((at, line.trim()));
        at += line.len();
    }
    let starts_item =
        |t: &str| t.starts_with("[[") || (t.starts_with('[') && !t.starts_with("[hinge.") && !t.starts_with("[body."));
    let here = lines.iter().rposition(|(start, _)| *start <= offset)?;
    let header = lines[..=here].iter().rposition(|(_, t)| starts_item(t))?;
    let kind = match lines[header].1 {
        "[[hinge]]" => "hinge",
        "[[body]]" => "body",
        _ => return None,
    };
    let name = lines[header + 1..]
        .iter()
        .take_while(|(_, t)| !starts_item(t))
        .find_map(|(_, t)| t.strip_prefix("name")?.trim_start().strip_prefix('=').map(|v| v.trim().trim_matches('"')));
    Some(match name {
        Some(n) => format!("{kind} '{n}'"),
        None => kind.to_string(),
    })
}

fn positive(ctx: &Ctx<'_>, v: &Spanned<f64>, key: &str, unit: &str) -> Result<f64, ScenarioError> {
    let x = *v.get_ref();
    if x > 0.0 && x.is_finite() {
        Ok(x)
    } else {
        Err(ctx.span(v, format!("'{key}' must be a finite number > 0 {unit}, got {x}")))
    }
}

fn build(ctx: &Ctx<'_>, raw: RawScenario) -> Result<Scenario, ScenarioError> {
    // Run settings.
    let run = raw.run.get_ref();
    let duration = positive(ctx, &run.duration, "run.duration", "s")?;
    let output_step = positive(ctx, &run.output_step, "run.output_step", "s")?;
    let need = |v: &Option<Spanned<f64>>, key: &str, what: &str| -> Result<f64, ScenarioError> {
        match v {
            Some(x) => positive(ctx, x, key, ""),
            None => Err(ctx
                .span(&raw.run, format!("[run] needs '{key}' ({what}) for integrator '{}'", run.integrator.get_ref()))),
        }
    };
    let forbid = |v: &Option<Spanned<f64>>, key: &str| -> Result<(), ScenarioError> {
        match v {
            Some(x) => Err(ctx.span(x, format!("'{key}' does not apply to integrator '{}'", run.integrator.get_ref()))),
            None => Ok(()),
        }
    };
    let integrator = match run.integrator.get_ref().as_str() {
        name @ ("dop853" | "dopri5" | "sdirk4") => {
            forbid(&run.step, "run.step")?;
            let rtol = need(&run.rtol, "run.rtol", "relative tolerance, e.g. 1e-10")?;
            let atol = need(&run.atol, "run.atol", "absolute tolerance, e.g. 1e-10")?;
            match name {
                "dop853" => Integrator::Dop853 { rtol, atol },
                "dopri5" => Integrator::Dopri5 { rtol, atol },
                _ => Integrator::Sdirk4 { rtol, atol },
            }
        }
        "rk4" => {
            forbid(&run.rtol, "run.rtol")?;
            forbid(&run.atol, "run.atol")?;
            Integrator::Rk4 { step: need(&run.step, "run.step", "fixed step in s")? }
        }
        other => {
            return Err(ctx.span(
                &run.integrator,
                format!("unknown integrator '{other}'; valid: \"dop853\", \"dopri5\", \"sdirk4\", \"rk4\""),
            ));
        }
    };
    let settings = RunSettings { duration, output_step, integrator, engage_locks_at_start: false };

    // Bodies.
    if raw.bodies.is_empty() {
        return Err(ctx.at(None, "no [[body]] given; the first [[body]] is the hub"));
    }
    let mut body_index: HashMap<String, usize> = HashMap::new();
    let mut bodies = Vec::with_capacity(raw.bodies.len());
    for (i, b) in raw.bodies.iter().enumerate() {
        let name = b.name.get_ref();
        check_name(ctx, &b.name, "body")?;
        if body_index.insert(name.clone(), i).is_some() {
            return Err(ctx.span(&b.name, format!("duplicate body name '{name}'; body names must be unique")));
        }
        let inertia = matrix(b.inertia.get_ref())
            .filter(|_| !matches!(b.inertia.get_ref(), toml::Value::Float(_) | toml::Value::Integer(_)));
        let inertia = inertia.ok_or_else(|| {
            ctx.span(&b.inertia, format!("body '{name}': 'inertia' must be 3 principal values [I1, I2, I3] or a full 3×3 tensor [[..],[..],[..]] in kg·m², body frame"))
        })?;
        let mass = *b.mass.get_ref();
        let body = Body::new(name, mass, inertia).map_err(|m| {
            let at = if mass > 0.0 && mass.is_finite() { b.inertia.span() } else { b.mass.span() };
            ctx.at(Some(at), m)
        })?;
        bodies.push(body);
    }

    // Hinges.
    let mut hinge_index: HashMap<String, usize> = HashMap::new();
    let mut specs = Vec::with_capacity(raw.hinges.len());
    for (i, h) in raw.hinges.iter().enumerate() {
        let name = h.name.get_ref();
        check_name(ctx, &h.name, "hinge")?;
        if hinge_index.insert(name.clone(), i).is_some() {
            return Err(ctx.span(&h.name, format!("duplicate hinge name '{name}'; hinge names must be unique")));
        }
        let lookup = |s: &Spanned<String>, key: &str| {
            body_index.get(s.get_ref()).copied().ok_or_else(|| {
                ctx.span(
                    s,
                    format!(
                        "hinge '{name}': {key} '{}' is not a body; bodies are: {}",
                        s.get_ref(),
                        names(&raw.bodies)
                    ),
                )
            })
        };
        let parent = lookup(&h.parent, "parent")?;
        let child = lookup(&h.child, "child")?;
        let parent_frame = parent_frame(ctx, name, &h.a0)?;
        let a = h.a.get_ref();
        let theta_c_a = angles(a.yaw, a.yaw_deg, a.pitch, a.pitch_deg, a.roll, a.roll_deg)
            .map_err(|m| ctx.span(&h.a, format!("hinge '{name}' a: {m}")))?
            .unwrap_or_default();
        let law = law(ctx, name, &h.law)?;
        specs.push(HingeSpec {
            name: name.clone(),
            parent,
            child,
            parent_frame,
            r_child_in_a: vec3(Some(a.child_com)),
            dcm_child_a: theta_c_a.to_dcm(),
            law,
        });
    }

    // Initial conditions.
    let mut ic = InitialConditions {
        hinges: vec![None; specs.len()],
        body_attitudes: vec![None; bodies.len()],
        ..Default::default()
    };
    if let Some(hub) = &raw.initial.hub {
        let r = hub.get_ref();
        ic.hub_position_in_n = vec3(r.position);
        ic.hub_velocity_in_n = vec3(r.velocity);
        ic.hub_omega_in_hub = vec3(r.omega);
        ic.hub_attitude = angles(r.yaw, r.yaw_deg, r.pitch, r.pitch_deg, r.roll, r.roll_deg)
            .map_err(|m| ctx.span(hub, format!("initial.hub: {m}")))?
            .unwrap_or_default();
    }
    let mut preferred = Vec::new();
    for (key, v) in &raw.initial.hinge {
        let Some(&i) = hinge_index.get(key.get_ref()) else {
            return Err(ctx.span(
                key,
                format!(
                    "initial.hinge.{}: no hinge of that name; hinges are: {}",
                    key.get_ref(),
                    hinge_names(&raw.hinges)
                ),
            ));
        };
        let r = v.get_ref();
        let theta = angles(r.yaw, r.yaw_deg, r.pitch, r.pitch_deg, r.roll, r.roll_deg)
            .map_err(|m| ctx.span(v, format!("initial.hinge.{}: {m}", key.get_ref())))?;
        ic.hinges[i] = Some(HingeInitial {
            twist: RelativeTwist {
                delta_in_a0: vec3(r.delta),
                delta_rate_in_a0: vec3(r.delta_rate),
                omega_rel_in_a: vec3(r.omega_rel),
            },
            theta,
        });
        preferred.push(i);
    }
    preferred.sort_unstable();
    let mut attitude_keys = HashMap::new();
    for (key, v) in &raw.initial.body {
        let Some(&i) = body_index.get(key.get_ref()) else {
            return Err(ctx.span(
                key,
                format!("initial.body.{}: no body of that name; bodies are: {}", key.get_ref(), names(&raw.bodies)),
            ));
        };
        if i == 0 {
            return Err(ctx.span(
                key,
                format!("initial.body.{}: that is the hub; give its attitude in [initial.hub]", key.get_ref()),
            ));
        }
        let r = v.get_ref();
        let att = angles(r.yaw, r.yaw_deg, r.pitch, r.pitch_deg, r.roll, r.roll_deg)
            .map_err(|m| ctx.span(v, format!("initial.body.{}: {m}", key.get_ref())))?;
        ic.body_attitudes[i] = att;
        attitude_keys.insert(i, key.span());
    }

    let model = Model::new(bodies, specs, &preferred).map_err(|e| model_error(ctx, &raw, e))?;

    // A body attitude replaces the angles of the tree hinge that places that body.
    for e in &model.tree {
        if let (Some(span), Some(Some(HingeInitial { theta: Some(_), .. }))) =
            (attitude_keys.get(&e.to), ic.hinges.get(e.hinge))
        {
            return Err(ctx.at(
                Some(span.clone()),
                format!(
                    "initial.body.{} gives the attitude of a body whose tree hinge '{}' also has initial angles; give one or the other",
                    model.bodies[e.to].name, model.hinges[e.hinge].name
                ),
            ));
        }
    }

    let columns = crate::observe::columns(&model);
    let mut seen = std::collections::HashSet::new();
    for c in &columns {
        if !seen.insert(c) {
            return Err(ctx.at(
                None,
                format!("output column '{c}' would appear twice; rename the body or hinge whose name makes it"),
            ));
        }
    }

    Ok(Scenario { title: raw.title, model, initial: ic, settings, csv: run.csv.as_ref().map(PathBuf::from) })
}

fn check_name(ctx: &Ctx<'_>, name: &Spanned<String>, what: &str) -> Result<(), ScenarioError> {
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

fn names(bodies: &[RawBody]) -> String {
    bodies.iter().map(|b| b.name.get_ref().as_str()).collect::<Vec<_>>().join(", ")
}

fn hinge_names(hinges: &[RawHinge]) -> String {
    hinges.iter().map(|h| h.name.get_ref().as_str()).collect::<Vec<_>>().join(", ")
}

fn parent_frame(ctx: &Ctx<'_>, hinge: &str, v: &Spanned<toml::Value>) -> Result<ParentFrame, ScenarioError> {
    let help = "a0 must be \"assembled\" or a table { position = [x, y, z] (m, parent frame), yaw_deg = .., pitch_deg = .., roll_deg = .. }";
    match v.get_ref() {
        toml::Value::String(s) if s == "assembled" => Ok(ParentFrame::Assembled),
        toml::Value::Table(_) => {
            let f: RawFrame = v.get_ref().clone().try_into().map_err(|e: toml::de::Error| {
                ctx.span(v, format!("hinge '{hinge}' a0: {}; {help}", e.message().trim()))
            })?;
            let position = f
                .position
                .ok_or_else(|| ctx.span(v, format!("hinge '{hinge}' a0: missing 'position' (m, parent frame)")))?;
            let theta = angles(f.yaw, f.yaw_deg, f.pitch, f.pitch_deg, f.roll, f.roll_deg)
                .map_err(|m| ctx.span(v, format!("hinge '{hinge}' a0: {m}")))?
                .unwrap_or_default();
            Ok(ParentFrame::Given { r_a0_in_parent: vec3(Some(position)), dcm_a0_parent: theta.to_dcm() })
        }
        _ => Err(ctx.span(v, format!("hinge '{hinge}': {help}"))),
    }
}

fn law(ctx: &Ctx<'_>, hinge: &str, v: &Spanned<RawLaw>) -> Result<Box<dyn HingeLaw>, ScenarioError> {
    let l = v.get_ref();
    let kind = l.kind.get_ref().as_str();
    let directional_keys = [&l.x, &l.y, &l.z, &l.rx, &l.ry, &l.rz];
    if kind == "directional" {
        for (m, key) in [(&l.k_f, "k_f"), (&l.k_theta, "k_theta"), (&l.c_f, "c_f"), (&l.c_theta, "c_theta")] {
            if let Some(m) = m {
                return Err(ctx.span(
                    m,
                    format!("hinge '{hinge}': law.{key} does not apply to a directional law; give each direction its own response"),
                ));
            }
        }
        return directional(ctx, hinge, v);
    }
    if let Some(a) = &l.angles {
        return Err(ctx.span(a, format!("hinge '{hinge}': law.angles applies only to type = \"directional\"")));
    }
    if let Some((d, name)) = directional_keys.iter().zip(DIRECTION_NAMES).find_map(|(d, n)| d.as_ref().map(|d| (d, n)))
    {
        return Err(ctx.span(d, format!("hinge '{hinge}': law.{name} applies only to type = \"directional\"")));
    }
    let mat = |m: &Option<Spanned<toml::Value>>, key: &str, unit: &str, required: bool| match m {
        Some(m) => matrix(m.get_ref()).ok_or_else(|| {
            ctx.span(
                m,
                format!(
                    "hinge '{hinge}' law.{key} must be a number, 3 numbers (a diagonal) or a 3×3 matrix, in {unit}"
                ),
            )
        }),
        None if required => Err(ctx.span(v, format!("hinge '{hinge}': law needs '{key}' ({unit})"))),
        None => Ok(Mat3::zeros()),
    };
    let gains = LinearGains {
        k_f: mat(&l.k_f, "k_f", "N/m", true)?,
        k_theta: mat(&l.k_theta, "k_theta", "N·m/rad", true)?,
        c_f: mat(&l.c_f, "c_f", "N·s/m", false)?,
        c_theta: mat(&l.c_theta, "c_theta", "N·m·s/rad", false)?,
    };
    let symmetric = |what: &str| -> Result<(), ScenarioError> {
        for (m, key) in [(&gains.k_f, &l.k_f), (&gains.k_theta, &l.k_theta)] {
            if (m - m.transpose()).abs().max() > 1e-12 * m.abs().max() {
                let key = key.as_ref().expect("required above");
                return Err(ctx.span(
                    key,
                    format!(
                        "hinge '{hinge}': the {what} law needs symmetric stiffness matrices (a potential's Hessian)"
                    ),
                ));
            }
        }
        Ok(())
    };
    match kind {
        "paper-linear" => Ok(Box::new(PaperLinear { gains })),
        "euler-potential" => {
            symmetric("euler-potential")?;
            Ok(Box::new(EulerPotential { gains }))
        }
        "rotation-vector" => {
            symmetric("rotation-vector")?;
            Ok(Box::new(RotationVectorLinear { gains }))
        }
        other => Err(ctx.span(
            &l.kind,
            format!(
                "hinge '{hinge}': unknown law type '{other}'; valid: \"paper-linear\" (MODEL.md §4 law 1), \"euler-potential\" (law 2), \"rotation-vector\", \"directional\""
            ),
        )),
    }
}

fn directional(ctx: &Ctx<'_>, hinge: &str, v: &Spanned<RawLaw>) -> Result<Box<dyn HingeLaw>, ScenarioError> {
    let l = v.get_ref();
    let angles = match l.angles.as_ref().map(|a| (a, a.get_ref().as_str())) {
        Some((_, "euler")) => Angles::Euler,
        Some((_, "rotation-vector")) => Angles::RotationVector,
        Some((a, other)) => {
            return Err(ctx.span(
                a,
                format!("hinge '{hinge}': law.angles '{other}' is not one of \"euler\", \"rotation-vector\""),
            ));
        }
        None => {
            return Err(ctx.span(
                v,
                format!("hinge '{hinge}': a directional law needs angles = \"euler\" or \"rotation-vector\""),
            ));
        }
    };
    let raw = [&l.x, &l.y, &l.z, &l.rx, &l.ry, &l.rz];
    let mut dirs = Vec::with_capacity(6);
    for (i, (d, name)) in raw.iter().zip(DIRECTION_NAMES).enumerate() {
        let Some(d) = d else {
            return Err(ctx.span(
                v,
                format!(
                    "hinge '{hinge}': a directional law needs all six directions x, y, z, rx, ry, rz; '{name}' is missing (write {name} = {{ free = true }} for no force)"
                ),
            ));
        };
        dirs.push(direction(ctx, hinge, name, i >= 3, d)?);
    }
    let directions: [Direction; 6] = dirs.try_into().expect("six directions");
    if angles == Angles::RotationVector
        && let Some(i) = (3..6).find(|&i| directions[i].response == Response::Locked)
    {
        let d = raw[i].as_ref().expect("checked above");
        return Err(ctx.span(
            d,
            format!(
                "hinge '{hinge}' law.{}: rotational directions are locked as 3-2-1 Euler angles; use angles = \"euler\" for a law with locked rotations",
                DIRECTION_NAMES[i]
            ),
        ));
    }
    Ok(Box::new(DirectionalLaw { angles, directions }))
}

fn direction(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    rotational: bool,
    d: &Spanned<DirectionEntry>,
) -> Result<Direction, ScenarioError> {
    let r = &d.get_ref().0;
    let here = |m: String| ctx.span(d, format!("hinge '{hinge}' law.{name}: {m}"));
    let (unit, rate_unit) = if rotational { ("N·m/rad", "N·m·s/rad") } else { ("N/m", "N·s/m") };
    let given = [
        r.free == Some(true),
        r.locked == Some(true),
        r.k.is_some(),
        r.table.is_some(),
        r.table2d.is_some(),
        r.tape_spring.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 || r.free == Some(false) || r.locked == Some(false) {
        return Err(here(format!(
            "give exactly one response: free = true, locked = true, k = <stiffness in {unit}>, table = {{ … }}, table2d = {{ … }} or tape_spring = {{ … }}"
        )));
    }
    if r.locked == Some(true) {
        if r.stop.is_some() || r.damping.is_some() || r.rest.is_some() || r.rest_deg.is_some() {
            return Err(here(
                "a locked direction is held at its initial value: it takes no stop, damping or rest".into(),
            ));
        }
        return Ok(Direction { response: Response::Locked, rest: 0.0, damping: 0.0, stop: None });
    }
    let angle = |rad: Option<f64>, deg: Option<f64>, key: &str| -> Result<Option<f64>, ScenarioError> {
        if !rotational && deg.is_some() {
            return Err(here(format!("'{key}_deg' applies only to rotational directions; use '{key}' in m")));
        }
        one_angle(key, rad, deg).map_err(&here)
    };
    let rest = angle(r.rest, r.rest_deg, "rest")?.unwrap_or(0.0);
    let damping = r.damping.unwrap_or(0.0);
    if damping < 0.0 {
        return Err(here(format!("damping must be ≥ 0 {rate_unit}, got {damping}")));
    }
    let response = if let Some(k) = r.k {
        Response::Linear { k }
    } else if let Some(t) = &r.table {
        Response::Table(table(ctx, hinge, name, rotational, t)?)
    } else if let Some(t) = &r.table2d {
        Response::Table2(table2(ctx, hinge, name, rotational, t)?)
    } else if let Some(ts) = &r.tape_spring {
        let raw = ts.get_ref();
        let k0 = *raw.transition_stiffness.get_ref();
        if k0 <= 0.0 {
            return Err(ctx.span(
                &raw.transition_stiffness,
                format!("hinge '{hinge}' law.{name}: transition_stiffness must be > 0 {unit}"),
            ));
        }
        let increasing = table(ctx, hinge, name, rotational, &raw.increasing)?;
        let decreasing = table(ctx, hinge, name, rotational, &raw.decreasing)?;
        // The slip element needs the increasing branch on or above the decreasing one
        // everywhere. Both interpolants are checked at every data point of either table and,
        // for PCHIP, at 64 points inside each interval (cubics can cross between points);
        // beyond the data, as far again as the data span.
        let mut at: Vec<f64> = increasing.points().iter().chain(decreasing.points()).copied().collect();
        at.sort_by(f64::total_cmp);
        at.dedup();
        let span = at[at.len() - 1] - at[0];
        at.insert(0, at[0] - span);
        at.push(at[at.len() - 1] + span);
        let fine =
            increasing.interpolation() == Interpolation::Pchip || decreasing.interpolation() == Interpolation::Pchip;
        let per = if fine { 64 } else { 1 };
        for w in at.windows(2) {
            for k in 0..=per {
                let u = w[0] + (w[1] - w[0]) * k as f64 / per as f64;
                let (fi, fd) = (increasing.eval(u).0, decreasing.eval(u).0);
                if fi < fd - 1e-12 * fd.abs().max(1.0) {
                    return Err(ctx.span(
                        ts,
                        format!(
                            "hinge '{hinge}' law.{name}: the increasing branch lies below the decreasing one at {u:.6} ({fi:.6} < {fd:.6}); the branches must not cross (with pchip they can between data points: add points or use linear)"
                        ),
                    ));
                }
            }
        }
        Response::TapeSpring(TapeSpring::new(increasing, decreasing, k0))
    } else {
        Response::Free
    };
    let stop = match &r.stop {
        None => None,
        Some(st) => {
            let raw = st.get_ref();
            let at = angle(raw.at, raw.at_deg, "at")?.ok_or_else(|| {
                ctx.span(
                    st,
                    format!(
                        "hinge '{hinge}' law.{name}.stop needs 'at'{}",
                        if rotational { " or 'at_deg'" } else { "" }
                    ),
                )
            })?;
            let free_above = match raw.free.get_ref().as_str() {
                "above" => true,
                "below" => false,
                other => {
                    return Err(ctx.span(
                        &raw.free,
                        format!("hinge '{hinge}' law.{name}.stop.free '{other}' must be \"above\" (the stop resists going below 'at') or \"below\""),
                    ));
                }
            };
            let stiffness = positive(ctx, &raw.stiffness, &format!("law.{name}.stop.stiffness"), unit)?;
            let damping = *raw.damping.get_ref();
            if damping < 0.0 {
                return Err(
                    ctx.span(&raw.damping, format!("hinge '{hinge}' law.{name}.stop.damping must be ≥ 0 {rate_unit}"))
                );
            }
            Some(Stop { at, free_above, stiffness, damping, lock: raw.lock })
        }
    };
    Ok(Direction { response, rest, damping, stop })
}

fn interpolation_and_outside(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    interpolation: &Spanned<String>,
    outside: &Spanned<String>,
) -> Result<(Interpolation, Outside), ScenarioError> {
    let i = match interpolation.get_ref().as_str() {
        "linear" => Interpolation::Linear,
        "pchip" => Interpolation::Pchip,
        other => {
            return Err(ctx.span(
                interpolation,
                format!("hinge '{hinge}' law.{name}: interpolation '{other}' must be \"linear\" or \"pchip\" (monotone C¹ cubic)"),
            ));
        }
    };
    let o = match outside.get_ref().as_str() {
        "error" => Outside::Error,
        "clamp" => Outside::Clamp,
        "extend" => Outside::Extend,
        other => {
            return Err(ctx.span(
                outside,
                format!("hinge '{hinge}' law.{name}: outside '{other}' must be \"error\", \"clamp\" or \"extend\""),
            ));
        }
    };
    Ok((i, o))
}

fn table2(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    rotational: bool,
    t: &Spanned<RawTable2>,
) -> Result<Table2, ScenarioError> {
    let r = t.get_ref();
    let here = |m: String| ctx.span(t, format!("hinge '{hinge}' law.{name} table2d: {m}"));
    let (interpolation, outside) = interpolation_and_outside(ctx, hinge, name, &r.interpolation, &r.outside)?;
    let Some(other) = DIRECTION_NAMES.iter().position(|d| *d == r.other.get_ref().as_str()) else {
        return Err(ctx.span(
            &r.other,
            format!(
                "hinge '{hinge}' law.{name}.table2d.other '{}' must be one of x, y, z, rx, ry, rz",
                r.other.get_ref()
            ),
        ));
    };
    if DIRECTION_NAMES[other] == name {
        return Err(ctx.span(&r.other, format!("hinge '{hinge}' law.{name}.table2d.other must be another direction")));
    }
    let path = ctx.base.join(&r.file);
    let grid = Table::read_grid_csv(&path).map_err(&here)?;
    if grid.u_angle != rotational || grid.v_angle != (other >= 3) {
        return Err(here(format!(
            "{}: the first column must be {} (direction {name}) and the second {} (direction {})",
            path.display(),
            if rotational { "an angle" } else { "a displacement" },
            if other >= 3 { "an angle" } else { "a displacement" },
            DIRECTION_NAMES[other]
        )));
    }
    let lines = grid
        .values
        .iter()
        .map(|vals| {
            let pts: Vec<(f64, f64)> = grid.u.iter().copied().zip(vals.iter().copied()).collect();
            Table::new(&pts, interpolation, outside)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(&here)?;
    Ok(Table2 { other, v: grid.v, lines, outside })
}

fn table(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    rotational: bool,
    t: &Spanned<RawTable>,
) -> Result<Table, ScenarioError> {
    let r = t.get_ref();
    let here = |m: String| ctx.span(t, format!("hinge '{hinge}' law.{name} table: {m}"));
    let (interpolation, outside) = interpolation_and_outside(ctx, hinge, name, &r.interpolation, &r.outside)?;
    let points = match (&r.file, &r.points) {
        (Some(file), None) => {
            let path = ctx.base.join(file);
            let (points, is_angle) = Table::read_csv(&path).map_err(&here)?;
            if is_angle != rotational {
                return Err(here(format!(
                    "{} has {} but direction {name} is {}",
                    path.display(),
                    if is_angle { "angles" } else { "displacements" },
                    if rotational {
                        "rotational (angle_rad or angle_deg, moment_Nm)"
                    } else {
                        "translational (displacement_m, force_N)"
                    }
                )));
            }
            points
        }
        (None, Some(p)) => p.iter().map(|[q, f]| (*q, *f)).collect(),
        _ => return Err(here("give either file = \"….csv\" or points = [[q, f], …] (SI units)".into())),
    };
    Table::new(&points, interpolation, outside).map_err(here)
}

fn model_error(ctx: &Ctx<'_>, raw: &RawScenario, e: ModelError) -> ScenarioError {
    let span = match (e.hinge, e.body) {
        (Some(h), _) => raw.hinges.get(h).map(|h| h.name.span()),
        (None, Some(b)) => raw.bodies.get(b).map(|b| b.name.span()),
        _ => None,
    };
    ctx.at(span, e.message)
}

/// The shipped example `file` (in `examples/`) with the lines whose key is in `keys` replaced
/// by `key = value`: for tests that vary one example.
#[cfg(test)]
pub(crate) fn example_with(file: &str, keys: &[&str], value: &str) -> Scenario {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(dir.join(file)).expect("example exists");
    let text: String = text
        .lines()
        .map(|l| {
            let key = l.split('=').next().unwrap_or("").trim();
            if keys.contains(&key) { format!("{key} = {value}") } else { l.to_string() }
        })
        .collect::<Vec<_>>()
        .join("\n");
    Scenario::from_toml_in(&text, file, &dir).expect("variant is valid")
}

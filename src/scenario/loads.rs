//! The `[[load]]` tables (docs/loads.md): external forces and torques on named bodies, each
//! value checked and located.

use super::error::{Ctx, ScenarioError};
use super::values::Exact;
use crate::loads::{Load, LoadFrame, Profile, Vector};
use crate::math::Vec3;
use crate::model::Model;
use serde::Deserialize;
use toml::Spanned;

/// One `[[load]]` table as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLoad {
    name: Spanned<String>,
    body: Spanned<String>,
    point: Option<Exact<f64, 3>>,
    force: Option<Spanned<toml::Value>>,
    force_frame: Option<Spanned<String>>,
    torque: Option<Spanned<toml::Value>>,
    torque_frame: Option<Spanned<String>>,
    times: Option<Spanned<Vec<f64>>>,
    on: Option<Spanned<Vec<Exact<f64, 2>>>>,
}

/// The loads of `raw`, added to `model`.
pub(super) fn add(ctx: &Ctx<'_>, raw: &[RawLoad], model: &mut Model, duration: f64) -> Result<(), ScenarioError> {
    let mut names = std::collections::HashSet::new();
    for r in raw {
        super::values::check_name(ctx, &r.name, "load")?;
        let name = r.name.get_ref().clone();
        if !names.insert(name.clone()) {
            return Err(ctx.span(&r.name, format!("a second load named '{name}': load names must be unique")));
        }
        let body = model.bodies.iter().position(|b| &b.name == r.body.get_ref()).ok_or_else(|| {
            ctx.span(
                &r.body,
                format!("load '{name}': no body '{}' (the bodies are {})", r.body.get_ref(), body_names(model)),
            )
        })?;
        let times = match &r.times {
            Some(t) => {
                let v = t.get_ref();
                if v.is_empty() || v.iter().any(|x| !x.is_finite()) || v.windows(2).any(|w| w[1] <= w[0]) {
                    return Err(
                        ctx.span(t, format!("load '{name}': 'times' must be finite and strictly increasing, s"))
                    );
                }
                Some(v.clone())
            }
            None => None,
        };
        let vector = |value: &Option<Spanned<toml::Value>>, frame: &Option<Spanned<String>>, key: &str, unit: &str| {
            let Some(value) = value else {
                return match frame {
                    Some(f) => Err(ctx.span(f, format!("load '{name}': '{key}_frame' without '{key}'"))),
                    None => Ok(None),
                };
            };
            let frame = match frame.as_ref().map(|f| (f, f.get_ref().as_str())) {
                Some((_, "inertial")) => LoadFrame::Inertial,
                Some((_, "body")) => LoadFrame::Body,
                Some((f, other)) => {
                    return Err(ctx.span(
                        f,
                        format!("load '{name}': '{key}_frame' is \"inertial\" or \"body\", got \"{other}\""),
                    ));
                }
                None => {
                    return Err(ctx.span(
                        value,
                        format!("load '{name}': give '{key}_frame' (\"inertial\": fixed in space; \"body\": turning with the body)"),
                    ));
                }
            };
            let bad = || {
                ctx.span(
                    value,
                    match &times {
                        Some(t) => format!(
                            "load '{name}': '{key}' must be {} vectors [x, y, z] in {unit}, one per time",
                            t.len()
                        ),
                        None => format!("load '{name}': '{key}' must be a vector [x, y, z] in {unit} (or give 'times' and one vector per time)"),
                    },
                )
            };
            let as_vec3 = |v: &toml::Value| -> Option<Vec3> {
                let a = v.as_array()?;
                if a.len() != 3 {
                    return None;
                }
                let x: Vec<f64> = a.iter().filter_map(super::values::number).filter(|x| x.is_finite()).collect();
                (x.len() == 3).then(|| Vec3::new(x[0], x[1], x[2]))
            };
            let profile = match &times {
                None => Profile::Constant(as_vec3(value.get_ref()).ok_or_else(bad)?),
                Some(t) => {
                    let rows = value.get_ref().as_array().ok_or_else(bad)?;
                    let values: Option<Vec<Vec3>> = rows.iter().map(as_vec3).collect();
                    let values = values.filter(|v| v.len() == t.len()).ok_or_else(bad)?;
                    Profile::Table { times: t.clone(), values }
                }
            };
            Ok(Some(Vector { profile, frame }))
        };
        let force = vector(&r.force, &r.force_frame, "force", "N")?;
        let torque = vector(&r.torque, &r.torque_frame, "torque", "N·m")?;
        if force.is_none() && torque.is_none() {
            return Err(ctx.span(&r.name, format!("load '{name}': give a 'force' or a 'torque' (or both)")));
        }
        let windows = super::values::windows(ctx, &r.on, &format!("load '{name}'"), duration)?;
        if r.point.is_some_and(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(ctx.span(&r.name, format!("load '{name}': 'point' must be finite, m")));
        }
        model.loads.push(Load {
            name,
            body,
            point_in_body: r.point.map_or(Vec3::zeros(), Vec3::from),
            force,
            torque,
            windows,
        });
    }
    Ok(())
}

fn body_names(model: &Model) -> String {
    model.bodies.iter().map(|b| format!("'{}'", b.name)).collect::<Vec<_>>().join(", ")
}

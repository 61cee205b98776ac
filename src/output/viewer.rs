//! A run as one self-contained HTML page (feature `animation`): the animation
//! ([`super::animation`]) embedded as base64, three.js with its glTF loader and orbit controls
//! (vendored in `viewer/three-bundle.js`, MIT licence in `viewer/LICENSE-three.txt`, built
//! from the npm registry's `three` by `viewer/package.json`), our viewer script
//! (`viewer/viewer.js`) and the run's data: chosen output columns for the plot, and every
//! panel's fold angle (the |yaw| of the tree hinge that places it) per frame, and its fold
//! moment (`_M_z`) where the CSV has it. No server and no network: the page opens from a
//! file.

use super::animation::{Frames, Table, glb_bytes};
use super::units::unit_of;
use crate::model::Model;
use base64::Engine;
use std::fmt::Write;

const TEMPLATE: &str = include_str!("../../viewer/template.html");
const THREE: &str = include_str!("../../viewer/three-bundle.js");
const THREE_LICENSE: &str = include_str!("../../viewer/LICENSE-three.txt");
const VIEWER: &str = include_str!("../../viewer/viewer.js");

/// The columns plotted when none are chosen: with contact, its columns (how deep, how hard,
/// how many pairs); else the spin-deployment ones if the run has them, else the first hinges'
/// fold angles.
fn default_columns(model: &Model, table: &Table) -> Vec<String> {
    if model.contact.is_some() {
        let contact: Vec<String> = crate::observe::CONTACT_COLUMNS
            .iter()
            .rev()
            .map(|c| c.to_string())
            .filter(|c| table.column(c).is_some())
            .collect();
        if !contact.is_empty() {
            return contact;
        }
    }
    if table.column("deployed").is_some() && model.hinges.len() > 8 {
        return vec!["deployed".into(), "spin_rate".into()];
    }
    model.hinges.iter().take(6).map(|h| format!("{}_yaw", h.name)).filter(|c| table.column(c).is_some()).collect()
}

/// A JSON array of numbers (non-finite values as null, which the plot leaves as gaps).
fn numbers(out: &mut String, values: impl Iterator<Item = f64>) {
    out.push('[');
    for (i, v) in values.enumerate() {
        if i > 0 {
            out.push(',');
        }
        if v.is_finite() {
            let _ = write!(out, "{}", ryu::Buffer::new().format(v));
        } else {
            out.push_str("null");
        }
    }
    out.push(']');
}

/// A JSON string, safe inside a `<script>` element.
fn string(s: &str) -> String {
    serde_json::to_string(s).expect("a string").replace("</", "<\\/")
}

/// `{ "bodies": [...], "values": [[per frame]] }` of the column `{hinge}{suffix}` of every
/// body's placing tree hinge that the CSV has, at the rows `kept`, through `scale`.
fn per_body(out: &mut String, model: &Model, table: &Table, kept: &[usize], suffix: &str, scale: fn(f64) -> f64) {
    let found: Vec<(String, usize)> = model
        .tree
        .iter()
        .filter_map(|e| {
            let column = table.column(&format!("{}{suffix}", model.hinges[e.hinge].name))?;
            Some((model.bodies[e.to].name.clone(), column))
        })
        .collect();
    out.push_str("{\"bodies\":[");
    out.push_str(&found.iter().map(|(b, _)| string(b)).collect::<Vec<_>>().join(","));
    out.push_str("],\"values\":[");
    for (k, (_, i)) in found.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        numbers(out, kept.iter().map(|&r| scale(table.rows[r][*i])));
    }
    out.push_str("]}");
}

/// The page for `table` (a run's CSV) of `model`, its animation `frames` taken from the rows
/// `kept`; `columns` are plotted (empty: a default choice). Fails naming a column it lacks.
pub fn page(
    title: &str,
    model: &Model,
    table: &Table,
    frames: &Frames,
    kept: &[usize],
    columns: &[String],
) -> Result<String, String> {
    let glb = glb_bytes(model, frames)?;
    let columns = if columns.is_empty() { default_columns(model, table) } else { columns.to_vec() };
    let mut plotted = Vec::new();
    for c in &columns {
        let i = table.column(c).ok_or_else(|| {
            format!(
                "--columns: the run's CSV has no column '{c}' (it has e.g. {})",
                table.header.iter().take(8).cloned().collect::<Vec<_>>().join(", ")
            )
        })?;
        plotted.push(i);
    }
    let t_col = table.column("t").ok_or("no column 't'")?;
    let mut data = String::new();
    let _ = write!(data, "{{\"title\":{},\"glb\":\"", string(title));
    data.push_str(&base64::engine::general_purpose::STANDARD.encode(&glb));
    data.push_str("\",\"times\":");
    numbers(&mut data, frames.times.iter().copied());
    data.push_str(",\"plot\":{\"names\":[");
    data.push_str(&columns.iter().map(|c| string(c)).collect::<Vec<_>>().join(","));
    data.push_str("],\"units\":[");
    data.push_str(&columns.iter().map(|c| string(unit_of(c))).collect::<Vec<_>>().join(","));
    data.push_str("],\"t\":");
    numbers(&mut data, table.rows.iter().map(|r| r[t_col]));
    data.push_str(",\"values\":[");
    for (k, &i) in plotted.iter().enumerate() {
        if k > 0 {
            data.push(',');
        }
        numbers(&mut data, table.rows.iter().map(|r| r[i]));
    }
    // Per body, the tree hinge that places it: its fold angle (degrees) and, where the CSV
    // has it (`_M_z`, written on request), its fold moment (N·m), per frame.
    data.push_str("]},\"fold\":");
    per_body(&mut data, model, table, kept, "_yaw", f64::to_degrees);
    data.push_str(",\"moment\":");
    per_body(&mut data, model, table, kept, "_M_z", |x| x);
    data.push('}');

    // One pass over the template, so nothing inserted is read as a placeholder.
    let mut out = String::with_capacity(TEMPLATE.len() + THREE.len() + VIEWER.len() + data.len());
    let mut rest = TEMPLATE;
    while let Some(start) = rest.find("{{") {
        let end = rest[start..].find("}}").map(|e| start + e + 2).ok_or("viewer template: an unclosed placeholder")?;
        out.push_str(&rest[..start]);
        match &rest[start..end] {
            "{{DATA}}" => out.push_str(&data),
            "{{THREE}}" => out.push_str(THREE),
            "{{VIEWER}}" => out.push_str(VIEWER),
            "{{THREE_LICENSE}}" => out.push_str(&THREE_LICENSE.replace('<', "&lt;")),
            other => return Err(format!("viewer template: unknown placeholder {other}")),
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    Ok(out)
}

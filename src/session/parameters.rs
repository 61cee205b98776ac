//! A scenario's numbers by key path, to be changed before a session starts (the C library's
//! `foldsim_set_parameter`, the FMU's parameters): the documented subset is every number the
//! scenario file writes as a single value outside `[run]` (a mass, a stiffness, a law's
//! damping, an initial angle), by the key paths sweeps use (docs/scenario.md, "Key paths").
//! Vectors, tables of points and `[run]` (how to run, not what runs) are not offered.

use crate::scenario::{ScenarioText, SetValue};

/// The parameters `text` offers: (key path, the file's value), in the file's order.
pub fn offered(text: &ScenarioText) -> Vec<(String, f64)> {
    text.numbers().into_iter().filter(|(p, _)| !is_run(p)).collect()
}

/// The offered parameters whose key paths match any of `patterns` (`*` any run of
/// characters, `?` one). Fails naming a pattern that matches none.
pub fn matching(text: &ScenarioText, patterns: &[String]) -> Result<Vec<(String, f64)>, String> {
    let all = offered(text);
    for p in patterns {
        if !all.iter().any(|(k, _)| crate::observe::glob(p, k)) {
            let some: Vec<&str> = all.iter().take(6).map(|(k, _)| k.as_str()).collect();
            return Err(format!(
                "parameter pattern '{p}' matches no number of the scenario (numbers written as single values outside [run], like {}{})",
                some.join(", "),
                if all.len() > 6 { ", …" } else { "" }
            ));
        }
    }
    Ok(all.into_iter().filter(|(k, _)| patterns.iter().any(|p| crate::observe::glob(p, k))).collect())
}

/// Sets the number at `path` to `value` in `text`. Refused, naming the path: a value that is
/// not finite, a path into `[run]`, a path that holds no single number in the file.
pub fn set(text: &mut ScenarioText, path: &str, value: f64) -> Result<(), String> {
    if !value.is_finite() {
        return Err(format!("parameter {path}: the value must be a finite number, got {value}"));
    }
    if is_run(path) {
        return Err(format!(
            "parameter {path}: [run] says how to run (duration, tolerances, output), not what runs; it is not a parameter"
        ));
    }
    let locations = text.locations(path)?;
    for at in &locations {
        let v = text.get(at)?;
        let number = v
            .as_deref()
            .and_then(|v| v.parse::<toml_edit::Value>().ok())
            .is_some_and(|v| v.is_float() || v.is_integer());
        if !number {
            return Err(match v {
                None => format!(
                    "parameter {path}: {at} is not in the scenario; only numbers the file writes are parameters"
                ),
                Some(v) => format!("parameter {path}: {at} holds {v}, not a single number"),
            });
        }
    }
    text.set(path, &SetValue::Number(value))
}

fn is_run(path: &str) -> bool {
    path.split('.').next() == Some("run")
}

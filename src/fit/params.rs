//! A fit's free parameters: scenario values by key path (as sweeps name them,
//! `crate::scenario::edit`), each with optional bounds, starting from the scenario's value.

use crate::scenario::ScenarioText;

/// One fitted value.
#[derive(Clone, Debug, PartialEq)]
pub struct Free {
    /// Its key path (`hinge.h1.law.k_theta`; a wildcard, `hinge.*.law.k_f`, ties one value
    /// across every entry it matches).
    pub path: String,
    /// Lower bound (−∞ for none), in the key's unit.
    pub low: f64,
    /// Upper bound (∞ for none).
    pub high: f64,
    /// The scenario's value: where the fit starts.
    pub start: f64,
}

/// Parses `--free` arguments, `KEY` or `KEY=LOW:HIGH` (either bound may be left empty:
/// `KEY=0:` is `KEY ≥ 0`), and reads each one's starting value from `text`. Refused, naming
/// the argument: a path that names no value or a value that is not a number, a wildcard
/// whose values differ (a tied parameter starts from one value), bounds that are not
/// numbers or not `LOW < HIGH`, a start outside its bounds, two paths naming one value, a
/// value of `[run]` (how to run is not fitted).
pub fn parse(args: &[String], text: &ScenarioText) -> Result<Vec<Free>, String> {
    if args.is_empty() {
        return Err("no --free parameter: name at least one scenario value to fit (--free hinge.h1.law.k_theta)".into());
    }
    let mut out = Vec::new();
    for arg in args {
        let (path, bounds) = match arg.split_once('=') {
            Some((p, b)) => (p.trim(), Some(b.trim())),
            None => (arg.trim(), None),
        };
        let bad = |m: String| format!("--free {arg}: {m}");
        if path.is_empty() {
            return Err(bad("no key path before '='".into()));
        }
        let (low, high) = match bounds {
            None => (f64::NEG_INFINITY, f64::INFINITY),
            Some(b) => {
                let (l, h) = b.split_once(':').ok_or_else(|| bad(format!("bounds '{b}' are not LOW:HIGH")))?;
                let bound = |s: &str, none: f64| -> Result<f64, String> {
                    let s = s.trim();
                    if s.is_empty() {
                        return Ok(none);
                    }
                    s.parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| bad(format!("bound '{s}' is not a finite number")))
                };
                (bound(l, f64::NEG_INFINITY)?, bound(h, f64::INFINITY)?)
            }
        };
        if path.split('.').next() == Some("run") {
            return Err(bad(
                "the [run] table says how to run (duration, tolerances, output), not what the structure is: fit the model's values".into(),
            ));
        }
        if low >= high {
            return Err(bad(format!("the bounds need LOW < HIGH; got {low}:{high}")));
        }
        let locations = text.locations(path).map_err(&bad)?;
        let mut values: Vec<(String, f64)> = Vec::new();
        for at in &locations {
            let v = text.get(at).map_err(&bad)?;
            let number = v.as_deref().and_then(|v| v.parse::<toml_edit::Value>().ok()).and_then(|v| match v {
                toml_edit::Value::Float(f) => Some(*f.value()),
                toml_edit::Value::Integer(i) => Some(*i.value() as f64),
                _ => None,
            });
            match (v, number) {
                (None, _) => {
                    return Err(bad(format!(
                        "{at} is not in the scenario: a fit starts from the scenario's value; write the key there"
                    )));
                }
                (Some(v), None) => return Err(bad(format!("{at} holds {v}, not a number"))),
                (Some(v), Some(x)) if !x.is_finite() => {
                    return Err(bad(format!("{at} holds {v}, not a finite number to start from")));
                }
                (_, Some(x)) => values.push((at.clone(), x)),
            }
        }
        let Some(&(_, start)) = values.first() else { return Err(bad("names no value".into())) };
        if let Some((at, x)) = values.iter().find(|(_, x)| *x != start) {
            return Err(bad(format!(
                "the values it names differ ({} = {start}, {at} = {x}): a tied parameter starts from one value; make them equal in the scenario or fit each by its own path",
                values[0].0
            )));
        }
        if !(low..=high).contains(&start) {
            return Err(bad(format!("the scenario's value {start} is outside the bounds {low}:{high}")));
        }
        out.push(Free { path: path.to_string(), low, high, start });
    }
    let paths: Vec<&str> = out.iter().map(|f| f.path.as_str()).collect();
    text.check_distinct(&paths).map_err(|e| format!("--free: {e}"))?;
    Ok(out)
}

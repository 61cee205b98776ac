//! A sweep's `[sweep]` table: the run count, the seed, the distributions of the swept values
//! and the metrics summarised per run (docs/sweep.md). Read from the file's own text, so
//! errors carry its lines.

use crate::scenario::ScenarioError;
use std::ops::Range;
use toml_edit::{Item, Value};

/// The most runs one sweep takes.
pub const MAX_RUNS: usize = 10_000_000;

/// How a swept value is drawn for each run.
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    /// Normal with `mean` and standard deviation `sd` (> 0).
    Normal {
        /// Mean, in the key's unit.
        mean: f64,
        /// Standard deviation, in the key's unit.
        sd: f64,
    },
    /// Uniform on [`low`, `high`).
    Uniform {
        /// Lower bound, in the key's unit.
        low: f64,
        /// Upper bound, in the key's unit.
        high: f64,
    },
    /// Log-uniform on [`low`, `high`) (0 < low < high): uniform in the logarithm.
    LogUniform {
        /// Lower bound (> 0), in the key's unit.
        low: f64,
        /// Upper bound, in the key's unit.
        high: f64,
    },
    /// One of `values`, each equally likely.
    Choice(Vec<f64>),
    /// Run `i` takes `values[i]` (an explicit list; the run count is its length).
    List(Vec<f64>),
}

/// A swept value: its key path in the scenario and how it is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Key path (`hinge.h1.law.k_theta.2`, see `crate::scenario::edit`).
    pub path: String,
    /// Its distribution.
    pub distribution: Distribution,
}

/// What a metric takes from an output column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Statistic {
    /// The value at the last output row.
    Final,
    /// The least value over the output rows.
    Min,
    /// The greatest value over the output rows.
    Max,
    /// The first time, s, the column crosses `value` (interpolated between output rows) in
    /// the given direction; empty if it never does.
    Crosses {
        /// The level, in the column's unit.
        value: f64,
        /// +1 upward only, −1 downward only, 0 either.
        direction: i8,
    },
}

/// A summary metric of each run.
#[derive(Clone, Debug, PartialEq)]
pub enum Metric {
    /// A statistic of an output column (by its name in the output catalogue).
    Column {
        /// Column name, as `run.columns` names it.
        column: String,
        /// What is taken from it.
        statistic: Statistic,
    },
    /// The time, s, a hinge's first latch engaged; empty if none did.
    Latch(String),
    /// The time, s, a hinge's first locked direction engaged (carried load); empty if none did.
    Lock(String),
}

/// The `[sweep]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// Number of runs.
    pub runs: usize,
    /// Seed of the draws (run `i` draws from its own stream of this seed).
    pub seed: u64,
    /// The swept values, in the file's order.
    pub parameters: Vec<Parameter>,
    /// The metrics, named, in the file's order.
    pub metrics: Vec<(String, Metric)>,
}

/// Reads the `[sweep]` table of scenario text (`None` if there is none).
pub fn read(text: &str, file: &str) -> Result<Option<SweepSpec>, ScenarioError> {
    let doc = toml_edit::Document::parse(text.to_string()).map_err(|e| ScenarioError {
        file: file.to_string(),
        location: e.span().map(|s| crate::scenario::error::line_col(text, s.start)),
        message: e.message().to_string(),
    })?;
    let Some(sweep) = doc.get("sweep") else { return Ok(None) };
    let err = |span: Option<Range<usize>>, message: String| ScenarioError {
        file: file.to_string(),
        location: span.map(|s| crate::scenario::error::line_col(text, s.start)),
        message,
    };
    let table = sweep.as_table_like().ok_or_else(|| err(sweep.span(), "'sweep' must be a table".into()))?;
    for (key, item) in table.iter() {
        if !["runs", "seed", "parameters", "metrics"].contains(&key) {
            return Err(err(
                span_of(item),
                format!("unknown key 'sweep.{key}': [sweep] takes runs, seed, parameters and metrics"),
            ));
        }
    }
    let whole = |key: &str| -> Result<Option<Located<i64>>, ScenarioError> {
        match table.get(key) {
            None => Ok(None),
            Some(item) => match item.as_integer() {
                Some(v) if v >= 0 => Ok(Some((v, span_of(item)))),
                _ => Err(err(span_of(item), format!("'sweep.{key}' must be a whole number ≥ 0"))),
            },
        }
    };
    let runs = whole("runs")?;
    let seed = whole("seed")?;
    let parameters = match table.get("parameters") {
        Some(p) => {
            let t = p.as_table_like().ok_or_else(|| {
                err(span_of(p), "'sweep.parameters' must be a table of key path = distribution".into())
            })?;
            t.iter().map(|(path, item)| parameter(path, item, &err)).collect::<Result<Vec<_>, _>>()?
        }
        None => Vec::new(),
    };
    if parameters.is_empty() {
        return Err(err(
            span_of(sweep),
            "[sweep] needs at least one entry in [sweep.parameters], e.g. \"hinge.h1.law.k_theta\" = { distribution = \"normal\", mean = 1.0, sd = 0.1 }".into(),
        ));
    }
    let metrics = match table.get("metrics") {
        Some(m) => {
            let t = m
                .as_table_like()
                .ok_or_else(|| err(span_of(m), "'sweep.metrics' must be a table of name = metric".into()))?;
            t.iter().map(|(name, item)| metric(name, item, &err)).collect::<Result<Vec<_>, _>>()?
        }
        None => Vec::new(),
    };
    // The run count: given, or the explicit lists' length; they must all agree.
    let lists: Vec<(&str, usize)> = parameters
        .iter()
        .filter_map(|p| match &p.distribution {
            Distribution::List(v) => Some((p.path.as_str(), v.len())),
            _ => None,
        })
        .collect();
    if let Some((path, _)) = lists.iter().find(|(_, len)| *len != lists[0].1) {
        return Err(err(
            span_of(sweep),
            format!("the lists of [sweep.parameters] must all have one value per run; '{path}' differs"),
        ));
    }
    let runs = match (runs, lists.first()) {
        (Some((n, span)), Some((path, len))) if n as usize != *len => {
            return Err(err(
                span,
                format!(
                    "'sweep.runs' = {n} but the list of '{path}' has {len} values: they must agree (or leave runs out)"
                ),
            ));
        }
        (Some((n, _)), _) => n as usize,
        (None, Some((_, len))) => *len,
        (None, None) => {
            return Err(err(span_of(sweep), "[sweep] needs 'runs', the number of runs (e.g. runs = 1000)".into()));
        }
    };
    if runs == 0 || runs > MAX_RUNS {
        return Err(err(span_of(sweep), format!("a sweep takes 1 to {MAX_RUNS} runs; got {runs}")));
    }
    let random = parameters.iter().any(|p| !matches!(p.distribution, Distribution::List(_)));
    let seed = match seed {
        Some((s, _)) => s as u64,
        None if random => {
            return Err(err(
                span_of(sweep),
                "[sweep] needs 'seed' (a whole number ≥ 0) for its random draws, so that the sweep can be repeated"
                    .into(),
            ));
        }
        None => 0,
    };
    Ok(Some(SweepSpec { runs, seed, parameters, metrics }))
}

/// A value and where it is in the text.
type Located<T> = (T, Option<Range<usize>>);

fn span_of(item: &Item) -> Option<Range<usize>> {
    item.span().or_else(|| item.as_value().and_then(Value::span))
}

type Err<'a> = &'a dyn Fn(Option<Range<usize>>, String) -> ScenarioError;

fn numbers(item: &Item, what: &str, err: Err<'_>) -> Result<Vec<f64>, ScenarioError> {
    let values: Option<Vec<f64>> = item
        .as_array()
        .map(|a| a.iter().map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64))).collect())
        .and_then(|v: Vec<Option<f64>>| v.into_iter().collect());
    match values {
        Some(v) if !v.is_empty() && v.iter().all(|x| x.is_finite()) => Ok(v),
        _ => Err(err(span_of(item), format!("{what} must be a list of one or more finite numbers"))),
    }
}

fn parameter(path: &str, item: &Item, err: Err<'_>) -> Result<Parameter, ScenarioError> {
    let at = span_of(item);
    let t = item.as_table_like().ok_or_else(|| {
        err(
            at.clone(),
            format!(
                "'{path}' must be a distribution table, e.g. {{ distribution = \"uniform\", low = 0.5, high = 2.0 }}"
            ),
        )
    })?;
    let num = |key: &str| -> Result<f64, ScenarioError> {
        let v = t.get(key).ok_or_else(|| err(at.clone(), format!("'{path}' needs '{key}'")))?;
        match v.as_float().or_else(|| v.as_integer().map(|i| i as f64)) {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(err(span_of(v), format!("'{path}': '{key}' must be a finite number"))),
        }
    };
    let allow = |keys: &[&str]| -> Result<(), ScenarioError> {
        match t.iter().find(|(k, _)| *k != "distribution" && !keys.contains(k)) {
            Some((k, v)) => Err(err(
                span_of(v),
                format!("'{path}': '{k}' does not apply here (this distribution takes {})", keys.join(", ")),
            )),
            None => Ok(()),
        }
    };
    let kind = t.get("distribution").and_then(Item::as_str);
    let distribution = match kind {
        Some("normal") => {
            allow(&["mean", "sd"])?;
            let (mean, sd) = (num("mean")?, num("sd")?);
            if sd <= 0.0 {
                return Err(err(at, format!("'{path}': sd must be > 0 (a fixed value needs no sweep)")));
            }
            Distribution::Normal { mean, sd }
        }
        Some(name @ ("uniform" | "log-uniform")) => {
            allow(&["low", "high"])?;
            let (low, high) = (num("low")?, num("high")?);
            if low >= high || (name == "log-uniform" && low <= 0.0) {
                let need = if name == "log-uniform" { "0 < low < high" } else { "low < high" };
                return Err(err(at, format!("'{path}': {name} needs {need}; got low = {low}, high = {high}")));
            }
            if name == "uniform" { Distribution::Uniform { low, high } } else { Distribution::LogUniform { low, high } }
        }
        Some("choice") | Some("list") => {
            allow(&["values"])?;
            let values = t.get("values").ok_or_else(|| err(at.clone(), format!("'{path}' needs 'values'")))?;
            let v = numbers(values, &format!("'{path}': values"), err)?;
            if kind == Some("choice") { Distribution::Choice(v) } else { Distribution::List(v) }
        }
        _ => {
            let at = t.get("distribution").and_then(span_of).or(at);
            return Err(err(
                at,
                format!("'{path}': 'distribution' must be one of normal, uniform, log-uniform, choice, list"),
            ));
        }
    };
    Ok(Parameter { path: path.to_string(), distribution })
}

fn metric(name: &str, item: &Item, err: Err<'_>) -> Result<(String, Metric), ScenarioError> {
    let at = span_of(item);
    let valid = !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !valid {
        return Err(err(at, format!("metric name '{name}' must be letters, digits and _ (it names a column)")));
    }
    let usage = "a metric is { column = \"NAME\", stat = \"final\" | \"min\" | \"max\" }, { column = \"NAME\", crosses = VALUE, direction = \"up\" | \"down\" | \"either\" }, { latch = \"HINGE\" } or { lock = \"HINGE\" }";
    let t = item.as_table_like().ok_or_else(|| err(at.clone(), format!("metric '{name}': {usage}")))?;
    let keys: Vec<&str> = t.iter().map(|(k, _)| k).collect();
    let text = |key: &str| t.get(key).and_then(Item::as_str).map(str::to_string);
    let only = |allowed: &[&str]| keys.iter().all(|k| allowed.contains(k));
    let m = if let (Some(column), Some(stat), true) = (text("column"), text("stat"), only(&["column", "stat"])) {
        let statistic = match stat.as_str() {
            "final" => Statistic::Final,
            "min" => Statistic::Min,
            "max" => Statistic::Max,
            _ => {
                return Err(err(
                    at,
                    format!("metric '{name}': stat must be final, min or max (or give crosses = VALUE)"),
                ));
            }
        };
        Metric::Column { column, statistic }
    } else if let (Some(column), Some(level), true) =
        (text("column"), t.get("crosses"), only(&["column", "crosses", "direction"]))
    {
        let value = level.as_float().or_else(|| level.as_integer().map(|i| i as f64)).filter(|x| x.is_finite());
        let value =
            value.ok_or_else(|| err(span_of(level), format!("metric '{name}': crosses must be a finite number")))?;
        let direction = match text("direction").as_deref() {
            None | Some("either") => 0,
            Some("up") => 1,
            Some("down") => -1,
            Some(_) => return Err(err(at, format!("metric '{name}': direction must be up, down or either"))),
        };
        Metric::Column { column, statistic: Statistic::Crosses { value, direction } }
    } else if let (Some(hinge), true) = (text("latch"), only(&["latch"])) {
        Metric::Latch(hinge)
    } else if let (Some(hinge), true) = (text("lock"), only(&["lock"])) {
        Metric::Lock(hinge)
    } else {
        return Err(err(at, format!("metric '{name}': {usage}")));
    };
    Ok((name.to_string(), m))
}

//! A fit's measurements: a CSV file with a `t` column (s) and any output columns by their
//! names (docs/outputs.md), read and checked against the model's columns and the run's span,
//! every error naming the file and the line or column.

use crate::model::Model;
use crate::observe::catalogue;
use std::path::Path;

/// Measured values of output columns at times.
#[derive(Clone, Debug, PartialEq)]
pub struct Data {
    /// The file (or label) the values came from.
    pub file: String,
    /// The measurement times, s, strictly ascending.
    pub times: Vec<f64>,
    /// The measured columns, in the file's order.
    pub columns: Vec<Measured>,
}

/// One measured column.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// The output column's name (`h1_yaw`, `deployed`, …).
    pub name: String,
    /// Its position in the model's output catalogue ([`crate::observe::row`]).
    pub index: usize,
    /// Per time: the measured value in the column's unit (docs/outputs.md), or `None` where
    /// the file's cell is empty (not measured then).
    pub values: Vec<Option<f64>>,
    /// The measurement's standard deviation in the column's unit, if given: its residuals
    /// are divided by it. `None`: weight 1 (the column's own unit).
    pub sigma: Option<f64>,
}

impl Data {
    /// Reads `path` (see [`Data::parse`]).
    pub fn read(path: &Path, model: &Model, duration: f64) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        Self::parse(&text, &path.display().to_string(), model, duration)
    }

    /// Parses CSV `text` (labelled `file` in errors): a header with `t` and output columns
    /// of `model`, then one row per time; blank lines and lines starting with `#` are skipped. Refused, with the line or column named: a column
    /// that is no output of the model (or named twice), no `t` column or no other column, a
    /// cell that is not a number (`NaN` and infinities included; an empty cell means "not
    /// measured then", except in `t`), times not strictly ascending or outside the run (0 to
    /// `duration` s), a row of the wrong length, fewer than two rows, a column with no value.
    pub fn parse(text: &str, file: &str, model: &Model, duration: f64) -> Result<Self, String> {
        let err = |line: usize, m: String| format!("{file}:{line}: {m}");
        let mut lines = data_lines(text);
        let Some((header_line, header)) = lines.next() else {
            return Err(format!("{file}: empty; a data file has a header (t and output columns) and rows of numbers"));
        };
        let names: Vec<String> = header.split(',').map(|h| h.trim().trim_matches('"').to_string()).collect();
        let t_at = names.iter().position(|n| n == "t").ok_or_else(|| {
            err(header_line, format!("no column 't' (the measurement time, s) in the header '{}'", header.trim()))
        })?;
        let outputs = catalogue(model);
        let mut columns = Vec::new();
        for (k, name) in names.iter().enumerate() {
            if k == t_at {
                continue;
            }
            if names[..k].contains(name) {
                return Err(err(header_line, format!("column '{name}' is named twice")));
            }
            let Some(index) = outputs.iter().position(|c| &c.name == name) else {
                let like: Vec<&str> = outputs.iter().skip(1).take(6).map(|c| c.name.as_str()).collect();
                return Err(err(
                    header_line,
                    format!(
                        "column '{name}' is not an output column of this scenario (they are named as in `foldsim run`'s CSV: {}, …; docs/outputs.md)",
                        like.join(", ")
                    ),
                ));
            };
            columns.push(Measured { name: name.clone(), index, values: Vec::new(), sigma: None });
        }
        if columns.is_empty() {
            return Err(err(header_line, "no measured column besides 't'".into()));
        }
        let mut times: Vec<f64> = Vec::new();
        for (line, row) in lines {
            let cells: Vec<&str> = row.split(',').map(str::trim).collect();
            if cells.len() != names.len() {
                return Err(err(line, format!("{} cells; the header has {}", cells.len(), names.len())));
            }
            let number = |k: usize| -> Result<Option<f64>, String> {
                let c = cells[k].trim_matches('"');
                if c.is_empty() {
                    return Ok(None);
                }
                match c.parse::<f64>() {
                    Ok(x) if x.is_finite() => Ok(Some(x)),
                    _ => Err(err(line, format!("column '{}': '{c}' is not a finite number", names[k]))),
                }
            };
            let t = number(t_at)?.ok_or_else(|| err(line, "no time in column 't'".into()))?;
            if !(0.0..=duration).contains(&t) {
                return Err(err(line, format!("t = {t} s is outside the run (0 to run.duration = {duration} s)")));
            }
            if let Some(&last) = times.last()
                && t <= last
            {
                return Err(err(line, format!("t = {t} s does not come after the row before ({last} s)")));
            }
            times.push(t);
            let mut c = 0;
            for k in 0..names.len() {
                if k != t_at {
                    columns[c].values.push(number(k)?);
                    c += 1;
                }
            }
        }
        if times.len() < 2 {
            return Err(format!("{file}: {} row(s) of data; a fit needs at least two", times.len()));
        }
        if let Some(c) = columns.iter().find(|c| c.values.iter().all(Option::is_none)) {
            return Err(format!("{file}: column '{}' has no value", c.name));
        }
        Ok(Self { file: file.to_string(), times, columns })
    }

    /// Sets column `name`'s standard deviation (> 0, finite; in its unit).
    pub fn set_sigma(&mut self, name: &str, sigma: f64) -> Result<(), String> {
        if !(sigma.is_finite() && sigma > 0.0) {
            return Err(format!("--sigma {name}={sigma}: a standard deviation is a finite number > 0"));
        }
        let names: Vec<String> = self.columns.iter().map(|c| c.name.clone()).collect();
        let c = self.columns.iter_mut().find(|c| c.name == name).ok_or_else(|| {
            format!("--sigma {name}: '{name}' is not a column of {} (its columns: {})", self.file, names.join(", "))
        })?;
        c.sigma = Some(sigma);
        Ok(())
    }

    /// The number of measured values (non-empty cells).
    pub fn count(&self) -> usize {
        self.columns.iter().map(|c| c.values.iter().flatten().count()).sum()
    }
}

/// A data file's lines with their numbers (from 1), blank lines and `#` comments left out.
pub(super) fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
}

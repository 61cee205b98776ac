//! Errors located in a scenario file: the file, the line and column, and the key.

use std::fmt;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

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

pub(super) struct Ctx<'a> {
    pub(super) file: &'a str,
    pub(super) text: &'a str,
    /// Directory that relative paths in the file are resolved against.
    pub(super) base: &'a Path,
    /// Files read while building (tables), in order.
    pub(super) inputs: std::cell::RefCell<Vec<std::path::PathBuf>>,
    /// Warnings, located ("file:line:col: message").
    pub(super) warnings: std::cell::RefCell<Vec<String>>,
}

impl Ctx<'_> {
    /// Records a warning at `span`.
    pub(super) fn warn(&self, span: Range<usize>, message: String) {
        let (line, col) = line_col(self.text, span.start);
        self.warnings.borrow_mut().push(format!("{}:{line}:{col}: {message}", self.file));
    }

    pub(super) fn at(&self, span: Option<Range<usize>>, message: impl Into<String>) -> ScenarioError {
        ScenarioError {
            file: self.file.to_string(),
            location: span.map(|s| line_col(self.text, s.start)),
            message: message.into(),
        }
    }
    pub(super) fn span<T>(&self, s: &Spanned<T>, message: impl Into<String>) -> ScenarioError {
        self.at(Some(s.span()), message)
    }
}

/// The 1-based line and column (in characters) of byte `offset` of `text`.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rfind('\n').map_or(before.chars().count(), |i| before[i + 1..].chars().count()) + 1;
    (line, col)
}

/// The `[[hinge]]` or `[[body]]` entry (as "hinge 'h1'") whose text contains byte `offset`,
/// if any: parse errors inside one then name it, not only its line.
pub(super) fn enclosing_item(text: &str, offset: usize) -> Option<String> {
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

/// A message of the TOML reader in the scenario's words: the key of a duplicate, "a number"
/// for `f64`, "a table { child_com = … }" for an internal type, "key" for "field". `text` and
/// `span` locate the offending item (a duplicate's key is read from there).
pub(super) fn in_user_words(message: &str, text: &str, span: Option<Range<usize>>) -> String {
    if message.starts_with("duplicate key") {
        let key = span
            .and_then(|s| text.get(s.start..))
            .map(|rest| rest.chars().take_while(|c| !matches!(c, '=' | '\n' | ']')).collect::<String>())
            .map(|k| k.trim().trim_matches(|c| c == '[' || c == '"').to_string())
            .filter(|k| !k.is_empty());
        return match key {
            Some(k) => format!("duplicate key '{k}': give each key once"),
            None => "duplicate key: give each key once".into(),
        };
    }
    let mut out = message.to_string();
    // Found values, as serde names them.
    for (from, to) in [
        ("invalid type: string ", "got the text "),
        ("invalid type: integer ", "got the whole number "),
        ("invalid type: floating point ", "got the number "),
        ("invalid type: boolean ", "got "),
        ("invalid type: sequence", "got a list"),
        ("invalid type: map", "got a table"),
        ("invalid length ", "got a list of length "),
        (" as i128", " (too large)"),
    ] {
        out = out.replace(from, to);
    }
    // Expected types, in the file's terms.
    for (from, to) in [
        (
            "expected struct RawChildFrame",
            "expected a table like { child_com = [x, y, z], yaw_deg = 0.0 } (m, A frame)",
        ),
        ("expected struct RawFrame", "expected a table like { position = [x, y, z], yaw_deg = 0.0 } (m, parent frame)"),
        ("expected struct RawLaw", "expected a table like { type = \"euler-potential\", k_f = …, k_theta = … }"),
        (
            "expected struct RawTable2",
            "expected a table like { file = \"….csv\", other = \"rz\", interpolation = \"linear\", outside = \"error\" }",
        ),
        (
            "expected struct RawTable",
            "expected a table like { points = [[u, f], …], interpolation = \"linear\", outside = \"error\" }",
        ),
        (
            "expected struct RawTapeSpring",
            "expected a table like { increasing = { … }, decreasing = { … }, transition_stiffness = … }",
        ),
        ("expected struct RawStop", "expected a table like { at_deg = 0.0, free = \"above\", stiffness = … }"),
        ("expected an array of length 3", "expected a list of 3 numbers [x, y, z]"),
        ("expected f64", "expected a number"),
        ("expected i64", "expected a whole number"),
        ("expected u64", "expected a whole number"),
        ("expected usize", "expected a whole number"),
        ("expected a boolean", "expected true or false"),
        ("expected a sequence", "expected a list [ … ]"),
        ("unknown field", "unknown key"),
        ("missing field", "missing key"),
        ("expected one of", "valid keys:"),
    ] {
        out = out.replace(from, to);
    }
    // Any other internal type name.
    while let Some(i) = out.find("struct Raw") {
        let end = out[i..].find(|c: char| !(c.is_alphanumeric() || c == ' ')).map_or(out.len(), |e| i + e);
        out.replace_range(i..end, "a table");
    }
    out.replace('`', "'")
}

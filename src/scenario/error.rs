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
}

impl Ctx<'_> {
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

pub(super) fn line_col(text: &str, offset: usize) -> (usize, usize) {
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

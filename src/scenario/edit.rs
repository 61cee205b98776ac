//! Changing a scenario's values by key path (`hinge.h1.law.k_theta`), keeping the rest of
//! its text as written, so that errors in the changed scenario still point at the file's own
//! lines (docs/scenario.md, "Key paths").
//!
//! A path is the keys from the top of the file down, joined by dots. Where a key holds a
//! list of tables (`body`, `hinge`), the next part picks one entry by its `name` (or by its
//! 0-based position); where it holds a list of values (a vector), the next part is the 0-based
//! position. The last key may be new (a key the file leaves at its default); every key
//! before it must exist.

use super::{Scenario, ScenarioError};
use std::path::{Path, PathBuf};
use toml_edit::{DocumentMut, Item, Value};

/// A scenario as text that can be changed by key path and then built.
#[derive(Clone, Debug)]
pub struct ScenarioText {
    /// The file name (or label) errors are located in.
    pub file: String,
    /// The directory table files are read from.
    pub base: PathBuf,
    /// The file it was read from, if any.
    path: Option<PathBuf>,
    doc: DocumentMut,
}

/// A value to set at a key path.
#[derive(Clone, Debug, PartialEq)]
pub enum SetValue {
    /// A number. Written as an integer where the key holds an integer and the number is
    /// whole, as a float otherwise.
    Number(f64),
    /// Any TOML value (a string, a vector, a table), as TOML text (`[1.0, 2.0, 3.0]`).
    Toml(String),
}

impl ScenarioText {
    /// Reads a scenario file's text (not yet checked: see [`ScenarioText::build`]).
    pub fn from_file(path: &Path) -> Result<Self, ScenarioError> {
        let text = super::build::read_file(path)?;
        let mut s = Self::new(&text, &path.display().to_string(), path.parent().unwrap_or(Path::new("")))?;
        s.path = Some(path.to_path_buf());
        Ok(s)
    }

    /// Scenario text labelled `file`, with table files read from `base`. Only the TOML syntax
    /// is checked here; the scenario itself when built.
    pub fn new(text: &str, file: &str, base: &Path) -> Result<Self, ScenarioError> {
        match text.parse::<DocumentMut>() {
            Ok(doc) => Ok(Self { file: file.to_string(), base: base.to_path_buf(), path: None, doc }),
            // The scenario parser words TOML errors for users and locates them: use it.
            Err(_) => Err(Scenario::from_toml_in(text, file, base).err().unwrap_or_else(|| ScenarioError {
                file: file.to_string(),
                location: None,
                message: "not valid TOML".into(),
            })),
        }
    }

    /// The text as it stands.
    pub fn text(&self) -> String {
        self.doc.to_string()
    }

    /// Checks and builds the scenario (as [`Scenario::from_file`] does when read from one).
    pub fn build(&self) -> Result<Scenario, ScenarioError> {
        let s = Scenario::from_toml_in(&self.text(), &self.file, &self.base)?;
        Ok(match &self.path {
            Some(path) => s.read_from(path),
            None => s,
        })
    }

    /// Replaces (or adds) the top-level table `key` (a sweep's `[sweep]`, say).
    pub fn set_table(&mut self, key: &str, table: toml_edit::Table) {
        self.doc.insert(key, Item::Table(table));
    }

    /// The text without its top-level table `key` (and the tables under it) when that table
    /// comes last in the file, so that every other line keeps its number; unchanged
    /// otherwise. A sweep's runs leave out the `[sweep]` table this way: it can hold long
    /// lists that every run would otherwise copy and parse again.
    pub fn without_trailing_table(&self, key: &str) -> Self {
        fn positions(item: &Item, out: &mut Vec<Option<isize>>) {
            if let Some(t) = item.as_table() {
                out.push(t.position());
                for (_, sub) in t.iter() {
                    positions(sub, out);
                }
            } else if let Some(tables) = item.as_array_of_tables() {
                for t in tables.iter() {
                    out.push(t.position());
                    for (_, sub) in t.iter() {
                        positions(sub, out);
                    }
                }
            }
        }
        let Some(own) = self.doc.get(key) else { return self.clone() };
        let (mut mine, mut others) = (Vec::new(), Vec::new());
        positions(own, &mut mine);
        for (k, item) in self.doc.iter() {
            if k != key {
                positions(item, &mut others);
            }
        }
        // A table made here (no position) is written at the end.
        let first_own = mine.iter().map(|p| p.unwrap_or(isize::MAX)).min().unwrap_or(isize::MAX);
        let last_other = others.iter().flatten().copied().max().unwrap_or(isize::MIN);
        let mut out = self.clone();
        if own.is_table() && first_own > last_other {
            out.doc.remove(key);
        }
        out
    }

    /// The value at `path`, as TOML text (`None` if no key is there).
    pub fn get(&self, path: &str) -> Result<Option<String>, String> {
        let parts = split(path)?;
        let mut item = self.doc.as_item();
        for (i, part) in parts.iter().enumerate() {
            match step(item, part, &parts[..i])? {
                Some(next) => item = next,
                None => return Ok(None),
            }
        }
        Ok(item_text(item))
    }

    /// Sets `path` to `value`. A part naming list entries may hold `*` and `?`
    /// (`hinge.*.law.k_theta.2`): every entry whose name matches is set, and at least one
    /// must. Errors name the path and the part that is wrong, and say what the file has
    /// there.
    pub fn set(&mut self, path: &str, value: &SetValue) -> Result<(), String> {
        let parts = split(path)?;
        set_in(self.doc.as_item_mut(), &parts, 0, path, value).map(|_| ())
    }

    /// The values `path` names, each as a path with list entries by position
    /// (`hinge.*.law.c_f` → `hinge.0.law.c_f`, `hinge.1.law.c_f`, …): how two spellings of
    /// one value are told apart from two values. Errors as [`ScenarioText::set`]'s.
    pub fn locations(&self, path: &str) -> Result<Vec<String>, String> {
        let parts = split(path)?;
        let mut out = Vec::new();
        locate(self.doc.as_item(), &parts, 0, path, &mut Vec::new(), &mut out)?;
        Ok(out)
    }

    /// Every number the text writes as a single value (not in a vector or a list), with its
    /// key path (list entries by `name` where they have one, by position otherwise), in the
    /// file's order: the values a C program or an FMU's host may change by key path.
    pub fn numbers(&self) -> Vec<(String, f64)> {
        fn walk(item: &Item, path: &mut Vec<String>, out: &mut Vec<(String, f64)>) {
            let table = |pairs: Vec<(&str, &Item)>, path: &mut Vec<String>, out: &mut Vec<(String, f64)>| {
                for (k, sub) in pairs {
                    path.push(k.to_string());
                    walk(sub, path, out);
                    path.pop();
                }
            };
            match item {
                Item::Table(t) => table(t.iter().collect(), path, out),
                Item::ArrayOfTables(list) => {
                    for (i, t) in list.iter().enumerate() {
                        let name = t.get("name").and_then(|n| n.as_str()).filter(|n| !n.contains('.'));
                        path.push(name.map_or_else(|| i.to_string(), str::to_string));
                        table(t.iter().collect(), path, out);
                        path.pop();
                    }
                }
                Item::Value(Value::InlineTable(t)) => {
                    for (k, v) in t.iter() {
                        path.push(k.to_string());
                        walk(&Item::Value(v.clone()), path, out);
                        path.pop();
                    }
                }
                Item::Value(Value::Float(f)) => out.push((path.join("."), *f.value())),
                Item::Value(Value::Integer(i)) => out.push((path.join("."), *i.value() as f64)),
                _ => {}
            }
        }
        let mut out = Vec::new();
        walk(self.doc.as_item(), &mut Vec::new(), &mut out);
        out
    }

    /// Refuses key paths of which two name the same value, or one a value inside the other's
    /// (`hinge.h1.law.k_theta` and `hinge.*.law.k_theta`, `body.0.mass` and `body.hub.mass`):
    /// one change would silently undo the other. The error names both paths.
    pub fn check_distinct(&self, paths: &[&str]) -> Result<(), String> {
        let located: Vec<Vec<String>> = paths.iter().map(|p| self.locations(p)).collect::<Result<_, _>>()?;
        let within = |a: &str, b: &str| a == b || b.strip_prefix(a).is_some_and(|rest| rest.starts_with('.'));
        for (i, a) in located.iter().enumerate() {
            for (j, b) in located.iter().enumerate().skip(i + 1) {
                if let Some((x, _)) =
                    a.iter().flat_map(|x| b.iter().map(move |y| (x, y))).find(|(x, y)| within(x, y) || within(y, x))
                {
                    return Err(format!(
                        "'{}' and '{}' both set {x}: give each value one key path",
                        paths[i], paths[j]
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Collects in `out` the positional paths below `item` that `parts[at..]` name; `trail` is
/// the positional path to `item`.
fn locate(
    item: &Item,
    parts: &[&str],
    at: usize,
    path: &str,
    trail: &mut Vec<String>,
    out: &mut Vec<String>,
) -> Result<(), String> {
    let part = parts[at];
    let before = &parts[..at];
    let last = at + 1 == parts.len();
    let down = |next: &Item, key: String, trail: &mut Vec<String>, out: &mut Vec<String>| {
        trail.push(key);
        let r = if last {
            out.push(trail.join("."));
            Ok(())
        } else {
            locate(next, parts, at + 1, path, trail, out)
        };
        trail.pop();
        r
    };
    if let Some(tables) = item.as_array_of_tables() {
        let names: Vec<Option<&str>> = tables.iter().map(|t| t.get("name").and_then(Item::as_str)).collect();
        let matching: Vec<usize> = if part.contains(['*', '?']) {
            let m: Vec<usize> =
                (0..names.len()).filter(|&i| names[i].is_some_and(|n| crate::observe::glob(part, n))).collect();
            if m.is_empty() {
                return Err(format!("'{path}': no entry of '{}' has a name matching '{part}'", before.join(".")));
            }
            m
        } else {
            vec![entry_position(names.iter().copied(), part, before)?]
        };
        for i in matching {
            down(&item[i], i.to_string(), trail, out)?;
        }
        return Ok(());
    }
    if let Some(array) = item.as_array() {
        let i = index(part, array.len(), path)?;
        return down(&item[i], i.to_string(), trail, out);
    }
    match item.as_table_like() {
        Some(t) => match t.get(part) {
            Some(next) => down(next, part.to_string(), trail, out),
            None if last => down(&Item::None, part.to_string(), trail, out),
            None => Err(format!(
                "'{path}': '{}' has no key '{part}'; only the last key of a path may be new",
                before.join(".")
            )),
        },
        None => Err(format!("'{path}': '{}' holds {}, not a table", before.join("."), kind(item))),
    }
}

/// Sets `parts[at..]` below `item` (which `parts[..at]` led to); returns how many values
/// were set.
fn set_in(item: &mut Item, parts: &[&str], at: usize, path: &str, value: &SetValue) -> Result<usize, String> {
    let part = parts[at];
    let before = &parts[..at];
    if at + 1 < parts.len() {
        if part.contains(['*', '?'])
            && let Some(tables) = item.as_array_of_tables()
        {
            let matching: Vec<usize> = (0..tables.len())
                .filter(|&i| {
                    tables
                        .get(i)
                        .and_then(|t| t.get("name"))
                        .and_then(Item::as_str)
                        .is_some_and(|n| crate::observe::glob(part, n))
                })
                .collect();
            if matching.is_empty() {
                return Err(format!("'{path}': no entry of '{}' has a name matching '{part}'", before.join(".")));
            }
            let mut count = 0;
            for i in matching {
                count += set_in(&mut item[i], parts, at + 1, path, value)?;
            }
            return Ok(count);
        }
        let next = step_mut(item, part, before)?;
        return set_in(next, parts, at + 1, path, value);
    }
    set_last(item, part, before, path, value).map(|_| 1)
}

/// Sets key (or position) `last` of `item` to `value`.
fn set_last(item: &mut Item, last: &str, parents: &[&str], path: &str, value: &SetValue) -> Result<(), String> {
    let new = |old: Option<&Value>| -> Result<Value, String> {
        match value {
            SetValue::Number(x) => {
                if !x.is_finite() {
                    return Err(format!("'{path}': {x} is not a finite number"));
                }
                let whole = x.fract() == 0.0 && x.abs() < 2f64.powi(53);
                // A new key takes a whole number as an integer: an integer key (max_steps)
                // refuses 1.0, and a float key takes 1 as well as 1.0.
                let integer = old.is_none_or(Value::is_integer);
                Ok(if integer && whole { Value::from(*x as i64) } else { Value::from(*x) })
            }
            SetValue::Toml(text) => {
                text.parse::<Value>().map_err(|e| format!("'{path}': '{text}' is not a TOML value: {}", e.message()))
            }
        }
    };
    let decorated = |mut v: Value, old: Option<&Value>| {
        if let Some(old) = old {
            *v.decor_mut() = old.decor().clone();
        }
        v
    };
    let here = format!("'{}'", parents.join("."));
    if let Some(array) = item.as_array_mut() {
        let i = index(last, array.len(), path)?;
        let v = new(array.get(i))?;
        let v = decorated(v, array.get(i));
        array.replace(i, v);
        return Ok(());
    }
    let what = kind(item);
    let table = item.as_table_like_mut().ok_or_else(|| format!("'{path}': {here} holds {what}, not a table"))?;
    let old = table.get(last).and_then(Item::as_value).cloned();
    if table.get(last).is_some_and(|i| i.as_value().is_none()) {
        return Err(format!("'{path}' is a table or a list of tables: give a path down to one of its numbers"));
    }
    let v = decorated(new(old.as_ref())?, old.as_ref());
    table.insert(last, Item::Value(v));
    Ok(())
}

/// The parts of a key path.
fn split(path: &str) -> Result<Vec<&str>, String> {
    let parts: Vec<&str> = path.split('.').collect();
    if parts.iter().any(|p| p.trim().is_empty() || p.trim() != *p) {
        return Err(format!(
            "'{path}' is not a key path: give keys joined by dots without spaces, e.g. hinge.h1.law.k_theta"
        ));
    }
    Ok(parts)
}

fn index(part: &str, len: usize, path: &str) -> Result<usize, String> {
    match part.parse::<usize>() {
        Ok(i) if i < len => Ok(i),
        _ => Err(format!("'{path}': '{part}' must be a position 0 to {} in a list of {len}", len.saturating_sub(1))),
    }
}

/// The entry of a list of tables named `part` (its `name` key) or at position `part`.
fn entry_position<'a>(
    names: impl Iterator<Item = Option<&'a str>>,
    part: &str,
    before: &[&str],
) -> Result<usize, String> {
    let names: Vec<Option<&str>> = names.collect();
    if let Some(i) = names.iter().position(|n| *n == Some(part)) {
        return Ok(i);
    }
    if let Ok(i) = part.parse::<usize>()
        && i < names.len()
    {
        return Ok(i);
    }
    let known: Vec<&str> = names.iter().flatten().copied().collect();
    Err(format!(
        "'{}' has no entry named '{part}' (names: {}; or a position 0 to {})",
        before.join("."),
        if known.is_empty() { "none".to_string() } else { known.join(", ") },
        names.len().saturating_sub(1)
    ))
}

/// One step down from `item` (read only); `None` if the key is absent.
fn step<'a>(item: &'a Item, part: &str, before: &[&str]) -> Result<Option<&'a Item>, String> {
    if let Some(tables) = item.as_array_of_tables() {
        let i = entry_position(tables.iter().map(|t| t.get("name").and_then(Item::as_str)), part, before)?;
        return Ok(tables.get(i).map(|_| &item[i]));
    }
    if let Some(array) = item.as_array() {
        let i = index(part, array.len(), &before.join("."))?;
        return Ok(Some(&item[i]));
    }
    match item.as_table_like() {
        Some(t) => Ok(t.get(part)),
        None => Err(format!("'{}' holds {}, not a table", before.join("."), kind(item))),
    }
}

/// One step down from `item`, which must exist.
fn step_mut<'a>(item: &'a mut Item, part: &str, before: &[&str]) -> Result<&'a mut Item, String> {
    let at = || if before.is_empty() { "the file".to_string() } else { format!("'{}'", before.join(".")) };
    if let Some(tables) = item.as_array_of_tables() {
        let i = entry_position(tables.iter().map(|t| t.get("name").and_then(Item::as_str)), part, before)?;
        return Ok(&mut item[i]);
    }
    if let Some(array) = item.as_array() {
        let i = index(part, array.len(), &before.join("."))?;
        return Ok(&mut item[i]);
    }
    let Some(table) = item.as_table_like_mut() else {
        return Err(format!("{} holds a value, not a table", at()));
    };
    if table.get(part).is_none() {
        let keys: Vec<String> = table.iter().map(|(k, _)| k.to_string()).collect();
        return Err(format!(
            "{} has no key '{part}' (it has: {}); only the last key of a path may be new",
            at(),
            if keys.is_empty() { "nothing".into() } else { keys.join(", ") }
        ));
    }
    Ok(table.get_mut(part).expect("checked above"))
}

fn item_text(item: &Item) -> Option<String> {
    match item {
        Item::None => None,
        Item::Value(v) => Some(v.clone().decorated("", "").to_string()),
        other => Some(other.to_string()),
    }
}

fn kind(item: &Item) -> &'static str {
    match item {
        Item::Value(Value::String(_)) => "a string",
        Item::Value(Value::Array(_)) => "a list",
        Item::Table(_) | Item::Value(Value::InlineTable(_)) => "a table",
        Item::Value(_) => "a value",
        Item::ArrayOfTables(_) => "a list of tables",
        Item::None => "nothing",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "title = \"t\"\n[run]\nduration = 1.0 # s\nmax_steps = 100\n\n[[body]]\nname = \"hub\"\nmass = 5.0\ninertia = [1.0, 2.0, 3.0]\n\n[[hinge]]\nname = \"h1\"\nlaw = { type = \"x\", k_theta = [1.0, 2.0, 3.0] }\n";

    fn doc() -> ScenarioText {
        ScenarioText::new(TEXT, "t.toml", Path::new("")).unwrap()
    }

    #[test]
    fn sets_by_name_position_and_new_last_key_keeping_the_rest_of_the_text() {
        let mut d = doc();
        d.set("hinge.h1.law.k_theta.2", &SetValue::Number(7.5)).unwrap();
        d.set("body.0.mass", &SetValue::Number(6.0)).unwrap();
        d.set("run.max_steps", &SetValue::Number(200.0)).unwrap();
        d.set("hinge.h1.law.c_theta", &SetValue::Number(0.25)).unwrap();
        d.set("run.duration", &SetValue::Number(2.0)).unwrap();
        let text = d.text();
        assert!(text.contains("k_theta = [1.0, 2.0, 7.5]"), "{text}");
        assert!(text.contains("mass = 6.0\n"), "{text}");
        assert!(text.contains("max_steps = 200\n"), "integer stays an integer: {text}");
        assert!(text.contains("c_theta = 0.25"), "{text}");
        assert!(text.contains("duration = 2.0 # s"), "comment kept: {text}");
        assert_eq!(text.lines().count(), TEXT.lines().count(), "lines kept: errors stay located");
        assert_eq!(d.get("hinge.h1.law.k_theta.2").unwrap().as_deref(), Some("7.5"));
        assert_eq!(d.get("hinge.h1.law.c_f").unwrap(), None);
    }

    #[test]
    fn a_wildcard_sets_every_matching_entry() {
        let text = format!(
            "{TEXT}\n[[hinge]]\nname = \"h2\"\nlaw = {{ k_theta = [1.0, 2.0, 3.0] }}\n\n[[hinge]]\nname = \"g\"\nlaw = {{ k_theta = [1.0, 2.0, 3.0] }}\n"
        );
        let mut d = ScenarioText::new(&text, "t.toml", Path::new("")).unwrap();
        d.set("hinge.h*.law.k_theta.2", &SetValue::Number(9.0)).unwrap();
        assert_eq!(d.get("hinge.h1.law.k_theta.2").unwrap().as_deref(), Some("9.0"));
        assert_eq!(d.get("hinge.h2.law.k_theta.2").unwrap().as_deref(), Some("9.0"));
        assert_eq!(d.get("hinge.g.law.k_theta.2").unwrap().as_deref(), Some("3.0"), "not matched");
        d.set("hinge.*.law.c_f", &SetValue::Number(0.5)).unwrap();
        assert_eq!(d.get("hinge.g.law.c_f").unwrap().as_deref(), Some("0.5"));
        let e = d.set("hinge.x*.law.k_f", &SetValue::Number(1.0)).unwrap_err();
        assert!(e.contains("no entry of 'hinge' has a name matching 'x*'"), "{e}");
    }

    #[test]
    fn two_spellings_of_one_value_are_refused() {
        let text = format!("{TEXT}\n[[hinge]]\nname = \"h2\"\nlaw = {{ k_theta = [1.0, 2.0, 3.0] }}\n");
        let d = ScenarioText::new(&text, "t.toml", Path::new("")).unwrap();
        assert_eq!(d.locations("hinge.*.law.k_theta.2").unwrap(), ["hinge.0.law.k_theta.2", "hinge.1.law.k_theta.2"]);
        for (a, b) in [
            ("hinge.h1.law.k_theta.1", "hinge.*.law.k_theta.1"),
            ("body.0.mass", "body.hub.mass"),
            ("hinge.h2.law.k_theta", "hinge.1.law.k_theta.0"),
            ("hinge.h1.law.c_f", "hinge.h?.law.c_f"),
        ] {
            let e = d.check_distinct(&["run.duration", a, b]).unwrap_err();
            assert!(e.contains(a) && e.contains(b), "{e}");
        }
        d.check_distinct(&[
            "hinge.h1.law.k_theta.1",
            "hinge.h2.law.k_theta.1",
            "body.hub.mass",
            "hinge.h1.law.k_theta.0",
        ])
        .unwrap();
    }

    #[test]
    fn a_trailing_table_is_left_out_and_a_middle_one_kept() {
        let last = format!("{TEXT}\n[sweep]\nruns = 2\n[sweep.parameters]\nx = 1\n");
        let d = ScenarioText::new(&last, "t.toml", Path::new("")).unwrap();
        let cut = d.without_trailing_table("sweep").text();
        assert!(!cut.contains("sweep") && cut.starts_with(TEXT.trim_end()), "{cut}");
        let middle = format!("[sweep]\nruns = 2\n{TEXT}");
        let d = ScenarioText::new(&middle, "t.toml", Path::new("")).unwrap();
        assert_eq!(d.without_trailing_table("sweep").text(), middle, "lines after it would move");
    }

    #[test]
    fn bad_paths_say_what_is_there() {
        let mut d = doc();
        let e = d.set("hinge.h2.law.k_theta", &SetValue::Number(1.0)).unwrap_err();
        assert!(e.contains("no entry named 'h2'") && e.contains("h1"), "{e}");
        let e = d.set("run.nope.x", &SetValue::Number(1.0)).unwrap_err();
        assert!(e.contains("no key 'nope'") && e.contains("duration"), "{e}");
        let e = d.set("body.hub.inertia.3", &SetValue::Number(1.0)).unwrap_err();
        assert!(e.contains("position 0 to 2"), "{e}");
        let e = d.set("run", &SetValue::Number(1.0)).unwrap_err();
        assert!(e.contains("table"), "{e}");
        let e = d.set("run..duration", &SetValue::Number(1.0)).unwrap_err();
        assert!(e.contains("not a key path"), "{e}");
        let e = d.set("run.duration", &SetValue::Number(f64::NAN)).unwrap_err();
        assert!(e.contains("finite"), "{e}");
    }
}

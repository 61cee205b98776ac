//! Python values as TOML values and back: scenarios built from dicts have the structure a
//! scenario file has (docs/scenario.md), so they go through the same checks.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use toml_edit::{Array, ArrayOfTables, DocumentMut, InlineTable, Item, Table, Value};

fn bad(path: &str, what: &str) -> PyErr {
    PyValueError::new_err(format!("{path}: {what}"))
}

/// How deep values may nest: a scenario file is at most six levels deep, so anything past
/// this is a mistake (and unbounded recursion would overflow the interpreter's stack).
pub const MAX_DEPTH: usize = 64;

/// The containers (dicts, lists) being converted, outermost first: a container met again
/// inside itself is a cycle.
#[derive(Default)]
pub struct Nesting(Vec<usize>);

impl Nesting {
    /// Enters `obj` (a container at `path`): refuses a cycle or nesting past [`MAX_DEPTH`].
    fn enter(&mut self, obj: &Bound<'_, PyAny>, path: &str) -> PyResult<()> {
        let id = obj.as_ptr() as usize;
        if self.0.contains(&id) {
            return Err(bad(path, "this value contains itself (a dict or list inside itself): a scenario is a tree"));
        }
        if self.0.len() >= MAX_DEPTH {
            return Err(bad(
                path,
                &format!("values nest deeper than {MAX_DEPTH} levels; a scenario file is at most a few levels deep"),
            ));
        }
        self.0.push(id);
        Ok(())
    }

    fn leave(&mut self) {
        self.0.pop();
    }
}

/// A Python value (bool, int, float, str, list or tuple, dict, NumPy array or scalar) as a
/// TOML value; `path` names it in errors.
pub fn value(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Value> {
    value_in(obj, path, &mut Nesting::default())
}

fn value_in(obj: &Bound<'_, PyAny>, path: &str, nesting: &mut Nesting) -> PyResult<Value> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(Value::from(obj.extract::<bool>()?));
    }
    if obj.is_instance_of::<PyInt>() {
        let i: i64 = obj.extract().map_err(|_| bad(path, "integer out of range"))?;
        return Ok(Value::from(i));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(Value::from(obj.extract::<f64>()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(Value::from(obj.extract::<String>()?));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        nesting.enter(obj, path)?;
        let mut a = Array::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            a.push(value_in(&item?, &format!("{path}[{i}]"), nesting)?);
        }
        nesting.leave();
        return Ok(Value::Array(a));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        nesting.enter(obj, path)?;
        let mut t = InlineTable::new();
        for (k, v) in d.iter() {
            let k = key(&k, path)?;
            t.insert(&k, value_in(&v, &format!("{path}.{k}"), nesting)?);
        }
        nesting.leave();
        return Ok(Value::InlineTable(t));
    }
    // NumPy arrays and scalars: their Python values (`tolist()` gives nested lists of
    // Python numbers, or the number itself).
    if obj.get_type().module().is_ok_and(|m| m == "numpy")
        && let Ok(plain) = obj.call_method0("tolist")
    {
        return value_in(&plain, path, nesting);
    }
    // Other numbers: anything float() takes.
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(Value::from(x));
    }
    Err(bad(
        path,
        &format!("a {} is not a scenario value (give numbers, strings, lists or dicts)", obj.get_type().name()?),
    ))
}

fn key(k: &Bound<'_, PyAny>, path: &str) -> PyResult<String> {
    k.extract::<String>().map_err(|_| bad(path, "dict keys must be strings"))
}

/// A list whose entries are all dicts: a list of tables (`[[body]]`).
fn is_list_of_dicts(obj: &Bound<'_, PyAny>) -> bool {
    obj.cast::<PyList>().is_ok_and(|l| !l.is_empty() && l.iter().all(|e| e.is_instance_of::<PyDict>()))
}

/// A dict as a TOML table: dicts inside become `[a.b]` tables and lists of dicts `[[a]]`
/// lists of tables, whose own dicts are written inline (`law = { … }`), as the example
/// files are.
pub fn table(d: &Bound<'_, PyDict>, path: &str) -> PyResult<Table> {
    table_in(d, path, &mut Nesting::default())
}

fn table_in(d: &Bound<'_, PyDict>, path: &str, nesting: &mut Nesting) -> PyResult<Table> {
    nesting.enter(d.as_any(), if path.is_empty() { "the dict" } else { path })?;
    let mut t = Table::new();
    for (k, v) in d.iter() {
        let k = key(&k, path)?;
        let here = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
        let item = if let Ok(sub) = v.cast::<PyDict>() {
            Item::Table(table_in(sub, &here, nesting)?)
        } else if is_list_of_dicts(&v) {
            nesting.enter(&v, &here)?;
            let mut tables = ArrayOfTables::new();
            for (i, entry) in v.try_iter()?.enumerate() {
                let entry = entry?;
                let entry = entry.cast::<PyDict>()?;
                let mut row = Table::new();
                for (ek, ev) in entry.iter() {
                    let ek = key(&ek, &here)?;
                    row.insert(&ek, Item::Value(value_in(&ev, &format!("{here}[{i}].{ek}"), nesting)?));
                }
                tables.push(row);
            }
            nesting.leave();
            Item::ArrayOfTables(tables)
        } else {
            Item::Value(value_in(&v, &here, nesting)?)
        };
        t.insert(&k, item);
    }
    nesting.leave();
    Ok(t)
}

/// A dict as a TOML document.
pub fn document(d: &Bound<'_, PyDict>) -> PyResult<DocumentMut> {
    let mut doc = DocumentMut::new();
    for (k, item) in table(d, "")? {
        doc.insert(&k, item);
    }
    Ok(doc)
}

/// Where line `line` (1-based) of text written by [`document`] is, as a key path with list
/// entries by name (`hinge 'h1' law`) or position: what a dict's author can find.
pub fn path_at_line(text: &str, line: usize) -> String {
    let mut section = String::new();
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    let mut entry_name: Option<String> = None;
    let mut key = None;
    for l in text.lines().take(line) {
        let l = l.trim();
        key = None;
        if let Some(h) = l.strip_prefix("[[").and_then(|h| h.strip_suffix("]]")) {
            let n = counts.entry(h.to_string()).or_insert(0);
            section = format!("{h}[{n}]");
            *n += 1;
            entry_name = None;
        } else if let Some(h) = l.strip_prefix('[').and_then(|h| h.strip_suffix(']')) {
            section = h.to_string();
            entry_name = None;
        } else if let Some((k, v)) = l.split_once('=') {
            if k.trim() == "name" {
                entry_name = Some(v.trim().trim_matches('"').to_string());
            }
            key = Some(k.trim().to_string());
        }
    }
    let section = match (&entry_name, section.split_once('[')) {
        (Some(n), Some((list, _))) => format!("{list} '{n}'"),
        _ => section,
    };
    [section, key.unwrap_or_default()].into_iter().filter(|s| !s.is_empty()).collect::<Vec<_>>().join(" ")
}

/// A TOML value as a Python value.
pub fn to_python<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Integer(i) => i.value().into_pyobject(py)?.into_any(),
        Value::Float(x) => x.value().into_pyobject(py)?.into_any(),
        Value::Boolean(b) => PyBool::new(py, *b.value()).to_owned().into_any(),
        Value::String(s) => s.value().into_pyobject(py)?.into_any(),
        Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            let items = a.iter().map(|x| to_python(py, x)).collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::InlineTable(t) => {
            let d = PyDict::new(py);
            for (k, x) in t.iter() {
                d.set_item(k, to_python(py, x)?)?;
            }
            d.into_any()
        }
    })
}

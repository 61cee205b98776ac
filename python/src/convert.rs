//! Python values as TOML values and back: scenarios built from dicts have the structure a
//! scenario file has (docs/scenario.md), so they go through the same checks.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use toml_edit::{Array, ArrayOfTables, DocumentMut, InlineTable, Item, Table, Value};

fn bad(path: &str, what: &str) -> PyErr {
    PyValueError::new_err(format!("{path}: {what}"))
}

/// A Python value (bool, int, float, str, list or tuple, dict) as a TOML value; `path` names
/// it in errors.
pub fn value(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Value> {
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
        let mut a = Array::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            a.push(value(&item?, &format!("{path}[{i}]"))?);
        }
        return Ok(Value::Array(a));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut t = InlineTable::new();
        for (k, v) in d.iter() {
            let k = key(&k, path)?;
            t.insert(&k, value(&v, &format!("{path}.{k}"))?);
        }
        return Ok(Value::InlineTable(t));
    }
    // NumPy scalars and other numbers: anything float() takes.
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
    let mut t = Table::new();
    for (k, v) in d.iter() {
        let k = key(&k, path)?;
        let here = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
        let item = if let Ok(sub) = v.cast::<PyDict>() {
            Item::Table(table(sub, &here)?)
        } else if is_list_of_dicts(&v) {
            let mut tables = ArrayOfTables::new();
            for (i, entry) in v.try_iter()?.enumerate() {
                let entry = entry?;
                let entry = entry.cast::<PyDict>()?;
                let mut row = Table::new();
                for (ek, ev) in entry.iter() {
                    let ek = key(&ek, &here)?;
                    row.insert(&ek, Item::Value(value(&ev, &format!("{here}[{i}].{ek}"))?));
                }
                tables.push(row);
            }
            Item::ArrayOfTables(tables)
        } else {
            Item::Value(value(&v, &here)?)
        };
        t.insert(&k, item);
    }
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

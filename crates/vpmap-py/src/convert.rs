//! Values both ways: the error type `VpmapError`, JSON values to Python objects, file paths
//! and points from Python.

use std::fmt::Display;
use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

pyo3::create_exception!(
    vpmap,
    VpmapError,
    PyValueError,
    "Every error of vpmap: bad input, a scene that cannot be built, a planner out of budget. \
     A ValueError whose message is the one the vpmap command prints."
);

/// A `VpmapError` with `message`.
pub fn error(message: impl Display) -> PyErr {
    VpmapError::new_err(message.to_string())
}

/// An error and its causes, `: `-joined, as the command line prints them.
pub fn with_causes(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        text.push_str(": ");
        text.push_str(&c.to_string());
        cause = c.source();
    }
    text
}

/// A JSON value as the Python object `json.loads` would give.
pub fn json_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (key, item) in map {
                dict.set_item(key, json_to_py(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// JSON text as a Python object, by Python's `json.loads` (whose float parsing is exact, so
/// every number is the one in the text).
pub fn json_text_to_py<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.getattr("loads")?.call1((text,))
}

/// A file path: a `str` or an `os.PathLike`, through `os.fspath`; `None` for anything else.
pub fn as_path(obj: &Bound<'_, PyAny>) -> Option<PathBuf> {
    if let Ok(text) = obj.extract::<String>() {
        return Some(PathBuf::from(text));
    }
    let os = obj.py().import("os").ok()?;
    let fspath = os.getattr("fspath").ok()?.call1((obj,)).ok()?;
    fspath.extract::<String>().ok().map(PathBuf::from)
}

/// A point `(x, y)` of two numbers named `what` in messages.
pub fn point(what: &str, obj: &Bound<'_, PyAny>) -> PyResult<[f64; 2]> {
    let refuse = || {
        let shown = obj
            .repr()
            .map_or_else(|_| "?".to_owned(), |r| r.to_string());
        error(format!(
            "{what} {shown} is not a point (x, y) of two numbers"
        ))
    };
    if obj.is_instance_of::<pyo3::types::PyString>() {
        return Err(refuse());
    }
    let len = obj.len().map_err(|_| refuse())?;
    if len != 2 {
        return Err(refuse());
    }
    let x: f64 = obj
        .get_item(0)
        .and_then(|v| v.extract())
        .map_err(|_| refuse())?;
    let y: f64 = obj
        .get_item(1)
        .and_then(|v| v.extract())
        .map_err(|_| refuse())?;
    Ok([x, y])
}

/// `repr()` of a Python value for a message.
pub fn shown(obj: &Bound<'_, PyAny>) -> String {
    obj.repr()
        .map_or_else(|_| "?".to_owned(), |r| r.to_string())
}

//! Python values → [`Data`], the plain scene data that glint-scene writes as `.glint` text.

use glint_scene::native::data::Data;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// Nested dicts, lists, tuples, numbers, strings, booleans and `None` (numpy arrays and
/// scalars through their `tolist()`) as [`Data`].
///
/// # Errors
///
/// A `TypeError` naming the key path of a value that has no place in a scene.
pub fn to_data(value: &Bound<'_, PyAny>, path: &str) -> PyResult<Data> {
    if value.is_none() {
        return Ok(Data::Null);
    }
    if value.is_instance_of::<PyBool>() {
        return Ok(Data::Bool(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() || value.is_instance_of::<PyFloat>() {
        return Ok(Data::Number(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(Data::Str(value.extract()?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        return map(dict, path);
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value.try_iter()?.enumerate().map(|(i, item)| to_data(&item?, &format!("{path}[{i}]")));
        return Ok(Data::List(items.collect::<PyResult<_>>()?));
    }
    if value.hasattr("tolist")? {
        return to_data(&value.call_method0("tolist")?, path);
    }
    let type_name = value.get_type().name()?;
    let at = if path.is_empty() { String::new() } else { format!("{path}: ") };
    Err(PyTypeError::new_err(format!(
        "{at}a {type_name} has no place in a scene; use dicts, lists, numbers, strings, booleans or None"
    )))
}

/// A dict whose keys are strings, in its order.
fn map(dict: &Bound<'_, PyDict>, path: &str) -> PyResult<Data> {
    let mut entries = Vec::with_capacity(dict.len());
    for (key, value) in dict.iter() {
        let Ok(key) = key.extract::<String>() else {
            return Err(PyTypeError::new_err(format!("{path}: the key {key} is not a string")));
        };
        let child = if path.is_empty() { key.clone() } else { format!("{path}.{key}") };
        entries.push((key, to_data(&value, &child)?));
    }
    Ok(Data::Map(entries))
}

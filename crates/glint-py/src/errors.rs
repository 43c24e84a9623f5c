//! glint's located errors as Python exceptions.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pyo3::create_exception!(
    _glint,
    SceneError,
    PyValueError,
    "A scene that glint cannot read: `str(e)` is `file:line:column: message`, also in `e.file`, `e.line`, `e.column` and `e.message` (line and column 0 when the error is about a whole file; for `load_dict`, `e.file` is the key path)."
);

/// A glint-scene error as a `SceneError` carrying its location as attributes.
pub fn scene_error(py: Python<'_>, error: &glint_scene::SceneError) -> PyErr {
    let err = SceneError::new_err(error.to_string());
    let value = err.value(py);
    let kind = match error.kind {
        glint_scene::SceneErrorKind::Syntax => "syntax",
        glint_scene::SceneErrorKind::Invalid => "invalid",
        glint_scene::SceneErrorKind::Io => "io",
    };
    let attributes = [
        value.setattr("file", &error.file),
        value.setattr("line", error.line),
        value.setattr("column", error.column),
        value.setattr("message", &error.message),
        value.setattr("kind", kind),
    ];
    match attributes.into_iter().find_map(Result::err) {
        Some(failed) => failed,
        None => err,
    }
}

/// A scene that loaded but does not compile (a degenerate camera, a bad image size, …).
pub fn compile_error(error: &impl std::fmt::Display) -> PyErr {
    SceneError::new_err(error.to_string())
}

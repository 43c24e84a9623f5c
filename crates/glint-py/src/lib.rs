//! `glint._glint`: the compiled half of the `glint` Python package.
//!
//! A thin binding over glint-scene and glint-core: every scene reader, override and
//! image writer is the one the `glint` command uses, so Python and the command line give
//! the same pixels. The Python package (`python/glint`) adds progress bars, warnings and
//! the `Image` array type on top.

mod data;
mod distributed;
mod errors;
mod image;
mod render;
mod scene;
mod settings;

use pyo3::prelude::*;

/// The module object maturin imports as `glint._glint`.
#[pymodule]
fn _glint(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<errors::SceneError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_dict, m)?)?;
    m.add_function(wrap_pyfunction!(scene::default_scene, m)?)?;
    m.add_function(wrap_pyfunction!(render::render_job, m)?)?;
    m.add_class::<distributed::Job>()?;
    m.add_class::<distributed::Merger>()?;
    m.add_function(wrap_pyfunction!(distributed::prepare, m)?)?;
    m.add_function(wrap_pyfunction!(distributed::render_job_part, m)?)?;
    m.add_function(wrap_pyfunction!(distributed::_job_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(image::write, m)?)?;
    m.add_function(wrap_pyfunction!(image::read, m)?)?;
    m.add_function(wrap_pyfunction!(image::encode_png, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

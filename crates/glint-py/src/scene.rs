//! `Scene` and the ways to make one: a file of any format, plain data, the default.

use std::path::PathBuf;

use glint_core::desc::{IntegratorDesc, SceneDesc};
use glint_scene::native::data::parse_data;
use pyo3::prelude::*;

use crate::errors::scene_error;

/// A scene description, ready to render; rendering never changes it.
#[pyclass(module = "glint", frozen)]
pub struct Scene {
    pub desc: SceneDesc,
    format: &'static str,
    warnings: Vec<String>,
}

#[pymethods]
impl Scene {
    /// Image width in pixels, as the scene sets it.
    #[getter]
    fn width(&self) -> u32 {
        self.desc.settings.width
    }

    /// Image height in pixels, as the scene sets it.
    #[getter]
    fn height(&self) -> u32 {
        self.desc.settings.height
    }

    /// Samples per pixel in total: the scene's `spp`, else `samples`².
    #[getter]
    fn spp(&self) -> u32 {
        let s = &self.desc.settings;
        s.spp.unwrap_or(s.samples_per_axis.saturating_mul(s.samples_per_axis))
    }

    /// `"whitted"` or `"path"`.
    #[getter]
    fn integrator(&self) -> &'static str {
        match self.desc.settings.integrator {
            IntegratorDesc::Whitted => "whitted",
            IntegratorDesc::Path(_) => "path",
        }
    }

    /// The format the scene was read from: `"native"`, `"course-xml"`, `"course-json"`,
    /// `"challenge-yaml"`, `"mitsuba"`, `"mesh"`, `"data"` or `"default"`.
    #[getter]
    fn format(&self) -> &'static str {
        self.format
    }

    /// Harmless oddities met while reading (skipped unknown elements, …).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    fn __repr__(&self) -> String {
        let d = &self.desc;
        format!(
            "<glint.Scene {} {}x{}, {} spp, {} integrator, {} objects, {} lights>",
            self.format,
            self.width(),
            self.height(),
            self.spp(),
            self.integrator(),
            d.objects.len(),
            d.lights.len()
        )
    }
}

/// Reads a scene file of any format glint reads; a `.glint` scene's keyed properties
/// are taken at `frame`.
#[pyfunction]
#[pyo3(signature = (path, frame=0.0))]
pub fn load(py: Python<'_>, path: PathBuf, frame: f64) -> PyResult<Scene> {
    let loaded = py.detach(|| glint_scene::load_any_at(&path, frame)).map_err(|e| scene_error(py, &e))?;
    let format = match loaded.format {
        glint_scene::SceneFormat::Native => "native",
        glint_scene::SceneFormat::CourseXml => "course-xml",
        glint_scene::SceneFormat::CourseJson => "course-json",
        glint_scene::SceneFormat::ChallengeYaml => "challenge-yaml",
        glint_scene::SceneFormat::Mitsuba => "mitsuba",
        glint_scene::SceneFormat::Pbrt => "pbrt",
        glint_scene::SceneFormat::Mesh => "mesh",
    };
    Ok(Scene { desc: loaded.scene, format, warnings: loaded.warnings })
}

/// Builds a scene from plain data with the native format's names; relative file paths
/// in it are found from `base_dir`.
#[pyfunction]
pub fn load_dict(py: Python<'_>, data: &Bound<'_, PyAny>, base_dir: PathBuf) -> PyResult<Scene> {
    let data = crate::data::to_data(data, "")?;
    let desc = py.detach(|| parse_data(&data, &base_dir)).map_err(|e| scene_error(py, &e))?;
    Ok(Scene { desc, format: "data", warnings: Vec::new() })
}

/// The built-in scene the command line renders when given no file.
#[pyfunction]
pub fn default_scene() -> Scene {
    Scene { desc: glint_scene::default_scene(), format: "default", warnings: Vec::new() }
}

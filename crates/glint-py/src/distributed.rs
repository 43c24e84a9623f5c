//! What a cluster render needs from the extension: a [`Job`] (a scene with its settings
//! applied) that pickles to plain bytes, so Dask can send it to every worker once; the
//! parts a worker renders, as the bytes of a part file; and a [`Merger`] that adds them
//! up as they arrive into the very image a single render gives.

use std::path::Path;
use std::sync::OnceLock;
use std::sync::atomic::AtomicBool;

use glint_core::desc::SceneDesc;
use glint_core::render::{Part, PartMerger, render_part};
use glint_core::scene::{RenderScene, compile};
use glint_scene::part_file::{PartMeta, decode_part, encode_part};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::compile_error;
use crate::render::to_array;
use crate::scene::Scene;
use crate::settings::{MaxDepth, RenderKwargs, override_error};

/// A scene with its render settings applied, ready to be cut into parts. Compiled once
/// per process that renders a part of it (the BVH is built where it is used); pickled
/// as its description.
#[pyclass(module = "glint", frozen)]
pub struct Job {
    desc: SceneDesc,
    compiled: OnceLock<Result<RenderScene, String>>,
}

impl Job {
    fn new(desc: SceneDesc) -> Self {
        Self { desc, compiled: OnceLock::new() }
    }

    /// The compiled scene, built on first use in this process.
    pub fn scene(&self, py: Python<'_>) -> PyResult<&RenderScene> {
        let compiled = self.compiled.get_or_init(|| py.detach(|| compile(&self.desc).map_err(|e| e.to_string())));
        compiled.as_ref().map_err(compile_error)
    }

    /// How 8/16-bit outputs of this scene are encoded: `"srgb"` or `"identity"`.
    pub fn transfer(&self) -> &'static str {
        transfer_name(self.desc.settings.output_transfer)
    }

    /// The fingerprint parts carry, so parts of different jobs are never merged.
    fn meta(&self) -> PartMeta {
        PartMeta { fingerprint: self.desc.fingerprint(), transfer: self.desc.settings.output_transfer }
    }
}

#[pymethods]
impl Job {
    /// How many tiles the image has: the most parts it can be cut into.
    #[getter]
    fn tiles(&self, py: Python<'_>) -> PyResult<u32> {
        Ok(glint_core::render::tile_count(self.scene(py)?))
    }

    /// Pickles as the description's JSON (exact for every number).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let json = serde_json::to_vec(&self.desc).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        let rebuild = py.import("glint._glint")?.getattr("_job_from_json")?;
        Ok((rebuild, (PyBytes::new(py, &json),)))
    }
}

/// Rebuilds a pickled [`Job`].
#[pyfunction]
pub fn _job_from_json(json: &[u8]) -> PyResult<Job> {
    let desc: SceneDesc = serde_json::from_slice(json).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(Job::new(desc))
}

/// `scene` with `render`'s settings applied, as a [`Job`] to cut into parts.
#[pyfunction]
#[pyo3(signature = (scene, *, spp=None, width=None, height=None, integrator=None, seed=None,
    samples=None, max_depth=None, rr_depth=None, sampler=None, pattern=None, filter=None,
    filter_radius=None, adaptive=None, camera=None))]
#[allow(clippy::too_many_arguments)] // Python keyword arguments, one per command-line flag.
pub fn prepare(
    py: Python<'_>,
    scene: &Scene,
    spp: Option<u32>,
    width: Option<u32>,
    height: Option<u32>,
    integrator: Option<String>,
    seed: Option<u32>,
    samples: Option<u32>,
    max_depth: Option<MaxDepth>,
    rr_depth: Option<u32>,
    sampler: Option<String>,
    pattern: Option<String>,
    filter: Option<String>,
    filter_radius: Option<f32>,
    adaptive: Option<(u32, u32, f32)>,
    camera: Option<usize>,
) -> PyResult<Job> {
    let kwargs = RenderKwargs {
        width,
        height,
        samples,
        spp,
        integrator,
        max_depth,
        rr_depth,
        sampler,
        pattern,
        filter,
        filter_radius,
        adaptive,
        seed,
        camera,
    };
    let mut desc = scene.desc.clone();
    kwargs.overrides()?.apply(&mut desc).map_err(override_error)?;
    // Compiled here, so a scene that cannot render fails at once, and kept for a render
    // in this process.
    let job = Job::new(desc);
    job.scene(py)?;
    Ok(job)
}

/// Renders part `index` of `count` of `job` on `threads` threads (0: every core) with
/// the GIL released; returns the part as the bytes of its OpenEXR part file.
#[pyfunction]
#[pyo3(signature = (job, index, count, threads=0))]
pub fn render_job_part<'py>(
    py: Python<'py>,
    job: &Job,
    index: u32,
    count: u32,
    threads: usize,
) -> PyResult<Bound<'py, PyBytes>> {
    let scene = job.scene(py)?;
    let part = Part::new(index, count, scene).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let bytes = py.detach(|| {
        let film = pool
            .install(|| render_part(scene, part, &|_, _| {}, &AtomicBool::new(false)))
            .map_err(|e| e.to_string())?;
        encode_part(&film, job.meta())
    });
    Ok(PyBytes::new(py, &bytes.map_err(PyRuntimeError::new_err)?))
}

/// Parts of one render added up as they arrive; [`Merger::finish`] gives the image.
#[pyclass(module = "glint")]
pub struct Merger {
    merger: Option<(PartMerger, PartMeta)>,
}

#[pymethods]
impl Merger {
    #[new]
    fn new() -> Self {
        Self { merger: None }
    }

    /// Adds a part (the bytes [`render_job_part`] returned).
    fn add(&mut self, py: Python<'_>, part: &[u8]) -> PyResult<()> {
        let (film, meta) =
            py.detach(|| decode_part(part, Path::new("<part>"))).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let bad = |e: glint_core::render::PartError| PyValueError::new_err(e.to_string());
        match &mut self.merger {
            None => self.merger = Some((PartMerger::new(film), meta)),
            Some((_, expected)) if *expected != meta => {
                return Err(PyValueError::new_err("this part belongs to another render (other scene or settings)"));
            }
            Some((merger, _)) => py.detach(|| merger.add(&film)).map_err(bad)?,
        }
        Ok(())
    }

    /// Parts added, of how many.
    #[getter]
    fn progress(&self) -> (usize, usize) {
        self.merger.as_ref().map_or((0, 0), |(m, _)| m.progress())
    }

    /// The merged image as a float32 array (height, width, 3) and the output transfer,
    /// once every part is in.
    fn finish<'py>(&mut self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, &'static str)> {
        let (merger, meta) = self.merger.take().ok_or_else(|| PyValueError::new_err("no part was added"))?;
        let (image, _stats) = merger.finish().map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok((to_array(py, &image)?, transfer_name(meta.transfer)))
    }
}

fn transfer_name(transfer: glint_core::film::Transfer) -> &'static str {
    match transfer {
        glint_core::film::Transfer::Srgb => "srgb",
        glint_core::film::Transfer::Identity => "identity",
    }
}

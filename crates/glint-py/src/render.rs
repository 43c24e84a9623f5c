//! `render`: the scene traced on every core with the GIL released, Ctrl-C and progress
//! handled on the calling thread.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

use glint_core::film::Image;
use glint_core::render::RenderError;
use glint_core::scene::RenderScene;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::distributed::Job;

/// How often the waiting thread reports progress and looks for Ctrl-C.
const POLL: Duration = Duration::from_millis(50);

/// Renders `job` (a scene with its settings applied, [`crate::distributed::prepare`]);
/// returns the linear RGB pixels as a float32 array (height, width, 3) and the scene's
/// output transfer (`"srgb"` or `"identity"`) for writing 8-bit images.
/// `progress(done, total)` is called with tiles.
#[pyfunction]
#[pyo3(signature = (job, *, threads=0, progress=None))]
pub fn render_job<'py>(
    py: Python<'py>,
    job: &Job,
    threads: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, &'static str)> {
    let compiled = job.scene(py)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let image = render_waiting(py, compiled, &pool, progress.as_ref())?;
    Ok((to_array(py, &image)?, job.transfer()))
}

/// Traces on `pool` in a scoped thread while this thread, every [`POLL`], takes the GIL
/// briefly to report progress and run Python's signal handlers; an exception from
/// either (KeyboardInterrupt) cancels the render between tiles and is raised.
fn render_waiting(
    py: Python<'_>,
    scene: &RenderScene,
    pool: &rayon::ThreadPool,
    progress: Option<&Py<PyAny>>,
) -> PyResult<Image> {
    let cancel = AtomicBool::new(false);
    let (done, total) = (AtomicUsize::new(0), AtomicUsize::new(glint_core::render::tile_count(scene) as usize));
    let on_tile = |d: usize, t: usize| {
        done.fetch_max(d, Ordering::Relaxed);
        total.store(t, Ordering::Relaxed);
    };
    let mut raised = None;
    let result = py.detach(|| {
        std::thread::scope(|s| {
            let worker = s.spawn(|| pool.install(|| glint_core::render::render(scene, &on_tile, &cancel)));
            let mut reported = usize::MAX;
            loop {
                let finished = worker.is_finished();
                if raised.is_none() {
                    let now = (done.load(Ordering::Relaxed), total.load(Ordering::Relaxed));
                    raised = Python::attach(|py| poll(py, progress, now, &mut reported)).err();
                    if raised.is_some() {
                        cancel.store(true, Ordering::Relaxed);
                    }
                }
                if finished {
                    break;
                }
                std::thread::park_timeout(POLL);
            }
            worker.join()
        })
    });
    if let Some(error) = raised {
        return Err(error);
    }
    match result {
        Ok(Ok((image, _stats))) => Ok(image),
        Ok(Err(RenderError::Cancelled)) => Err(PyRuntimeError::new_err("render cancelled")),
        Err(_) => Err(PyRuntimeError::new_err("the render panicked; this is a bug in glint")),
    }
}

/// Runs Python's signal handlers and reports new progress as `progress(done, total)`.
fn poll(
    py: Python<'_>,
    progress: Option<&Py<PyAny>>,
    (done, total): (usize, usize),
    reported: &mut usize,
) -> PyResult<()> {
    py.check_signals()?;
    if let Some(callback) = progress.filter(|_| done != *reported) {
        *reported = done;
        callback.call1(py, (done, total))?;
    }
    Ok(())
}

/// The pixels as a float32 array of shape (height, width, 3), row 0 at the top.
pub fn to_array<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = image.pixels.iter().flat_map(|p| p.to_array()).collect();
    let shape = [image.height as usize, image.width as usize, 3];
    Ok(PyArray1::from_vec(py, flat).reshape(shape)?.into_any())
}

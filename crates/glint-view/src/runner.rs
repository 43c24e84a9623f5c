//! Where the viewer's passes run: previews and debug pictures on the CPU, one-sample
//! passes on the GPU when the viewer was given one. The GPU keeps the uploaded scene and
//! its compiled kernels across camera moves and accumulates the samples of a still view
//! itself, so a pass there costs one dispatch and one read-back.

use std::sync::PoisonError;
use std::time::Instant;

use glint_gpu::{Gpu, GpuError, Progressive};

use crate::pass::{Finished, Job, PassKind, run};

/// Runs [`Job`]s; holds the GPU render of the current view between passes.
pub struct Runner {
    gpu: Option<GpuRender>,
}

/// The GPU and the render of one view on it.
struct GpuRender {
    gpu: &'static Gpu,
    /// The render, with the scene version and the view (generation) it holds samples of.
    current: Option<(u64, u64, Progressive<'static>)>,
}

impl Runner {
    /// A runner that uses `gpu` for one-sample passes, or the CPU for all.
    pub fn new(gpu: Option<&'static Gpu>) -> Self {
        Self { gpu: gpu.map(|gpu| GpuRender { gpu, current: None }) }
    }

    /// Runs `job`; `None` when it was cancelled. A sample pass the GPU cannot run (a
    /// reloaded scene its driver cannot run, a device error) runs on the CPU and says
    /// why in the result's note.
    pub fn run(&mut self, job: &Job) -> Option<Finished> {
        let (PassKind::Sample(index), Some(gpu)) = (job.kind, self.gpu.as_mut()) else {
            return run(job);
        };
        let start = Instant::now();
        match gpu.sample(job, index) {
            Ok((image, samples)) => Some(Finished {
                generation: job.generation,
                kind: job.kind,
                image,
                rays: 0,
                elapsed: start.elapsed(),
                mean_of: Some(samples),
                on_gpu: true,
                note: None,
            }),
            Err(e) => {
                gpu.current = None;
                let mut finished = run(job)?;
                finished.note = Some(format!("this pass ran on the CPU: {e}"));
                Some(finished)
            }
        }
    }
}

impl GpuRender {
    /// Adds sample `index` of the job's view to the GPU's film and returns the mean of
    /// all its samples so far, and their number; a new view restarts the film, a new
    /// scene, size or integrator makes a new render.
    fn sample(&mut self, job: &Job, index: u32) -> Result<(glint_core::film::Image, u32), GpuError> {
        let mut scene = job.scene.lock().unwrap_or_else(PoisonError::into_inner);
        scene.camera = job.camera;
        scene.settings = job.settings.clone();
        // The viewer seeds each CPU pass by its index; the GPU draws sample `index` of
        // one seed instead, so its passes keep the first pass's seed.
        scene.settings.seed = scene.settings.seed.wrapping_sub(index);
        let continues = matches!(&self.current, Some((version, generation, render))
            if *version == job.scene_version && *generation == job.generation && render.samples_done() == index);
        if !continues {
            let reused = match &mut self.current {
                Some((version, _, render)) if *version == job.scene_version => render.restart(&scene)?,
                _ => false,
            };
            if !reused {
                self.current = None;
                self.current = Some((job.scene_version, job.generation, Progressive::new(self.gpu, &scene)?));
            }
            if let Some((_, generation, _)) = &mut self.current {
                *generation = job.generation;
            }
        }
        let (_, _, render) = self.current.as_mut().expect("a render was made above");
        render.add_samples(1)?;
        Ok((render.image()?, render.samples_done()))
    }
}

//! One unit of the viewer's work: a quick subsampled preview, one sample per pixel,
//! or a debug picture. A pass is a pure function of the scene, camera and settings it
//! carries, so it can run on any thread and be thrown away when the view has moved on.

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use glint_core::camera::Camera;
use glint_core::film::Image;
use glint_core::render::inspect::{DebugView, debug_image};
use glint_core::render::{render, render_preview};
use glint_core::scene::{RenderScene, Settings};

/// What a pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassKind {
    /// One sample per `block`×`block` pixels: a picture at once after any change.
    Preview(u32),
    /// One sample per pixel; pass `index` seeds its random numbers, so passes are
    /// independent estimates that average toward the converged image.
    Sample(u32),
    /// A picture of a property of the first hits.
    Debug(DebugView),
}

/// A pass to run: the view it was asked for travels with it, as does the flag that
/// abandons it.
#[derive(Clone)]
pub struct Job {
    /// Which state of the view this pass draws; results of older ones are dropped.
    pub generation: u64,
    /// Which scene (counting reloads) the pass draws: a GPU render is of one scene.
    pub scene_version: u64,
    pub kind: PassKind,
    pub camera: Camera,
    pub settings: Settings,
    pub scene: Arc<Mutex<RenderScene>>,
    pub cancel: Arc<AtomicBool>,
}

/// A finished pass.
pub struct Finished {
    pub generation: u64,
    pub kind: PassKind,
    pub image: Image,
    /// Rays traced (0 where the pass does not count them: previews, debug views, the
    /// GPU).
    pub rays: u64,
    pub elapsed: Duration,
    /// `Some(n)`: the image is already the mean of the view's first `n` sample passes
    /// (the GPU accumulates them itself); `None`: it is this pass alone.
    pub mean_of: Option<u32>,
    /// The pass ran on the GPU.
    pub on_gpu: bool,
    /// Something the user should know about this pass (it fell back to the CPU).
    pub note: Option<String>,
}

/// Runs `job` on the current rayon pool; `None` when it was cancelled.
pub fn run(job: &Job) -> Option<Finished> {
    let start = Instant::now();
    let mut scene = job.scene.lock().unwrap_or_else(PoisonError::into_inner);
    scene.camera = job.camera;
    scene.settings = job.settings.clone();
    let (image, rays) = match job.kind {
        PassKind::Preview(block) => (render_preview(&scene, block), 0),
        PassKind::Debug(view) => (debug_image(&scene, view), 0),
        PassKind::Sample(_) => {
            let (image, stats) = render(&scene, &|_, _| {}, &job.cancel).ok()?;
            (image, stats.rays)
        }
    };
    Some(Finished {
        generation: job.generation,
        kind: job.kind,
        image,
        rays,
        elapsed: start.elapsed(),
        mean_of: None,
        on_gpu: false,
        note: None,
    })
}

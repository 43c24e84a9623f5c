//! The viewer without a window: camera, toggles, the pass schedule and the running
//! average of samples. A front end feeds it [`Input`]s, runs the [`Job`]s it hands out
//! (on any thread) and shows what [`Viewer::image`] holds; the headless mode and the
//! tests drive it the same way, one pass at a time.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use glam::Vec3;
use glint_core::camera::Camera;
use glint_core::desc::{IntegratorDesc, PathDesc, SceneDesc};
use glint_core::film::Image;
use glint_core::integrator::observe::RayTree;
use glint_core::math::Aabb;
use glint_core::render::inspect::{DebugView, explain_pixel};
use glint_core::sampling::{PixelSampler, SamplePattern};
use glint_core::scene::{RenderScene, Settings, compile};
use glint_scene::image_out::{OutputFormat, write_image};

use crate::camera::OrbitCamera;
use crate::pass::{Finished, Job, PassKind};
use crate::runner::Runner;

/// The first preview's block size: 1/64 of the samples, so it is there at once.
const FIRST_BLOCK: u32 = 8;
/// Accumulation stops here: the image no longer changes visibly.
pub const MAX_PASSES: u32 = 1024;
/// Wheel step: each notch brings the eye this much closer.
const ZOOM_PER_STEP: f32 = 0.85;
/// Narrowest and widest view angles the fov keys reach, degrees.
const FOV_RANGE: (f32, f32) = (5.0, 150.0);

/// Something the user did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Input {
    /// A drag of (dx, dy) pixels that turns the camera about its target.
    Orbit {
        dx: f32,
        dy: f32,
    },
    /// A drag of (dx, dy) pixels that slides the camera: the scene follows the cursor.
    Pan {
        dx: f32,
        dy: f32,
    },
    /// Wheel notches, positive toward the scene.
    Zoom(f32),
    /// Fly for `seconds` along camera axes (x right, y up, z forward) at the speed of
    /// one scene diameter per second.
    Fly {
        direction: Vec3,
        seconds: f32,
    },
    /// Back to the scene file's camera.
    Reset,
    /// Look at everything from the current direction.
    Frame,
    /// Widen (positive) or narrow the view angle, degrees.
    Fov(f32),
    Toggle(Toggle),
    /// Raise or lower the depth limit.
    MaxDepth(i32),
    /// Cycle beauty → each debug view → beauty.
    NextView,
    /// Trace pixel (x, y)'s ray tree and show it.
    Explain {
        x: u32,
        y: u32,
    },
    /// Hide the explained ray tree.
    ClearExplain,
    /// The window's size in pixels: the image is rendered at it.
    Resize {
        width: u32,
        height: u32,
    },
}

/// Effects and helpers that switch on and off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Toggle {
    /// Whitted ↔ path tracing.
    Integrator,
    Shadows,
    Reflections,
    Refractions,
    /// A random position in the pixel per pass (on) or its centre (off).
    AntiAliasing,
    Hud,
}

/// The switches the user controls on top of the scene's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Toggles {
    pub path: bool,
    pub shadows: bool,
    pub reflections: bool,
    pub refractions: bool,
    pub anti_aliasing: bool,
    pub max_depth: u32,
    pub hud: bool,
}

/// What the image shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewMode {
    Beauty,
    Debug(DebugView),
}

/// The views [`Input::NextView`] steps through, in order.
const VIEWS: [ViewMode; 7] = [
    ViewMode::Beauty,
    ViewMode::Debug(DebugView::Normal),
    ViewMode::Debug(DebugView::Depth),
    ViewMode::Debug(DebugView::Uv),
    ViewMode::Debug(DebugView::Albedo),
    ViewMode::Debug(DebugView::TraversalCost),
    ViewMode::Debug(DebugView::RecursionDepth),
];

/// Timing of the latest passes, for the HUD and the benchmark.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// Duration of the latest pass of any kind.
    pub last_pass: Duration,
    /// Rays per second of the latest one-sample-per-pixel pass (0 on the GPU, which
    /// does not count them).
    pub rays_per_second: f64,
    /// The latest one-sample-per-pixel pass ran on the GPU.
    pub on_gpu: bool,
}

/// A pixel's ray tree, shown over the image until cleared.
#[derive(Clone, Debug)]
pub struct Explained {
    pub x: u32,
    pub y: u32,
    pub tree: RayTree,
    /// The camera that traced it: the overlay projects the rays with it.
    pub camera: Camera,
}

/// The whole state of a viewer session.
pub struct Viewer {
    desc: SceneDesc,
    scene: Arc<Mutex<RenderScene>>,
    /// Counts reloads: a GPU render is of one version of the scene.
    scene_version: u64,
    /// The GPU that runs sample passes, if the viewer was given one.
    gpu: Option<&'static glint_gpu::Gpu>,
    /// Runs [`Viewer::step`]'s passes (the window runs its own, on its render thread).
    runner: Runner,
    /// The compiled scene's own settings, before the toggles apply.
    base: Settings,
    bounds: Aabb,
    camera: OrbitCamera,
    toggles: Toggles,
    view: ViewMode,
    size: (u32, u32),
    generation: u64,
    cancel: Arc<AtomicBool>,
    next: Option<PassKind>,
    in_flight: bool,
    sum: Vec<Vec3>,
    passes: u32,
    image: Image,
    timing: Timing,
    error: Option<String>,
    status: Option<String>,
    explained: Option<Explained>,
}

impl Viewer {
    /// A viewer of `desc`, rendered at `size` (the scene's own size when `None`).
    ///
    /// # Errors
    ///
    /// The compiler's message when the scene cannot be rendered.
    pub fn new(mut desc: SceneDesc, size: Option<(u32, u32)>) -> Result<Self, String> {
        if let Some((width, height)) = size {
            (desc.settings.width, desc.settings.height) = (width, height);
        }
        let scene = compile(&desc).map_err(|e| e.to_string())?;
        let base = scene.settings.clone();
        let bounds = scene.bvh.bounds();
        let toggles = Toggles {
            path: matches!(base.integrator, IntegratorDesc::Path(_)),
            shadows: base.features.shadows,
            reflections: base.features.reflections,
            refractions: base.features.refractions,
            anti_aliasing: true,
            max_depth: base.max_depth,
            hud: true,
        };
        let mut viewer = Self {
            camera: OrbitCamera::from_desc(&desc.camera, &bounds),
            size: (base.width, base.height),
            image: Image::new(base.width, base.height),
            desc,
            scene: Arc::new(Mutex::new(scene)),
            scene_version: 0,
            gpu: None,
            runner: Runner::new(None),
            base,
            bounds,
            toggles,
            view: ViewMode::Beauty,
            generation: 0,
            cancel: Arc::new(AtomicBool::new(false)),
            next: None,
            in_flight: false,
            sum: Vec::new(),
            passes: 0,
            timing: Timing::default(),
            error: None,
            status: None,
            explained: None,
        };
        viewer.restart();
        Ok(viewer)
    }

    /// Runs the one-sample passes on `gpu` from now on (previews, debug views and
    /// explanations stay on the CPU), or all passes on the CPU with `None`.
    pub fn use_gpu(&mut self, gpu: Option<&'static glint_gpu::Gpu>) {
        self.gpu = gpu;
        self.runner = Runner::new(gpu);
        self.restart();
    }

    /// The GPU sample passes run on, if any: a front end's own [`Runner`] takes it.
    pub fn gpu(&self) -> Option<&'static glint_gpu::Gpu> {
        self.gpu
    }

    /// Applies `input`; anything that changes the picture abandons the pass in flight
    /// and starts again from a preview.
    pub fn handle(&mut self, input: Input) {
        let changes_picture = match input {
            Input::Toggle(Toggle::Hud) => {
                self.toggles.hud = !self.toggles.hud;
                false
            }
            Input::Explain { x, y } => {
                self.explain(x, y);
                false
            }
            Input::ClearExplain => {
                self.explained = None;
                false
            }
            Input::Toggle(toggle) => {
                self.toggle(toggle);
                true
            }
            other => self.move_or_resize(other),
        };
        if changes_picture {
            self.restart();
        }
    }

    /// Camera moves, depth, view and size changes; `true` when the picture changed.
    fn move_or_resize(&mut self, input: Input) -> bool {
        let height = self.size.1 as f32;
        match input {
            Input::Orbit { dx, dy } => {
                // A drag across the window's height turns the camera half a circle.
                let per_pixel = std::f32::consts::PI / height;
                self.camera.orbit(-dx * per_pixel, dy * per_pixel);
            }
            Input::Pan { dx, dy } => {
                let per_pixel = self.camera.film_height_at_target(self.tan_half_vertical()) / height;
                self.camera.pan(-dx * per_pixel, dy * per_pixel);
            }
            Input::Zoom(steps) => self.camera.zoom(ZOOM_PER_STEP.powf(steps)),
            Input::Fly { direction, seconds } => self.camera.fly(direction * self.scene_diameter() * seconds),
            Input::Reset => self.camera = OrbitCamera::from_desc(&self.desc.camera, &self.bounds),
            Input::Frame => self.camera.frame(&self.bounds, self.tan_half_narrower()),
            Input::Fov(degrees) => {
                self.camera.fov_degrees = (self.camera.fov_degrees + degrees).clamp(FOV_RANGE.0, FOV_RANGE.1)
            }
            Input::MaxDepth(change) => {
                self.toggles.max_depth = self.toggles.max_depth.saturating_add_signed(change).min(64)
            }
            Input::NextView => {
                let at = VIEWS.iter().position(|&v| v == self.view).unwrap_or(0);
                self.view = VIEWS[(at + 1) % VIEWS.len()];
            }
            Input::Resize { width, height } => {
                let size = (width.max(1), height.max(1));
                if size == self.size {
                    return false;
                }
                self.size = size;
            }
            _ => return false,
        }
        true
    }

    fn toggle(&mut self, toggle: Toggle) {
        let t = &mut self.toggles;
        match toggle {
            Toggle::Integrator => t.path = !t.path,
            Toggle::Shadows => t.shadows = !t.shadows,
            Toggle::Reflections => t.reflections = !t.reflections,
            Toggle::Refractions => t.refractions = !t.refractions,
            Toggle::AntiAliasing => t.anti_aliasing = !t.anti_aliasing,
            Toggle::Hud => t.hud = !t.hud,
        }
    }

    /// A new view: new generation, the old pass cancelled, the schedule from the top.
    /// The last image stays on screen until the first new one replaces it.
    fn restart(&mut self) {
        self.generation += 1;
        self.cancel.store(true, Ordering::Relaxed);
        self.cancel = Arc::new(AtomicBool::new(false));
        self.passes = 0;
        self.next = Some(match self.view {
            ViewMode::Beauty => PassKind::Preview(FIRST_BLOCK),
            ViewMode::Debug(view) => PassKind::Debug(view),
        });
    }

    /// The next pass to run, if the schedule has one and no pass is in flight; the
    /// caller runs it and hands the result to [`Viewer::finish`].
    pub fn next_job(&mut self) -> Option<Job> {
        if self.in_flight {
            return None;
        }
        let kind = self.next?;
        let camera = self.render_camera()?;
        self.in_flight = true;
        Some(Job {
            generation: self.generation,
            scene_version: self.scene_version,
            kind,
            camera,
            settings: self.pass_settings(kind),
            scene: Arc::clone(&self.scene),
            cancel: Arc::clone(&self.cancel),
        })
    }

    /// Takes a pass's result (`None`: it was cancelled) and schedules the next;
    /// returns the kind of pass now shown, `None` when the result was stale.
    pub fn finish(&mut self, finished: Option<Finished>) -> Option<PassKind> {
        self.in_flight = false;
        let done = finished.filter(|f| f.generation == self.generation)?;
        self.timing.last_pass = done.elapsed;
        if let Some(note) = done.note {
            self.status = Some(note);
        }
        let shown = done.kind;
        self.next = match done.kind {
            PassKind::Preview(block) => {
                self.image = done.image;
                Some(if block > 2 { PassKind::Preview(block / 2) } else { PassKind::Sample(0) })
            }
            PassKind::Debug(_) => {
                self.image = done.image;
                None
            }
            PassKind::Sample(index) => {
                self.timing.rays_per_second = done.rays as f64 / done.elapsed.as_secs_f64().max(1e-9);
                self.timing.on_gpu = done.on_gpu;
                match done.mean_of {
                    Some(passes) => (self.image, self.passes) = (done.image, passes),
                    None => self.accumulate(&done.image),
                }
                (self.keeps_accumulating() && index + 1 < MAX_PASSES).then_some(PassKind::Sample(index + 1))
            }
        };
        Some(shown)
    }

    /// Runs the next pass on this thread; `false` when there is none (converged, or
    /// one is in flight elsewhere).
    pub fn step(&mut self) -> bool {
        let Some(job) = self.next_job() else { return false };
        let finished = self.runner.run(&job);
        self.finish(finished);
        true
    }

    /// Adds a one-sample pass to the running mean and shows the mean.
    fn accumulate(&mut self, pass: &Image) {
        if self.passes == 0 || self.sum.len() != pass.pixels.len() {
            self.sum = pass.pixels.clone();
            self.passes = 1;
        } else {
            self.sum.iter_mut().zip(&pass.pixels).for_each(|(s, p)| *s += *p);
            self.passes += 1;
        }
        let scale = 1.0 / self.passes as f32;
        let pixels = self.sum.iter().map(|s| *s * scale).collect();
        self.image = Image { width: pass.width, height: pass.height, pixels };
    }

    /// More passes change the image only when each draws different random numbers:
    /// jittered pixel positions or path tracing.
    fn keeps_accumulating(&self) -> bool {
        self.toggles.anti_aliasing || self.toggles.path
    }

    /// The scene's settings with the toggles, the window's size and pass `kind`'s
    /// seed: one sample per pixel.
    pub fn pass_settings(&self, kind: PassKind) -> Settings {
        let t = &self.toggles;
        let mut s = self.base.clone();
        (s.width, s.height) = self.size;
        s.features.shadows = t.shadows;
        s.features.reflections = t.reflections;
        s.features.refractions = t.refractions;
        s.max_depth = t.max_depth;
        s.integrator = match (t.path, self.base.integrator) {
            (false, _) => IntegratorDesc::Whitted,
            // Mitsuba counts depth from the emitter: 2 is direct light, as Whitted's 0.
            (true, IntegratorDesc::Path(p)) => IntegratorDesc::Path(PathDesc { max_depth: t.max_depth + 2, ..p }),
            (true, IntegratorDesc::Whitted) => {
                IntegratorDesc::Path(PathDesc { max_depth: t.max_depth + 2, ..PathDesc::default() })
            }
        };
        (s.samples_per_axis, s.spp, s.adaptive) = (1, 1, None);
        let index = if let PassKind::Sample(i) = kind { i } else { 0 };
        s.seed = self.base.seed.wrapping_add(index);
        let pattern = if t.anti_aliasing { SamplePattern::Jittered } else { SamplePattern::Grid };
        s.sampler = PixelSampler { pattern, per_axis: 1, seed: s.seed };
        // Accumulated passes are one image's samples: pass k narrows filtered textures'
        // footprint as k samples per pixel would, so the sum converges to what `glint
        // render` gives with many samples, and the first pass alone shows no moiré.
        s.footprint_scale = if t.anti_aliasing { glint_core::footprint::footprint_scale(index + 1) } else { 1.0 };
        s
    }

    /// The core camera for the current view; `None` if the orbit degenerated.
    pub fn render_camera(&self) -> Option<Camera> {
        Camera::new(&self.camera.to_desc(&self.desc.camera), self.aspect())
    }

    fn aspect(&self) -> f32 {
        self.size.0 as f32 / self.size.1 as f32
    }

    fn tan_half_vertical(&self) -> f32 {
        self.desc.camera.fov_axis.tan_half_vertical(self.camera.fov_degrees, self.aspect())
    }

    /// tan of half the narrower of the two view angles.
    fn tan_half_narrower(&self) -> f32 {
        let vertical = self.tan_half_vertical();
        vertical.min(vertical * self.aspect())
    }

    /// The diagonal of everything bounded (1 for a scene of planes alone).
    fn scene_diameter(&self) -> f32 {
        let diagonal = (self.bounds.max - self.bounds.min).length();
        if diagonal.is_finite() && diagonal > 0.0 { diagonal } else { 1.0 }
    }

    /// Traces pixel (x, y)'s Whitted ray tree through its centre, with the current
    /// camera and toggles, and keeps it for the overlay.
    pub fn explain(&mut self, x: u32, y: u32) -> Option<&Explained> {
        let camera = self.render_camera()?;
        let (x, y) = (x.min(self.size.0 - 1), y.min(self.size.1 - 1));
        let mut settings = self.pass_settings(PassKind::Sample(0));
        settings.integrator = IntegratorDesc::Whitted;
        settings.sampler.pattern = SamplePattern::Grid;
        let tree = {
            let mut scene = self.scene.lock().unwrap_or_else(PoisonError::into_inner);
            (scene.camera, scene.settings) = (camera, settings);
            explain_pixel(&scene, x, y)
        };
        self.explained = Some(Explained { x, y, tree, camera });
        self.explained.as_ref()
    }

    /// Takes a freshly loaded scene (keeping camera and toggles), or shows why the file
    /// could not be loaded and keeps the last good scene and image.
    pub fn reload(&mut self, loaded: Result<SceneDesc, String>) {
        let compiled = loaded.and_then(|mut desc| {
            (desc.settings.width, desc.settings.height) = self.size;
            compile(&desc).map(|scene| (desc, scene)).map_err(|e| e.to_string())
        });
        match compiled {
            Ok((desc, scene)) => {
                self.cancel.store(true, Ordering::Relaxed);
                self.base = scene.settings.clone();
                self.bounds = scene.bvh.bounds();
                *self.scene.lock().unwrap_or_else(PoisonError::into_inner) = scene;
                self.desc = desc;
                self.scene_version += 1;
                self.error = None;
                self.explained = None;
                self.restart();
            }
            Err(message) => self.error = Some(message),
        }
    }

    /// Writes the image (without HUD) to `path`, in the format its extension names
    /// (PNG when it names none), and says so in the status line.
    ///
    /// # Errors
    ///
    /// The writer's message.
    pub fn save(&mut self, path: &Path) -> Result<(), String> {
        let format = OutputFormat::from_path(path).unwrap_or(OutputFormat::Png8);
        let written = write_image(&self.image, path, format, self.desc.settings.output_transfer);
        self.status = Some(match &written {
            Ok(()) => format!("saved {}", path.display()),
            Err(e) => e.to_string(),
        });
        written.map_err(|e| e.to_string())
    }

    /// What the window shows: the latest preview, the running mean or a debug view.
    pub fn image(&self) -> &Image {
        &self.image
    }

    /// One-sample passes averaged into the image so far.
    pub fn passes(&self) -> u32 {
        self.passes
    }

    /// True while passes remain to be run (or one is in flight).
    pub fn busy(&self) -> bool {
        self.next.is_some() || self.in_flight
    }

    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }

    pub fn toggles(&self) -> &Toggles {
        &self.toggles
    }

    pub fn view(&self) -> ViewMode {
        self.view
    }

    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    pub fn timing(&self) -> Timing {
        self.timing
    }

    /// The message of the last failed reload, while it lasts.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// The latest note for the user (a saved file, a write error).
    pub fn status(&self) -> Option<&str> {
        self.status.as_deref()
    }

    pub fn explained(&self) -> Option<&Explained> {
        self.explained.as_ref()
    }

    /// The scene as loaded last: material names for explanations.
    pub fn desc(&self) -> &SceneDesc {
        &self.desc
    }

    /// The compiled scene, shared with the pass in flight.
    pub fn scene(&self) -> &Arc<Mutex<RenderScene>> {
        &self.scene
    }
}

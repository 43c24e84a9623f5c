//! The window: winit turns the user's actions into [`Input`]s for the viewer, the
//! render thread runs its passes, and [`Presenter`] shows each new picture. Nothing here
//! decides anything; the [`Viewer`] does.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, EventLoopProxy};
use winit::keyboard::{KeyCode, ModifiersState, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::draw::{Canvas, compose};
use crate::pass::Finished;
use crate::present::Presenter;
use crate::viewer::{Input, Toggle, Viewer};
use crate::watch::Watcher;
use crate::worker::Worker;

/// How often the scene's files are checked for changes.
const POLL_EVERY: Duration = Duration::from_millis(200);
/// A press that moves less than this many pixels is a click (explain), not a drag.
const CLICK_SLOP: f32 = 3.0;
/// Fly steps while a fly key is held: about 60 a second.
const FLY_TICK: Duration = Duration::from_millis(16);

/// Where the window's files come from and go to.
pub struct Files {
    /// The scene file, watched and reloaded (none for the built-in scene).
    pub scene: Option<PathBuf>,
    /// Where `S` saves (and `Shift+S` the same name as .exr).
    pub output: PathBuf,
}

/// Opens the window and runs until it is closed.
///
/// # Errors
///
/// Why no window could be opened (no display, for one).
pub fn run(viewer: Viewer, files: Files) -> Result<(), String> {
    let event_loop = EventLoop::<Option<Finished>>::with_user_event().build().map_err(|e| no_window(&e))?;
    let proxy: EventLoopProxy<Option<Finished>> = event_loop.create_proxy();
    let worker = Worker::spawn(crate::runner::Runner::new(viewer.gpu()), move |done| {
        let _ = proxy.send_event(done);
    });
    let watcher = files.scene.as_deref().map(|s| Watcher::new(s, Some(viewer.desc())));
    let mut app = App {
        viewer,
        files,
        worker,
        watcher,
        next_poll: Instant::now() + POLL_EVERY,
        window: None,
        presenter: None,
        frame: Vec::new(),
        mouse: Mouse::default(),
        keys: HashSet::new(),
        modifiers: ModifiersState::empty(),
        last_fly: Instant::now(),
        failure: None,
    };
    event_loop.run_app(&mut app).map_err(|e| no_window(&e))?;
    app.failure.map_or(Ok(()), Err)
}

fn no_window(e: &dyn std::fmt::Display) -> String {
    format!("cannot open a window ({e}); is DISPLAY set? `glint view --no-window` renders without one")
}

/// The buttons held and where the cursor was.
#[derive(Default)]
struct Mouse {
    at: Vec2,
    /// Where the held button went down, and whether it has moved enough to be a drag.
    pressed: Option<(MouseButton, Vec2, bool)>,
    right_held: bool,
}

struct App {
    viewer: Viewer,
    files: Files,
    worker: Worker,
    watcher: Option<Watcher>,
    next_poll: Instant,
    window: Option<Window>,
    presenter: Option<Presenter>,
    /// The picture scaled to the window, where their sizes differ.
    frame: Vec<u32>,
    mouse: Mouse,
    keys: HashSet<KeyCode>,
    modifiers: ModifiersState,
    last_fly: Instant,
    failure: Option<String>,
}

impl ApplicationHandler<Option<Finished>> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        if let Err(e) = self.open(event_loop) {
            self.failure = Some(e);
            event_loop.exit();
        }
    }

    fn user_event(&mut self, _: &ActiveEventLoop, finished: Option<Finished>) {
        self.viewer.finish(finished);
        self.dispatch();
        self.redraw();
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => self.present(),
            WindowEvent::Resized(size) => self.input(Input::Resize { width: size.width, height: size.height }),
            WindowEvent::ModifiersChanged(m) => self.modifiers = m.state(),
            WindowEvent::CursorMoved { position, .. } => self.cursor(Vec2::new(position.x as f32, position.y as f32)),
            WindowEvent::MouseInput { state, button, .. } => self.button(button, state),
            WindowEvent::MouseWheel { delta, .. } => self.input(Input::Zoom(match delta {
                MouseScrollDelta::LineDelta(_, y) => y,
                MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
            })),
            WindowEvent::KeyboardInput { event, .. } => self.key(event_loop, &event),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        if now >= self.next_poll {
            self.next_poll = now + POLL_EVERY;
            self.poll_files();
        }
        let flying = self.fly(now);
        let wake = if flying { now + FLY_TICK } else { self.next_poll };
        event_loop.set_control_flow(ControlFlow::WaitUntil(wake));
    }
}

impl App {
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let (width, height) = self.viewer.size();
        let name = self.files.scene.as_deref().map_or("default scene".into(), |p| p.display().to_string());
        let attributes = Window::default_attributes()
            .with_title(format!("glint view - {name}"))
            .with_inner_size(winit::dpi::PhysicalSize::new(width, height));
        let window = event_loop.create_window(attributes).map_err(|e| no_window(&e))?;
        self.presenter = Some(Presenter::new(&window).map_err(|e| no_window(&e))?);
        self.window = Some(window);
        self.dispatch();
        Ok(())
    }

    /// Hands the viewer's next pass to the render thread, if it has one.
    fn dispatch(&mut self) {
        if let Some(job) = self.viewer.next_job() {
            self.worker.send(job);
        }
    }

    fn input(&mut self, input: Input) {
        self.viewer.handle(input);
        if let (Input::Explain { .. }, Some(explained)) = (input, self.viewer.explained()) {
            let scene = self.viewer.scene().lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            print!(
                "{}",
                crate::explain::describe(&explained.tree, (explained.x, explained.y), &scene, self.viewer.desc())
            );
        }
        self.dispatch();
        self.redraw();
    }

    fn redraw(&self) {
        if let Some(window) = &self.window {
            window.request_redraw();
        }
    }

    /// Shows the composed picture, scaled to the window if their sizes differ (for the
    /// moment between a resize and the first pass at the new size).
    fn present(&mut self) {
        let (Some(window), Some(presenter)) = (&self.window, &self.presenter) else { return };
        let size = window.inner_size();
        let (width, height) = (size.width, size.height);
        if width == 0 || height == 0 {
            return;
        }
        let canvas = compose(&self.viewer);
        let pixels = if (canvas.width, canvas.height) == (width, height) {
            &canvas.pixels
        } else {
            self.frame.resize(width as usize * height as usize, 0);
            blit(&canvas, &mut self.frame, width, height);
            &self.frame
        };
        // Only a lost connection fails here (the server's complaints are read and
        // dropped): the window then stays as it is, as softbuffer left it.
        let _ = presenter.show(pixels, width, height);
    }

    fn cursor(&mut self, at: Vec2) {
        let delta = at - self.mouse.at;
        self.mouse.at = at;
        let Some((button, from, dragging)) = &mut self.mouse.pressed else { return };
        if !*dragging && at.distance(*from) < CLICK_SLOP {
            return;
        }
        *dragging = true;
        let pan = *button != MouseButton::Left || self.modifiers.shift_key();
        let (dx, dy) = (delta.x, delta.y);
        self.input(if pan { Input::Pan { dx, dy } } else { Input::Orbit { dx, dy } });
    }

    fn button(&mut self, button: MouseButton, state: ElementState) {
        if button == MouseButton::Right {
            self.mouse.right_held = state == ElementState::Pressed;
        }
        match state {
            ElementState::Pressed => self.mouse.pressed = Some((button, self.mouse.at, false)),
            ElementState::Released => {
                let click = matches!(self.mouse.pressed, Some((MouseButton::Left, _, false)));
                self.mouse.pressed = None;
                if click && button == MouseButton::Left {
                    let (x, y) = (self.mouse.at.x.max(0.0) as u32, self.mouse.at.y.max(0.0) as u32);
                    self.input(Input::Explain { x, y });
                }
            }
        }
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent) {
        let PhysicalKey::Code(code) = event.physical_key else { return };
        if event.state == ElementState::Released {
            self.keys.remove(&code);
            return;
        }
        self.keys.insert(code);
        if fly_direction(code).is_some() && self.mouse.right_held {
            return;
        }
        match code {
            KeyCode::KeyS => self.save(self.modifiers.shift_key()),
            KeyCode::Escape if self.viewer.explained().is_none() => event_loop.exit(),
            code => {
                if let Some(input) = key_input(code) {
                    self.input(input);
                }
            }
        }
    }

    /// `S`: the image as --output names it; `Shift+S`: the same name as OpenEXR.
    fn save(&mut self, exr: bool) {
        let path = if exr { self.files.output.with_extension("exr") } else { self.files.output.clone() };
        match self.viewer.save(&path) {
            Ok(()) => eprintln!("glint view: saved {}", path.display()),
            Err(e) => eprintln!("glint view: error: {e}"),
        }
        self.redraw();
    }

    /// While the right button is held, W/A/S/D/Q/E fly; true while flying.
    fn fly(&mut self, now: Instant) -> bool {
        let seconds = now.duration_since(self.last_fly).as_secs_f32().min(0.1);
        self.last_fly = now;
        if !self.mouse.right_held {
            return false;
        }
        let direction: Vec3 = self.keys.iter().filter_map(|&k| fly_direction(k)).sum();
        if direction == Vec3::ZERO {
            return false;
        }
        self.input(Input::Fly { direction, seconds });
        true
    }

    /// Reloads the scene when one of its files changed, and watches what it now uses.
    fn poll_files(&mut self) {
        let (Some(watcher), Some(scene)) = (&mut self.watcher, &self.files.scene) else { return };
        if !watcher.changed() {
            return;
        }
        self.viewer.reload(load(scene));
        if let Some(error) = self.viewer.error() {
            eprintln!("glint view: {error}");
        }
        self.watcher = Some(Watcher::new(scene, Some(self.viewer.desc())));
        self.dispatch();
        self.redraw();
    }
}

/// A scene file, its warnings printed, or the located error as one message.
pub fn load(path: &Path) -> Result<glint_core::desc::SceneDesc, String> {
    let loaded = glint_scene::load_any(path).map_err(|e| e.to_string())?;
    for warning in &loaded.warnings {
        eprintln!("glint view: warning: {warning}");
    }
    Ok(loaded.scene)
}

/// The keys bound to viewer inputs (see docs/viewer.md).
fn key_input(code: KeyCode) -> Option<Input> {
    Some(match code {
        KeyCode::KeyR => Input::Reset,
        KeyCode::KeyF => Input::Frame,
        KeyCode::Equal => Input::Fov(-5.0),
        KeyCode::Minus => Input::Fov(5.0),
        KeyCode::BracketRight => Input::MaxDepth(1),
        KeyCode::BracketLeft => Input::MaxDepth(-1),
        KeyCode::KeyI => Input::Toggle(Toggle::Integrator),
        KeyCode::Digit1 => Input::Toggle(Toggle::Shadows),
        KeyCode::Digit2 => Input::Toggle(Toggle::Reflections),
        KeyCode::Digit3 => Input::Toggle(Toggle::Refractions),
        KeyCode::Digit4 => Input::Toggle(Toggle::AntiAliasing),
        KeyCode::KeyH => Input::Toggle(Toggle::Hud),
        KeyCode::KeyV => Input::NextView,
        KeyCode::Escape => Input::ClearExplain,
        _ => return None,
    })
}

/// Camera axes a fly key moves along (x right, y up, z forward).
fn fly_direction(code: KeyCode) -> Option<Vec3> {
    Some(match code {
        KeyCode::KeyW => Vec3::Z,
        KeyCode::KeyS => Vec3::NEG_Z,
        KeyCode::KeyA => Vec3::NEG_X,
        KeyCode::KeyD => Vec3::X,
        KeyCode::KeyE => Vec3::Y,
        KeyCode::KeyQ => Vec3::NEG_Y,
        _ => return None,
    })
}

/// Copies `canvas` into a `width`×`height` buffer, nearest-neighbour scaled.
fn blit(canvas: &Canvas, buffer: &mut [u32], width: u32, height: u32) {
    if canvas.width == width && canvas.height == height {
        buffer.copy_from_slice(&canvas.pixels);
        return;
    }
    for y in 0..height {
        let sy = (y as u64 * canvas.height as u64 / height as u64) as u32;
        for x in 0..width {
            let sx = (x as u64 * canvas.width as u64 / width as u64) as u32;
            buffer[(y * width + x) as usize] = canvas.pixels[(sy * canvas.width + sx) as usize];
        }
    }
}

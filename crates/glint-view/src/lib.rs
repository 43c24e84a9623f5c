//! glint-view: `glint view`, the interactive viewer.
//!
//! A [`viewer::Viewer`] holds the whole session without a window — camera, toggles,
//! the pass schedule (a subsampled preview at once, then one sample per pixel, then
//! more passes averaged while nothing moves) — so the window front end
//! ([`window`]) only forwards events and shows pictures, and the headless mode and the
//! tests drive the same code. Rendering is on the CPU through glint-core, or, with
//! `--device gpu|auto`, the one-sample passes on the GPU backend ([`runner`]).

pub mod camera;
pub mod draw;
pub mod explain;
pub mod headless;
pub mod pass;
mod present;
pub mod runner;
pub mod viewer;
pub mod watch;
pub mod window;
pub mod worker;

use std::path::PathBuf;

use glint_core::desc::SceneDesc;

use crate::viewer::{Input, Toggle, Viewer};

/// The arguments of `glint view`.
#[derive(clap::Args, Debug, Clone)]
pub struct ViewArgs {
    /// Scene file to view (any format `glint render` reads); without one, the built-in
    /// default scene. The file, its includes, meshes and textures are watched: saving
    /// any of them reloads the scene and keeps the camera.
    pub scene: Option<PathBuf>,
    /// Image width in pixels (overrides the scene; the window's size wins once resized).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene).
    #[arg(long)]
    pub height: Option<u32>,
    /// Where `S` saves the image (`Shift+S`: the same name as .exr), and where
    /// --no-window writes it; the format follows the extension (.png, .exr, .ppm).
    #[arg(short, long, default_value = "glint-view.png")]
    pub output: PathBuf,
    /// Render without a window: --frames one-sample passes averaged, written to --output.
    #[arg(long)]
    pub no_window: bool,
    /// One-sample-per-pixel passes to average without a window.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=i64::from(viewer::MAX_PASSES)))]
    pub frames: u32,
    /// Print the ray tree of pixel X,Y (what a click in the window prints).
    #[arg(long, value_name = "X,Y", value_parser = parse_pixel)]
    pub explain: Option<(u32, u32)>,
    /// Each pass at the pixel centre instead of a random point in the pixel.
    #[arg(long)]
    pub no_aa: bool,
    /// Hide the HUD (samples, timing, switches) at the start; `H` shows it.
    #[arg(long)]
    pub no_hud: bool,
    /// Where the one-sample passes run, as for `glint render`: `gpu` (an error when
    /// there is no GPU adapter), `auto` (a hardware GPU if there is one whose driver can
    /// run the scene, else the CPU, saying why) or `cpu`. Previews, debug views and explanations run on the CPU.
    #[arg(long, value_enum, default_value_t = Device::Cpu)]
    pub device: Device,
    /// Without a window: measure passes per second and the latency from an input to
    /// its first picture, and print them as JSON (bench/viewer_fps.sh).
    #[arg(long, requires = "no_window")]
    pub bench: bool,
}

/// `--device`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Device {
    Cpu,
    Gpu,
    Auto,
}

/// `X,Y` for --explain.
fn parse_pixel(text: &str) -> Result<(u32, u32), String> {
    let (x, y) = text.split_once(',').ok_or_else(|| format!("expected X,Y such as 320,180, found '{text}'"))?;
    let whole = |s: &str| s.trim().parse::<u32>().map_err(|_| format!("'{s}' is not a pixel coordinate"));
    Ok((whole(x)?, whole(y)?))
}

/// Runs `glint view` as `args` asks.
///
/// # Errors
///
/// A message for the user: the scene could not be loaded or rendered, no window could
/// be opened, or the image could not be written.
pub fn run(args: &ViewArgs) -> Result<(), String> {
    let desc = match &args.scene {
        Some(path) => window::load(path)?,
        None => glint_scene::default_scene(),
    };
    let mut viewer = Viewer::new(desc.clone(), size(args, &desc))?;
    viewer.use_gpu(choose_gpu(args.device, &viewer)?);
    if args.no_aa {
        viewer.handle(Input::Toggle(Toggle::AntiAliasing));
    }
    if args.no_hud {
        viewer.handle(Input::Toggle(Toggle::Hud));
    }
    if args.no_window {
        return headless::run(viewer, args);
    }
    window::run(viewer, window::Files { scene: args.scene.clone(), output: args.output.clone() })
}

/// The GPU `device` asks for, kept for the whole session (hence leaked); `None` for
/// the CPU. `auto` says on stderr why it chose the CPU.
fn choose_gpu(device: Device, viewer: &Viewer) -> Result<Option<&'static glint_gpu::Gpu>, String> {
    if device == Device::Cpu {
        return Ok(None);
    }
    let chosen = match device {
        Device::Gpu => Ok(glint_gpu::Gpu::new().map_err(|e| e.to_string())?),
        _ => glint_gpu::Gpu::open_hardware(&viewer.scene().lock().unwrap_or_else(std::sync::PoisonError::into_inner)),
    };
    match chosen {
        Ok(gpu) => {
            eprintln!("glint view: sample passes run on {}", gpu.describe());
            Ok(Some(Box::leak(Box::new(gpu))))
        }
        Err(why) => {
            eprintln!("glint view: rendering on the CPU: {why}");
            Ok(None)
        }
    }
}

/// The image size the flags ask for, the scene's for what they leave out.
fn size(args: &ViewArgs, desc: &SceneDesc) -> Option<(u32, u32)> {
    (args.width.is_some() || args.height.is_some())
        .then(|| (args.width.unwrap_or(desc.settings.width), args.height.unwrap_or(desc.settings.height)))
}

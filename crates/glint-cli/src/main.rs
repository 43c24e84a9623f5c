//! `glint`: render scene files to images from the command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use clap::{Parser, Subcommand, ValueEnum};
use glint_core::desc::SceneDesc;
use glint_core::render::{RenderError, render};
use glint_core::scene::compile;
use glint_scene::image_out::{OutputFormat, write_image};
use indicatif::{ProgressBar, ProgressStyle};

/// glint — a ray tracer faithful to the classic Whitted model.
#[derive(Parser)]
#[command(name = "glint", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file (or the built-in default scene) to an image.
    Render(RenderArgs),
}

#[derive(clap::Args)]
struct RenderArgs {
    /// Scene file to render: .glint, course XML/JSON or Ray Tracer Challenge YAML, recognised by content. Without one, the built-in default scene is rendered.
    scene: Option<PathBuf>,
    /// Output image; the format follows the extension (.png, .exr, .ppm) unless --format is given.
    #[arg(short, long, default_value = "glint.png")]
    output: PathBuf,
    /// Output encoding, overriding the extension.
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Image width in pixels (overrides the scene).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (overrides the scene).
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel along each axis: N gives an N×N grid per pixel (overrides the scene).
    #[arg(long)]
    samples: Option<u32>,
    /// Maximum recursion depth of reflected and refracted rays (overrides the scene).
    #[arg(long)]
    max_depth: Option<u32>,
    /// Worker threads; 0 or absent uses every core. The image is identical for any count.
    #[arg(short = 'j', long, default_value_t = 0)]
    threads: usize,
    /// Print no progress bar and no summary.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum FormatArg {
    /// 8-bit sRGB PNG.
    Png,
    /// 16-bit sRGB PNG.
    Png16,
    /// 32-bit float linear OpenEXR.
    Exr,
    /// 8-bit sRGB binary PPM.
    Ppm,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => run_render(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Cancelled) => {
            eprintln!("glint: cancelled; no image was written");
            ExitCode::from(130)
        }
        Err(Failure::Message(message)) => {
            eprintln!("glint: error: {message}");
            ExitCode::FAILURE
        }
    }
}

enum Failure {
    Cancelled,
    Message(String),
}

impl<E: std::fmt::Display> From<E> for Failure {
    fn from(e: E) -> Self {
        Failure::Message(e.to_string())
    }
}

fn run_render(args: &RenderArgs) -> Result<(), Failure> {
    let format = match args.format {
        Some(FormatArg::Png) => OutputFormat::Png8,
        Some(FormatArg::Png16) => OutputFormat::Png16,
        Some(FormatArg::Exr) => OutputFormat::Exr,
        Some(FormatArg::Ppm) => OutputFormat::Ppm,
        None => OutputFormat::from_path(&args.output).ok_or_else(|| {
            format!(
                "cannot tell the image format of '{}': use .png, .exr or .ppm, or pass --format",
                args.output.display()
            )
        })?,
    };
    let mut desc = load(args.scene.as_deref())?;
    apply_overrides(&mut desc, args);
    let scene = compile(&desc)?;

    let cancel = Arc::new(AtomicBool::new(false));
    let handler_flag = Arc::clone(&cancel);
    ctrlc::set_handler(move || handler_flag.store(true, Ordering::Relaxed))?;

    let pool = rayon::ThreadPoolBuilder::new().num_threads(args.threads).build()?;
    let bar = progress_bar(args.quiet);
    let start = Instant::now();
    let result = pool.install(|| {
        render(
            &scene,
            &|done, total| {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            },
            &cancel,
        )
    });
    bar.finish_and_clear();
    let (image, stats) = result.map_err(|RenderError::Cancelled| Failure::Cancelled)?;
    let seconds = start.elapsed().as_secs_f64();
    write_image(&image, &args.output, format, desc.settings.output_transfer)?;
    if !args.quiet {
        let (w, h, n) = (scene.settings.width, scene.settings.height, scene.settings.samples_per_axis);
        eprintln!(
            "wrote {} ({w}x{h}, {} spp) in {seconds:.2} s on {} threads: {} rays, {:.2} Mrays/s{}",
            args.output.display(),
            n * n,
            pool.current_num_threads(),
            stats.rays,
            stats.rays as f64 / seconds / 1e6,
            peak_memory().map(|m| format!(", peak memory {m}")).unwrap_or_default(),
        );
    }
    Ok(())
}

fn load(path: Option<&Path>) -> Result<SceneDesc, Failure> {
    match path {
        None => Ok(glint_scene::default_scene()),
        Some(path) => {
            let loaded = glint_scene::load_any(path)?;
            for warning in &loaded.warnings {
                eprintln!("glint: warning: {warning}");
            }
            Ok(loaded.scene)
        }
    }
}

fn apply_overrides(desc: &mut SceneDesc, args: &RenderArgs) {
    let s = &mut desc.settings;
    s.width = args.width.unwrap_or(s.width);
    s.height = args.height.unwrap_or(s.height);
    s.samples_per_axis = args.samples.unwrap_or(s.samples_per_axis);
    s.max_depth = args.max_depth.unwrap_or(s.max_depth);
}

fn progress_bar(quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(1);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}% tiles {pos}/{len}, {elapsed} elapsed, ETA {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar
}

/// Peak resident memory of this process (Linux `VmHWM`), for the render summary.
fn peak_memory() -> Option<String> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(format!("{:.1} MiB", kib / 1024.0))
}

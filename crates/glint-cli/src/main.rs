//! `glint`: render scene files to images from the command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use clap::{Parser, Subcommand, ValueEnum};
mod frames;
mod parts;

use glint_cli::checkpoint::{Checkpointer, DEFAULT_INTERVAL_SECONDS};
use glint_core::desc::{AdaptiveDesc, FilterKind, SamplePattern, SamplerKind, SceneDesc};
use glint_core::film::Image;
use glint_core::film::Transfer;
use glint_core::render::{NonFiniteSamples, RenderError, RenderStats, render_progressive};
use glint_core::scene::compile;
use glint_scene::image_out::{OutputFormat, write_exr_layers, write_image};
use glint_scene::input::InputLimits;
use glint_scene::native::MAX_SPP;
use glint_scene::overrides::{IntegratorChoice, OverrideError, Overrides, PathOnly};
use indicatif::{ProgressBar, ProgressStyle};

/// glint — a ray tracer faithful to the classic Whitted model.
#[derive(Parser)]
#[command(name = "glint", version, about, long_about = None)]
struct Cli {
    /// Raise a limit on the files glint reads, as KIND=SIZE (repeat it, or separate with commas).
    ///
    /// Every file is checked before it is read: a directory, FIFO or device is refused, and
    /// so is a file larger than the limit for its kind. KIND is `scene` (scene files and
    /// their includes; default 256M), `mesh` (OBJ and MTL, PLY, glTF and its buffers;
    /// default 4G), `image` (textures and environment maps; default 1G) or `pixels` (the
    /// pixels of a decoded image; default 64M, that is 8192x8192; also written WxH). SIZE
    /// is a whole number with an optional K, M, G or T suffix, powers of 1024 (KiB, MiB, …
    /// too). Example: --input-limit scene=1G,pixels=16384x8192
    #[arg(long, global = true, value_name = "KIND=SIZE", value_delimiter = ',', value_parser = parse_input_limit)]
    input_limit: Vec<(LimitKind, u64)>,
    #[command(subcommand)]
    command: Command,
}

/// What an `--input-limit` sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LimitKind {
    Scene,
    Mesh,
    Image,
    Pixels,
}

/// `KIND=SIZE` for --input-limit.
fn parse_input_limit(text: &str) -> Result<(LimitKind, u64), String> {
    let (kind, value) =
        text.split_once('=').ok_or_else(|| format!("expected KIND=SIZE such as scene=1G, found '{text}'"))?;
    let kind = match kind.trim() {
        "scene" => LimitKind::Scene,
        "mesh" => LimitKind::Mesh,
        "image" => LimitKind::Image,
        "pixels" => LimitKind::Pixels,
        other => return Err(format!("unknown limit '{other}': expected scene, mesh, image or pixels")),
    };
    let value = value.trim();
    let size = match value.split_once(['x', 'X']) {
        Some((w, h)) if kind == LimitKind::Pixels => {
            let side = |s: &str| s.trim().parse::<u64>().map_err(|_| format!("'{s}' is not a whole number"));
            side(w)?.checked_mul(side(h)?).ok_or_else(|| format!("{value} pixels is too many to count"))?
        }
        _ => parse_size(value)?,
    };
    Ok((kind, size))
}

/// A whole number with an optional binary suffix: `256M`, `4GiB`, `1024`.
fn parse_size(text: &str) -> Result<u64, String> {
    let digits = text.find(|c: char| !c.is_ascii_digit()).unwrap_or(text.len());
    let (number, suffix) = text.split_at(digits);
    let number: u64 = number.parse().map_err(|_| format!("'{text}' is not a size such as 512M or 4G"))?;
    let shift = match suffix.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kib" => 10,
        "m" | "mib" => 20,
        "g" | "gib" => 30,
        "t" | "tib" => 40,
        other => return Err(format!("unknown unit '{other}' in '{text}': use K, M, G or T (powers of 1024)")),
    };
    number.checked_mul(1 << shift).ok_or_else(|| format!("'{text}' is too large"))
}

/// The default limits with the command line's changes.
fn input_limits(changes: &[(LimitKind, u64)]) -> InputLimits {
    let mut limits = InputLimits::DEFAULT;
    for &(kind, value) in changes {
        *match kind {
            LimitKind::Scene => &mut limits.scene_bytes,
            LimitKind::Mesh => &mut limits.mesh_bytes,
            LimitKind::Image => &mut limits.image_bytes,
            LimitKind::Pixels => &mut limits.image_pixels,
        } = value;
    }
    limits
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file (or the built-in default scene) to an image.
    Render(Box<RenderArgs>),
    /// Write a scene file of any format as a native .glint file that renders the same image.
    Convert(ConvertArgs),
    /// Time the mesh BVH: build, and closest/any-hit rays per second for camera and random
    /// rays, single and in packets of 8.
    ///
    /// What is timed: the build is `Mesh::compile` (validation, parallel binned-SAH BVH, its
    /// collapse to an 8-wide BVH, triangle packing), best of 3, in CPU seconds of the whole
    /// process and in wall seconds. Each query runs --rounds times over all rays; the median
    /// rate is reported with the slowest and fastest run. Camera rays go into packets as 4x2
    /// pixel tiles, random rays in the order they come; packets and single rays must find
    /// the same hits, and every ray is checked against the input's reference hits if it
    /// has any.
    ///
    /// Input: without --input, a bumpy sphere of 1M triangles, 1024x1024 camera rays from
    /// (0, 0.3, 3) and 2^20 random rays in [-1.5, 1.5]^3 (--quick: 40,000 triangles, 256x256
    /// and 2^16 rays). A GLBENCH1 file is little-endian: the 8 bytes "GLBENCH1"; u32 counts
    /// of vertices V, triangles T, camera rays C, random rays R; V×3 f32 positions; T×3 u32
    /// indices; C then R rays of 6 f32 (origin, direction); C then R f32 reference
    /// closest-hit distances (infinity for a miss).
    Bench(BenchArgs),
    /// Merge the parts of a render (files of `glint render --part I/N`) into its image: the
    /// very image one `glint render` of the scene writes, bit for bit.
    Merge(MergeArgs),
    /// Open an interactive viewer: progressive CPU rendering, camera, toggles, explain a pixel, live reload.
    View(glint_view::ViewArgs),
}

#[derive(clap::Args)]
struct MergeArgs {
    /// The parts, all N of them, in any order (e.g. part_*.exr).
    #[arg(required = true, num_args = 1..)]
    parts: Vec<PathBuf>,
    /// Output image; the format follows the extension (.png, .exr, .ppm) unless --format is given.
    #[arg(short, long)]
    output: PathBuf,
    /// Output encoding, overriding the extension.
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Print no summary.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(clap::Args)]
struct BenchArgs {
    /// A GLBENCH1 file of mesh and rays (bench/embree_compare.sh writes one and times Embree on it). Without one, the same kind of scene is generated: a 1M-triangle bumpy sphere, 1024² camera rays, 2²⁰ random rays.
    #[arg(long)]
    input: Option<PathBuf>,
    /// A smaller generated scene (40,000 triangles, 256² camera rays, 2¹⁶ random rays): a quick check.
    #[arg(long, conflicts_with = "input")]
    quick: bool,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Threads building the BVH and tracing the rays (as many as Embree gets in
    /// bench/embree_native.sh). With 1, rates are rays per CPU second of that thread;
    /// with more, rays per wall-clock second.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: u32,
    /// Timed runs of each query; the median is reported with the slowest and fastest.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=100))]
    rounds: u32,
    /// Write the mesh and rays (and glint's closest hits) as a GLBENCH1 file instead of
    /// timing anything, for another library to trace the same rays
    /// (bench/embree_native.sh does).
    #[arg(long, value_name = "FILE")]
    write_input: Option<PathBuf>,
}

#[derive(clap::Args)]
struct ConvertArgs {
    /// Scene file to convert: .glint, course XML/JSON, Ray Tracer Challenge YAML, Mitsuba 3 XML or pbrt-v4 (.pbrt), recognised by content.
    input: PathBuf,
    /// The .glint file to write; image textures are referenced relative to its folder.
    #[arg(short, long)]
    output: PathBuf,
    /// Print no summary (warnings are still printed).
    #[arg(short, long)]
    quiet: bool,
}

#[derive(clap::Args)]
struct RenderArgs {
    /// Scene file to render: .glint, course XML/JSON, Ray Tracer Challenge YAML, Mitsuba 3 XML or pbrt-v4 (.pbrt), recognised by content. Without one, the built-in default scene is rendered.
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
    /// Samples per pixel along each axis: N gives an N×N grid per pixel (overrides the
    /// scene, including a total set by its `spp` and its adaptive sampling; --spp wins
    /// when both are given).
    #[arg(long)]
    samples: Option<u32>,
    /// Samples per pixel in total, for any integrator (overrides the scene, its adaptive
    /// sampling included, and --samples; a count that is not a square takes Sobol
    /// positions).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SPP)))]
    spp: Option<u32>,
    /// Light-transport algorithm (overrides the scene). `path` keeps the scene's path
    /// settings when it is already path traced, else takes Mitsuba's defaults: unlimited
    /// depth, Russian roulette from depth 5, Sobol samples.
    #[arg(long, value_enum)]
    integrator: Option<IntegratorArg>,
    /// Depth limit (overrides the scene). It sets the Whitted integrator's maximum number
    /// of reflection/refraction bounces after the primary ray and, when the integrator is
    /// path, also the longest path, counted as Mitsuba counts it: 1 = emitters seen
    /// directly, 2 = direct lighting, each further step one more bounce. -1 or
    /// `unlimited` = no limit (path integrator only).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = parse_max_depth)]
    max_depth: Option<u32>,
    /// Path depth from which Russian roulette may end a path (path integrator only;
    /// overrides the scene).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    rr_depth: Option<u32>,
    /// Sequence that draws the path tracer's random numbers (path integrator only;
    /// overrides the scene).
    #[arg(long, value_enum)]
    sampler: Option<SamplerArg>,
    /// Where samples go inside each pixel (overrides the scene).
    #[arg(long, value_enum)]
    pattern: Option<PatternArg>,
    /// Reconstruction filter that weighs samples into pixels (overrides the scene).
    #[arg(long, value_enum)]
    filter: Option<FilterArg>,
    /// Filter radius in pixels (overrides the scene; box 0.5 = each pixel's own samples).
    #[arg(long)]
    filter_radius: Option<f32>,
    /// Adaptive sampling as MIN,MAX,THRESHOLD: start with MIN samples per pixel and double
    /// up to MAX while the standard error of the pixel exceeds THRESHOLD (e.g. 4,64,0.01).
    #[arg(long, value_parser = parse_adaptive)]
    adaptive: Option<AdaptiveDesc>,
    /// Seed of every random choice (jitter, lens, area light samples).
    #[arg(long)]
    seed: Option<u32>,
    /// Which of the file's cameras looks, from 0 (a glTF model may hold several; the
    /// first is the default).
    #[arg(long, value_name = "N")]
    camera: Option<usize>,
    /// Also write the number of samples each pixel took, as a greyscale image (white =
    /// the most), to see where adaptive sampling worked.
    #[arg(long, value_name = "PATH")]
    aov_samples: Option<PathBuf>,
    /// Auxiliary outputs of the first surface each camera ray meets, written as extra
    /// layers of the EXR output (for denoisers and debugging): any of `albedo` (the
    /// surface's main reflectance), `normal` (world-space shading normal) and `depth`
    /// (distance from the camera), comma-separated. Needs an .exr output.
    #[arg(long, value_delimiter = ',', value_enum)]
    aov: Vec<AovArg>,
    /// Write quick subsampled previews to the output first (one sample per 16×16, 8×8,
    /// … block), then the full image, so a viewer watching the file sees it refine.
    #[arg(long)]
    progressive: bool,
    /// Where to render: `cpu` (every core), `gpu` (the most capable Vulkan, Metal or DX12
    /// adapter, a CPU driver such as lavapipe included) or `auto` (a hardware GPU when
    /// there is one and it can render the scene, else the CPU; the summary says which).
    /// The GPU runs the Whitted and path integrators and gives the CPU's image within rounding.
    #[arg(long, value_enum, default_value_t = DeviceArg::Cpu)]
    device: DeviceArg,
    /// Save the finished part of the render to FILE every few seconds (atomically, flushed
    /// to disk), so that a render killed by a signal or a power cut can go on with
    /// `--resume FILE` and still give the image an uninterrupted render gives. The file is
    /// deleted once the image is written. CPU only.
    #[arg(long, value_name = "FILE")]
    checkpoint: Option<PathBuf>,
    /// Seconds between checkpoints.
    #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_INTERVAL_SECONDS, value_parser = parse_interval)]
    checkpoint_every: f64,
    /// Go on with the render whose checkpoint is FILE: give the same scene and options
    /// (only --output, --threads, --quiet and the checkpoint options may change). Saving
    /// goes on into FILE, or into --checkpoint's file when given.
    #[arg(long, value_name = "FILE")]
    resume: Option<PathBuf>,
    /// Render only part I of N (counted from 0) into an .exr file of weighted sums, for a
    /// batch scheduler (a Slurm array, a Kubernetes indexed Job): part I traces every N-th
    /// tile. `glint merge` puts the N files together into exactly the image one render
    /// writes. CPU only.
    #[arg(long, value_name = "I/N", value_parser = parse_part_arg)]
    part: Option<(u32, u32)>,
    /// Render an animation's frames: `A..B` (both included) or one frame `N`. The output
    /// names each frame's file with a run of `#`, replaced by the frame number padded with
    /// zeros (`-o out_####.png` writes out_0000.png, out_0001.png, …). Without it, an
    /// output with `#` renders the frames the scene's `settings { frames [A B] }` gives.
    #[arg(long, value_name = "A..B", value_parser = frames::parse_range)]
    frames: Option<(u32, u32)>,
    /// Worker threads; 0 or absent uses every core. The image is identical for any count.
    #[arg(short = 'j', long, default_value_t = 0)]
    threads: usize,
    /// Print no progress bar and no summary.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum PatternArg {
    /// n×n regular grid (n = --samples; 1 = the pixel centre).
    Grid,
    /// The four pixel corners and the centre.
    Corners,
    /// n×n strata, one random sample in each.
    Jittered,
    /// Owen-scrambled Sobol points (n×n of them).
    Sobol,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum DeviceArg {
    Cpu,
    Gpu,
    Auto,
}

#[derive(Clone, Copy, ValueEnum)]
enum IntegratorArg {
    /// The lecture's recursive model: Phong lighting with shadow rays, mirror
    /// reflection and refraction.
    Whitted,
    /// Unidirectional path tracing: global illumination.
    Path,
}

#[derive(Clone, Copy, ValueEnum)]
enum SamplerArg {
    /// Owen-scrambled Sobol points.
    Sobol,
    /// Independent uniform random numbers.
    Independent,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum AovArg {
    Albedo,
    Normal,
    Depth,
}

#[derive(Clone, Copy, ValueEnum)]
enum FilterArg {
    Box,
    Tent,
    Gaussian,
    Mitchell,
    Lanczos,
}

/// `I/N` for --part.
fn parse_part_arg(text: &str) -> Result<(u32, u32), String> {
    glint_scene::part_file::parse_part(text)
        .map(|p| (p.index, p.count))
        .ok_or_else(|| format!("expected I/N with 0 <= I < N, such as 0/4, found '{text}'"))
}

/// Seconds for --checkpoint-every: a positive number, fractions allowed.
fn parse_interval(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 && s <= 1e6 => Ok(s),
        _ => Err(format!("expected a number of seconds greater than 0, found '{text}'")),
    }
}

/// A depth for --max-depth: a whole number, or -1 / `unlimited` for `u32::MAX`.
fn parse_max_depth(text: &str) -> Result<u32, String> {
    match text.trim() {
        "-1" | "unlimited" => Ok(u32::MAX),
        n => n.parse::<u32>().map_err(|_| format!("expected a whole number 0 or more, -1 or 'unlimited', found '{n}'")),
    }
}

fn parse_adaptive(text: &str) -> Result<AdaptiveDesc, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [min, max, threshold] = parts.as_slice() else {
        return Err(format!("expected MIN,MAX,THRESHOLD such as 4,64,0.01, found '{text}'"));
    };
    let whole = |s: &str| s.parse::<u32>().map_err(|_| format!("'{s}' is not a whole number"));
    let threshold = threshold.parse::<f32>().map_err(|_| format!("'{threshold}' is not a number"))?;
    Ok(AdaptiveDesc { min_samples: whole(min)?, max_samples: whole(max)?, threshold })
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

/// mimalloc rather than glibc's malloc. glibc grew its arenas for the tiles' films a page
/// at a time (`brk`, `mprotect` and a fault per page: a tenth of a small render's CPU
/// went to the kernel), where mimalloc takes its memory in large spans advised onto huge
/// pages and reuses what is freed (docs/performance.md, 7 December, evening).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    let cli = Cli::parse();
    glint_scene::input::set_limits(input_limits(&cli.input_limit));
    let result = match cli.command {
        Command::Render(args) => run_render(&args),
        Command::Convert(args) => run_convert(&args),
        Command::Bench(args) => run_bench(&args),
        Command::Merge(args) => parts::run_merge(&args),
        Command::View(args) => glint_view::run(&args).map_err(Failure::Message),
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
    let cancel = Arc::new(AtomicBool::new(false));
    let handler_flag = Arc::clone(&cancel);
    ctrlc::set_handler(move || handler_flag.store(true, Ordering::Relaxed))?;
    // One pool of the threads `--threads` asks for runs everything: loading, building
    // the BVHs, tracing and encoding (compiled outside it, a mesh's BVH was built on
    // rayon's global pool of every core, whose threads also cost a small render's start).
    let pool = rayon::ThreadPoolBuilder::new().num_threads(args.threads).build()?;
    pool.install(|| {
        let first = load(args.scene.as_deref(), 0.0)?;
        match frames::plan(args, &first)? {
            None => render_scene_to(args, first, &args.output, &cancel),
            Some(frames) => frames::render_all(args, &frames, &cancel),
        }
    })
}

/// Renders `desc` with the command line's settings and writes the image to `output`,
/// on the current rayon pool.
fn render_scene_to(args: &RenderArgs, mut desc: SceneDesc, output: &Path, cancel: &AtomicBool) -> Result<(), Failure> {
    let format = output_format(args.format, output)?;
    if !args.aov.is_empty() && format != OutputFormat::Exr {
        return Err(Failure::Message(format!(
            "--aov writes extra layers into an OpenEXR file, but '{}' is not one: use an .exr output",
            output.display()
        )));
    }
    apply_overrides(&mut desc, args)?;
    let mut scene = compile(&desc)?;
    scene.settings.aovs = !args.aov.is_empty();

    if let Some(part) = args.part {
        return parts::run_part(args, part, format, &desc, &scene, cancel);
    }
    // Checkpoints hold the CPU's tiles: `auto` means the CPU for them.
    let checkpointing = args.checkpoint.is_some() || args.resume.is_some();
    let device = match args.device {
        DeviceArg::Gpu if checkpointing => {
            return Err(Failure::Message("--checkpoint and --resume work on the CPU only: use --device cpu".into()));
        }
        DeviceArg::Auto if checkpointing => DeviceArg::Cpu,
        device => device,
    };
    if let Some(gpu) = choose_gpu(device, &scene, args.quiet)? {
        return render_on_gpu(&gpu, (&scene, &desc), args, (output, format), cancel);
    }
    let checkpointer = checkpointer(args, &desc, &scene)?;
    if let Some(saved) = checkpointer.as_ref().map(|c| c.store().len()).filter(|&n| n > 0 && !args.quiet) {
        let total = glint_core::render::tile_count(&scene);
        eprintln!("glint: resuming: {saved} of {total} tiles were done");
    }

    let bar = progress_bar(args.quiet);
    let start = Instant::now();
    let transfer = desc.settings.output_transfer;
    // Previews go to the output as they come; the full image is written below.
    let mut preview_error = None;
    let mut on_pass = |image: &Image, block: u32| {
        if args.progressive && block > 1 && preview_error.is_none() {
            preview_error = write_image(image, output, format, transfer).err();
        }
    };
    let first_block = if args.progressive { 16 } else { 1 };
    let store = checkpointer.as_ref().map(Checkpointer::store);
    let mut render = || {
        render_progressive(
            &scene,
            store,
            first_block,
            &mut on_pass,
            &|done, total| {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            },
            cancel,
        )
    };
    let result = match &checkpointer {
        Some(checkpointer) => checkpointer.run(render),
        None => render(),
    };
    bar.finish_and_clear();
    if let Some(checkpointer) = &checkpointer {
        if let Some(warning) = checkpointer.failure() {
            eprintln!("glint: warning: {warning}");
        } else if result.is_err() {
            let path = checkpointer.path().display();
            eprintln!("glint: the finished tiles are saved in '{path}': go on with --resume {path}");
        }
    }
    if let Some(e) = preview_error {
        return Err(e.into());
    }
    let (image, stats) = result.map_err(|RenderError::Cancelled| Failure::Cancelled)?;
    let traced = start.elapsed().as_secs_f64();
    write_outputs(args, (output, format, transfer), &image, &stats)?;
    let seconds = start.elapsed().as_secs_f64();
    if let Some(checkpointer) = &checkpointer {
        checkpointer.remove();
    }
    report_non_finite(&stats.non_finite, Some((&scene, &desc)));
    if !args.quiet {
        let (w, h) = (scene.settings.width, scene.settings.height);
        let mean_spp =
            stats.samples_per_pixel.iter().map(|&c| u64::from(c)).sum::<u64>() as f64 / (w as f64 * h as f64);
        eprintln!(
            "wrote {} ({w}x{h}, {:.1} spp) in {seconds:.2} s (traced in {traced:.3} s) on {} threads: {} rays, \
             {:.2} Mrays/s{}",
            output.display(),
            mean_spp,
            rayon::current_num_threads(),
            stats.rays,
            stats.rays as f64 / traced / 1e6,
            peak_memory().map(|m| format!(", peak memory {m}")).unwrap_or_default(),
        );
    }
    Ok(())
}

/// The checkpointing that `--checkpoint` and `--resume` ask for, if they do.
fn checkpointer(
    args: &RenderArgs,
    desc: &SceneDesc,
    scene: &glint_core::scene::RenderScene,
) -> Result<Option<Checkpointer>, Failure> {
    let every = std::time::Duration::from_secs_f64(args.checkpoint_every);
    Ok(match (&args.resume, &args.checkpoint) {
        (Some(from), to) => Some(Checkpointer::resume(scene, desc, from, to.clone().unwrap_or(from.clone()), every)?),
        (None, Some(to)) => Some(Checkpointer::fresh(scene, desc, to.clone(), every)?),
        (None, None) => None,
    })
}

/// Says once, after the render, how many samples were NaN or infinite and which
/// surfaces produced them: those samples were left out of the image.
/// `scene` names the objects and materials; without it (merging parts) they are numbered.
fn report_non_finite(non_finite: &NonFiniteSamples, scene: Option<(&glint_core::scene::RenderScene, &SceneDesc)>) {
    if non_finite.is_empty() {
        return;
    }
    eprintln!(
        "glint: warning: {} samples came back NaN or infinite and were left out of the image:",
        non_finite.total()
    );
    for (source, tally) in non_finite.by_source() {
        let (x, y) = tally.example_pixel;
        let from = match source {
            Some(surface) => {
                let instance = scene.and_then(|(scene, _)| scene.instances.get(surface.instance as usize));
                let kind = instance.map_or("an object".into(), |i| format!("a {:?}", i.shape.kind).to_lowercase());
                let name = scene.and_then(|(_, desc)| desc.materials.get(surface.material as usize));
                let material = match name.map(|m| m.name.as_str()) {
                    Some(name) if !name.is_empty() => format!("material '{name}'"),
                    _ => format!("material #{}", surface.material),
                };
                format!("{kind} (object #{}) with {material}", surface.instance)
            }
            None => "the background or environment".to_string(),
        };
        eprintln!("  {} from {from}, e.g. at pixel ({x}, {y})", tally.count);
    }
}

/// Writes a finished render: the image (with the AOV layers `--aov` asks for, into
/// one OpenEXR file) and, with `--aov-samples`, the samples each pixel took.
fn write_outputs(
    args: &RenderArgs,
    (output, format, transfer): (&Path, OutputFormat, Transfer),
    image: &Image,
    stats: &RenderStats,
) -> Result<(), Failure> {
    match &stats.aovs {
        Some(aovs) => {
            let mut layers = Vec::new();
            for aov in [AovArg::Albedo, AovArg::Normal, AovArg::Depth].into_iter().filter(|a| args.aov.contains(a)) {
                layers.push(match aov {
                    AovArg::Albedo => ("albedo", &["R", "G", "B"][..], &aovs.albedo),
                    AovArg::Normal => ("normal", &["X", "Y", "Z"][..], &aovs.normal),
                    AovArg::Depth => ("depth", &["Z"][..], &aovs.depth),
                });
            }
            write_exr_layers(output, image, &layers)?;
        }
        None => write_image(image, output, format, transfer)?,
    }
    if let Some(path) = &args.aov_samples {
        let counts = sample_count_image(image, &stats.samples_per_pixel);
        write_image(&counts, path, OutputFormat::Png8, Transfer::Identity)?;
    }
    Ok(())
}

/// The GPU to render on, if `device` asks for one and (for `auto`) a hardware GPU
/// can render this scene; `None` means the CPU.
fn choose_gpu(
    device: DeviceArg,
    scene: &glint_core::scene::RenderScene,
    quiet: bool,
) -> Result<Option<glint_gpu::Gpu>, Failure> {
    let note = |why: &str| {
        if !quiet {
            eprintln!("glint: rendering on the CPU: {why}");
        }
    };
    match device {
        DeviceArg::Cpu => Ok(None),
        DeviceArg::Gpu => Ok(Some(glint_gpu::Gpu::new()?)),
        DeviceArg::Auto => match glint_gpu::Gpu::open_hardware(scene) {
            Ok(gpu) => Ok(Some(gpu)),
            Err(why) => {
                note(&why);
                Ok(None)
            }
        },
    }
}

/// Renders on `gpu` pass by pass (or, for adaptive sampling, round by round), with
/// the same progress bar, Ctrl-C, `--progressive` and outputs as on the CPU.
fn render_on_gpu(
    gpu: &glint_gpu::Gpu,
    (scene, desc): (&glint_core::scene::RenderScene, &SceneDesc),
    args: &RenderArgs,
    (output, format): (&Path, OutputFormat),
    cancel: &AtomicBool,
) -> Result<(), Failure> {
    let transfer = desc.settings.output_transfer;
    let start = Instant::now();
    let mut film = glint_gpu::Progressive::new(gpu, scene)?;
    let setup = start.elapsed().as_secs_f64();
    let bar = progress_bar(args.quiet);
    if scene.settings.adaptive.is_some() {
        let on_round = |done: usize, total: usize| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        };
        film.sample_adaptively(&on_round, cancel).map_err(|e| match e {
            glint_gpu::GpuRenderError::Cancelled => Failure::Cancelled,
            glint_gpu::GpuRenderError::Gpu(e) => e.into(),
        })?;
    } else {
        let total = scene.settings.spp;
        bar.set_length(total as u64);
        // Passes of about a tenth of the samples keep the bar and Ctrl-C responsive.
        let pass = total.div_ceil(10).max(1);
        while film.samples_done() < total {
            if cancel.load(Ordering::Relaxed) {
                bar.finish_and_clear();
                return Err(Failure::Cancelled);
            }
            film.add_samples(pass.min(total - film.samples_done()))?;
            bar.set_position(film.samples_done() as u64);
            if args.progressive && film.samples_done() < total {
                write_image(&film.image()?, output, format, transfer)?;
            }
        }
    }
    bar.finish_and_clear();
    let image = film.image()?;
    let stats = RenderStats {
        rays: 0,
        samples_per_pixel: film.samples_per_pixel()?,
        aovs: film.aovs()?,
        non_finite: film.non_finite()?,
    };
    write_outputs(args, (output, format, transfer), &image, &stats)?;
    if !args.quiet {
        let seconds = start.elapsed().as_secs_f64();
        let (w, h) = (scene.settings.width, scene.settings.height);
        let samples = stats.samples_per_pixel.iter().map(|&c| c as f64).sum::<f64>();
        // Setup (upload and kernel compilation, which a driver may cache) is reported
        // apart: the rate is the rendering's own.
        eprintln!(
            "wrote {} ({w}x{h}, {:.1} spp) in {seconds:.2} s on the GPU {} ({setup:.2} s setup): {:.2} M samples/s",
            output.display(),
            samples / (w as f64 * h as f64),
            gpu.describe(),
            samples / (seconds - setup).max(1e-9) / 1e6,
        );
    }
    report_non_finite(&stats.non_finite, Some((scene, desc)));
    Ok(())
}

/// The per-pixel sample counts as a greyscale image, white = the most samples.
fn sample_count_image(like: &Image, counts: &[u32]) -> Image {
    let most = counts.iter().copied().max().unwrap_or(1).max(1) as f32;
    let pixels = counts.iter().map(|&c| glint_core::math::Vec3::splat(c as f32 / most)).collect();
    Image { pixels, ..*like }
}

fn run_bench(args: &BenchArgs) -> Result<(), Failure> {
    use glint_cli::bench;
    let input = match (&args.input, args.quick) {
        (Some(path), _) => bench::read_input(path)?,
        (None, true) => bench::generate(100, 200, 256, 1 << 16),
        (None, false) => bench::generate(500, 1000, 1024, 1 << 20),
    };
    if let Some(path) = &args.write_input {
        let [coherent, incoherent] = bench::closest_distances(&input)?;
        bench::write_input(path, &input, [&coherent, &incoherent])?;
        return Ok(());
    }
    let spinner = ProgressBar::new_spinner();
    spinner.enable_steady_tick(std::time::Duration::from_millis(120));
    let options = bench::BenchOptions { threads: args.threads as usize, rounds: args.rounds as usize };
    let measures = bench::run(&input, options, |step| spinner.set_message(step.to_string()));
    spinner.finish_and_clear();
    let measures = measures?;
    if args.json {
        println!("{}", bench::to_json(&measures));
    } else {
        print!("{}", bench::to_table(&measures));
    }
    Ok(())
}

fn run_convert(args: &ConvertArgs) -> Result<(), Failure> {
    let converted = glint_scene::convert::convert(&args.input, &args.output)?;
    for warning in &converted.warnings {
        eprintln!("glint: warning: {warning}");
    }
    if !args.quiet {
        eprintln!("wrote {} ({:?} scene from {})", args.output.display(), converted.format, args.input.display());
    }
    Ok(())
}

/// The scene at `path` (the built-in one without), animated properties at `frame`.
fn load(path: Option<&Path>, frame: f64) -> Result<SceneDesc, Failure> {
    match path {
        None => Ok(glint_scene::default_scene()),
        Some(path) => {
            let loaded = glint_scene::load_any_at(path, frame)?;
            for warning in &loaded.warnings {
                eprintln!("glint: warning: {warning}");
            }
            Ok(loaded.scene)
        }
    }
}

/// Applies the command line's settings on top of the scene's (the same
/// [`Overrides`] the Python API applies).
///
/// # Errors
///
/// A message when a flag does not apply to the integrator that will render: an
/// unlimited --max-depth, --rr-depth or --sampler with the Whitted integrator.
fn apply_overrides(desc: &mut SceneDesc, args: &RenderArgs) -> Result<(), String> {
    overrides(args).apply(desc).map_err(|e| {
        let flag = match e {
            OverrideError::PathOnly(PathOnly::UnlimitedMaxDepth) => {
                "an unlimited --max-depth (the Whitted integrator needs a finite depth)"
            }
            OverrideError::PathOnly(PathOnly::RrDepth) => "--rr-depth",
            OverrideError::PathOnly(PathOnly::Sampler) => "--sampler",
            OverrideError::RrDepthZero | OverrideError::NoSuchCamera { .. } => return e.to_string(),
        };
        format!("{flag} applies only to the path integrator; add --integrator path or render a path-traced scene")
    })
}

/// The render flags that replace the scene's settings.
fn overrides(args: &RenderArgs) -> Overrides {
    Overrides {
        width: args.width,
        height: args.height,
        samples: args.samples,
        spp: args.spp,
        integrator: args.integrator.map(|i| match i {
            IntegratorArg::Whitted => IntegratorChoice::Whitted,
            IntegratorArg::Path => IntegratorChoice::Path,
        }),
        max_depth: args.max_depth,
        rr_depth: args.rr_depth,
        sampler: args.sampler.map(|s| match s {
            SamplerArg::Sobol => SamplerKind::Sobol,
            SamplerArg::Independent => SamplerKind::Independent,
        }),
        pattern: args.pattern.map(|p| match p {
            PatternArg::Grid => SamplePattern::Grid,
            PatternArg::Corners => SamplePattern::CornersAndCentre,
            PatternArg::Jittered => SamplePattern::Jittered,
            PatternArg::Sobol => SamplePattern::Sobol,
        }),
        filter: args.filter.map(|f| match f {
            FilterArg::Box => FilterKind::Box,
            FilterArg::Tent => FilterKind::Tent,
            FilterArg::Gaussian => FilterKind::Gaussian,
            FilterArg::Mitchell => FilterKind::Mitchell,
            FilterArg::Lanczos => FilterKind::Lanczos,
        }),
        filter_radius: args.filter_radius,
        adaptive: args.adaptive,
        seed: args.seed,
        camera: args.camera,
    }
}

/// The encoding `--format` asks for, else the one `path`'s extension names.
fn output_format(format: Option<FormatArg>, path: &Path) -> Result<OutputFormat, Failure> {
    Ok(match format {
        Some(FormatArg::Png) => OutputFormat::Png8,
        Some(FormatArg::Png16) => OutputFormat::Png16,
        Some(FormatArg::Exr) => OutputFormat::Exr,
        Some(FormatArg::Ppm) => OutputFormat::Ppm,
        None => OutputFormat::from_path(path).ok_or_else(|| {
            format!("cannot tell the image format of '{}': use .png, .exr or .ppm, or pass --format", path.display())
        })?,
    })
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

#[cfg(test)]
mod tests {
    use glint_core::desc::{IntegratorDesc, PathDesc, RenderSettings};

    use super::*;

    /// The scene after `glint render <flags>` applied its overrides to `desc`.
    fn overridden(desc: &SceneDesc, flags: &[&str]) -> Result<SceneDesc, String> {
        let cli = Cli::try_parse_from(["glint", "render"].iter().chain(flags)).map_err(|e| e.to_string())?;
        let Command::Render(args) = cli.command else { unreachable!("render was given") };
        let mut desc = desc.clone();
        apply_overrides(&mut desc, &args)?;
        Ok(desc)
    }

    fn path_scene(path: PathDesc) -> SceneDesc {
        let mut desc = SceneDesc::default();
        desc.settings.integrator = IntegratorDesc::Path(path);
        desc
    }

    #[test]
    fn input_limits_parse_and_the_documented_defaults_are_the_real_ones() {
        let cli = Cli::try_parse_from(["glint", "render", "--input-limit", "scene=1G,pixels=16384x8192"]).unwrap();
        let limits = input_limits(&cli.input_limit);
        assert_eq!((limits.scene_bytes, limits.image_pixels), (1 << 30, 16384 * 8192));
        assert_eq!(limits.mesh_bytes, InputLimits::DEFAULT.mesh_bytes);
        let cli = Cli::try_parse_from(["glint", "--input-limit", "mesh=12KiB", "convert", "a", "-o", "b"]).unwrap();
        assert_eq!(input_limits(&cli.input_limit).mesh_bytes, 12 << 10);
        for bad in ["scene", "disk=1G", "scene=1Q", "scene=-1", "pixels=4x", "scene=99999999999T"] {
            assert!(parse_input_limit(bad).is_err(), "{bad}");
        }
        // The defaults --help states.
        let documented = ["scene=256M", "mesh=4G", "image=1G", "pixels=64M", "pixels=8192x8192"];
        let parsed: Vec<(LimitKind, u64)> = documented.iter().map(|t| parse_input_limit(t).unwrap()).collect();
        let (limits, pixels) = (input_limits(&parsed[..4]), parsed[4].1);
        assert_eq!((limits, pixels), (InputLimits::DEFAULT, InputLimits::DEFAULT.image_pixels));
    }

    #[test]
    fn integrator_path_keeps_the_scenes_path_settings_or_takes_the_defaults() {
        let whitted = SceneDesc::default();
        let s = overridden(&whitted, &["--integrator", "path"]).unwrap().settings;
        assert_eq!(s.integrator, IntegratorDesc::Path(PathDesc::default()));
        let own = PathDesc { max_depth: 4, rr_depth: 2, sampler: SamplerKind::Independent };
        let s = overridden(&path_scene(own), &["--integrator", "path"]).unwrap().settings;
        assert_eq!(s.integrator, IntegratorDesc::Path(own));
        let s = overridden(&path_scene(own), &["--integrator", "whitted"]).unwrap().settings;
        assert_eq!(s.integrator, IntegratorDesc::Whitted);
        assert_eq!(overridden(&path_scene(own), &[]).unwrap().settings.integrator, IntegratorDesc::Path(own));
    }

    #[test]
    fn max_depth_sets_whitted_and_path_depths() {
        let s = overridden(&SceneDesc::default(), &["--max-depth", "3"]).unwrap().settings;
        assert_eq!((s.max_depth, s.integrator), (3, IntegratorDesc::Whitted));
        let s = overridden(&SceneDesc::default(), &["--integrator", "path", "--max-depth", "7"]).unwrap().settings;
        assert_eq!(s.max_depth, 7);
        assert_eq!(s.integrator, IntegratorDesc::Path(PathDesc { max_depth: 7, ..PathDesc::default() }));
        for unlimited in ["-1", "unlimited"] {
            let scene = path_scene(PathDesc { max_depth: 3, ..PathDesc::default() });
            let s = overridden(&scene, &["--max-depth", unlimited]).unwrap().settings;
            assert_eq!(s.integrator, IntegratorDesc::Path(PathDesc::default()), "{unlimited}");
            assert_eq!(s.max_depth, RenderSettings::default().max_depth, "the Whitted depth stays finite");
        }
        let err = overridden(&SceneDesc::default(), &["--max-depth", "-1"]).unwrap_err();
        assert!(err.contains("only to the path integrator"), "{err}");
        assert!(overridden(&SceneDesc::default(), &["--max-depth", "-2"]).is_err());
    }

    #[test]
    fn rr_depth_and_sampler_need_the_path_integrator() {
        let flags = ["--integrator", "path", "--rr-depth", "9", "--sampler", "independent"];
        let s = overridden(&SceneDesc::default(), &flags).unwrap().settings;
        assert_eq!(
            s.integrator,
            IntegratorDesc::Path(PathDesc { rr_depth: 9, sampler: SamplerKind::Independent, ..PathDesc::default() })
        );
        for flags in [["--rr-depth", "9"], ["--sampler", "sobol"]] {
            let err = overridden(&SceneDesc::default(), &flags).unwrap_err();
            assert!(err.contains(&format!("{} applies only to the path integrator", flags[0])), "{err}");
        }
        assert!(overridden(&SceneDesc::default(), &["--integrator", "path", "--rr-depth", "0"]).is_err());
    }

    #[test]
    fn spp_overrides_for_any_integrator_and_samples_still_counts() {
        let s = overridden(&SceneDesc::default(), &["--spp", "37"]).unwrap().settings;
        assert_eq!((s.spp, s.integrator), (Some(37), IntegratorDesc::Whitted));
        let mut scene = path_scene(PathDesc::default());
        scene.settings.spp = Some(64);
        let s = overridden(&scene, &["--samples", "3"]).unwrap().settings;
        assert_eq!((s.samples_per_axis, s.spp), (3, None));
        let s = overridden(&scene, &["--samples", "3", "--spp", "5"]).unwrap().settings;
        assert_eq!((s.samples_per_axis, s.spp), (3, Some(5)));
        let s = overridden(&scene, &[]).unwrap().settings;
        assert_eq!(s.spp, Some(64));
        assert!(overridden(&scene, &["--spp", "0"]).is_err());
        assert!(overridden(&scene, &["--spp", "1048577"]).is_err());
    }
}

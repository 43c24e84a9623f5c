//! `glint render --part I/N` and `glint merge`: a render cut into parts for batch
//! schedulers, and the parts put back together bit for bit.

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use glint_core::desc::SceneDesc;
use glint_core::render::{Part, RenderError, merge_parts, render_part};
use glint_core::scene::RenderScene;
use glint_scene::image_out::{OutputFormat, write_image};
use glint_scene::part_file::{PartMeta, read_part, write_part};

use crate::{DeviceArg, Failure, MergeArgs, RenderArgs, output_format, progress_bar, report_non_finite};

/// Renders part `index` of `count` of `scene` into the .exr file `args.output` names, on
/// the current rayon pool.
pub(crate) fn run_part(
    args: &RenderArgs,
    (index, count): (u32, u32),
    format: OutputFormat,
    desc: &SceneDesc,
    scene: &RenderScene,
    cancel: &AtomicBool,
) -> Result<(), Failure> {
    refuse_with_part(args, format)?;
    let part = Part::new(index, count, scene)?;
    let bar = progress_bar(args.quiet);
    let start = Instant::now();
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let film = render_part(scene, part, &progress, cancel);
    bar.finish_and_clear();
    let film = film.map_err(|RenderError::Cancelled| Failure::Cancelled)?;
    let fingerprint = glint_cli::checkpoint::fingerprint(scene, desc);
    write_part(&args.output, &film, PartMeta { fingerprint, transfer: desc.settings.output_transfer })?;
    if !args.quiet {
        eprintln!(
            "wrote part {index}/{count} to {} in {:.2} s: {} rays; merge all {count} with `glint merge`",
            args.output.display(),
            start.elapsed().as_secs_f64(),
            film.rays,
        );
    }
    Ok(())
}

/// The options a part cannot honour, refused by name.
fn refuse_with_part(args: &RenderArgs, format: OutputFormat) -> Result<(), Failure> {
    let conflict = if format != OutputFormat::Exr {
        Some("an .exr output (a part holds weighted sums, not an image)")
    } else if !args.aov.is_empty() {
        Some("no --aov (merged parts hold colour only)")
    } else if args.progressive {
        Some("no --progressive")
    } else if args.checkpoint.is_some() || args.resume.is_some() {
        Some("no --checkpoint or --resume (a part is small: run it again)")
    } else if args.device == DeviceArg::Gpu {
        Some("the CPU (--device cpu)")
    } else {
        None
    };
    match conflict {
        Some(needs) => Err(Failure::Message(format!("--part needs {needs}"))),
        None => Ok(()),
    }
}

/// Reads every part `args.parts` names, checks they are all the parts of one render,
/// and writes the merged image.
pub(crate) fn run_merge(args: &MergeArgs) -> Result<(), Failure> {
    let format = output_format(args.format, &args.output)?;
    let start = Instant::now();
    let mut films = Vec::with_capacity(args.parts.len());
    let mut first: Option<(PartMeta, &Path)> = None;
    for path in &args.parts {
        let (film, meta) = read_part(path)?;
        match first {
            None => first = Some((meta, path)),
            Some((expected, first_path)) if meta != expected => {
                return Err(Failure::Message(format!(
                    "{} and {} are parts of different renders (other scenes or settings)",
                    first_path.display(),
                    path.display()
                )));
            }
            Some(_) => {}
        }
        films.push(film);
    }
    let (meta, _) = first.expect("clap requires a part");
    let (image, stats) = merge_parts(&films)?;
    write_image(&image, &args.output, format, meta.transfer)?;
    report_non_finite(&stats.non_finite, None);
    if !args.quiet {
        eprintln!(
            "wrote {} ({}x{}) from {} parts in {:.2} s: {} rays",
            args.output.display(),
            image.width,
            image.height,
            films.len(),
            start.elapsed().as_secs_f64(),
            stats.rays
        );
    }
    Ok(())
}

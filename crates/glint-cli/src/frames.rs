//! `glint render --frames A..B -o out_####.png`: an animation rendered frame by frame,
//! each frame's keyed properties read at its time and its image written to its own file.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use glint_core::desc::SceneDesc;

use crate::{Failure, RenderArgs, render_scene_to};

/// `A..B` (both included) or a single frame `N`.
pub(crate) fn parse_range(text: &str) -> Result<(u32, u32), String> {
    let whole = |s: &str| s.trim().parse::<u32>().map_err(|_| format!("'{s}' is not a whole frame number"));
    let (first, last) = match text.split_once("..") {
        Some((a, b)) => (whole(a)?, whole(b.strip_prefix('=').unwrap_or(b))?),
        None => (whole(text)?, whole(text)?),
    };
    if first > last {
        return Err(format!("the range {text} runs backwards: write the first frame first"));
    }
    Ok((first, last))
}

/// The frames to render, or `None` for a single image of the scene as it stands: the
/// range of `--frames`, else the scene's own `frames` when the output names frames.
pub(crate) fn plan(args: &RenderArgs, scene: &SceneDesc) -> Result<Option<Vec<u32>>, Failure> {
    let numbered = has_frame_number(&args.output);
    let range = match (args.frames, scene.settings.frames) {
        (Some(range), _) => range,
        (None, Some([first, last])) if numbered => (first, last),
        (None, None) if numbered => {
            return Err(Failure::Message(format!(
                "the output '{}' numbers frames (#), but the scene gives no `frames` in its settings and \
                 --frames is not given",
                args.output.display()
            )));
        }
        (None, _) => return Ok(None),
    };
    let frames: Vec<u32> = (range.0..=range.1).collect();
    if frames.len() > 1 && !numbered {
        return Err(Failure::Message(format!(
            "{} frames would all be written to '{}': put a run of # in the output for the frame number, \
             as in out_####.png",
            frames.len(),
            args.output.display()
        )));
    }
    if args.part.is_some() || args.checkpoint.is_some() || args.resume.is_some() {
        return Err(Failure::Message(
            "--frames renders whole frames: it cannot be combined with --part, --checkpoint or --resume".into(),
        ));
    }
    Ok(Some(frames))
}

/// Renders every frame of `frames` to its numbered file, in order.
pub(crate) fn render_all(args: &RenderArgs, frames: &[u32], cancel: &AtomicBool) -> Result<(), Failure> {
    let start = Instant::now();
    for (done, &frame) in frames.iter().enumerate() {
        if cancel.load(Ordering::Relaxed) {
            return Err(Failure::Cancelled);
        }
        let output = frame_path(&args.output, frame);
        if !args.quiet {
            eprintln!("glint: frame {frame} ({} of {}) → {}", done + 1, frames.len(), output.display());
        }
        let scene = match &args.scene {
            Some(path) => glint_scene::load_any_at(path, f64::from(frame))?.scene,
            None => glint_scene::default_scene(),
        };
        render_scene_to(args, scene, &output, cancel)?;
    }
    if !args.quiet && frames.len() > 1 {
        let seconds = start.elapsed().as_secs_f64();
        eprintln!("glint: {} frames in {seconds:.1} s ({:.2} s a frame)", frames.len(), seconds / frames.len() as f64);
    }
    Ok(())
}

fn has_frame_number(path: &Path) -> bool {
    path.file_name().is_some_and(|name| name.to_string_lossy().contains('#'))
}

/// `pattern` with the last run of `#` in its file name replaced by `frame`, padded
/// with zeros to the run's length.
pub(crate) fn frame_path(pattern: &Path, frame: u32) -> PathBuf {
    let Some(name) = pattern.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return pattern.to_path_buf();
    };
    let Some(end) = name.rfind('#') else { return pattern.to_path_buf() };
    let start = name[..end].trim_end_matches('#').len();
    let width = end + 1 - start;
    let numbered = format!("{}{frame:0width$}{}", &name[..start], &name[end + 1..]);
    pattern.with_file_name(numbered)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_numbers_replace_the_last_run_of_hashes() {
        assert_eq!(frame_path(Path::new("out/f_####.png"), 7), PathBuf::from("out/f_0007.png"));
        assert_eq!(frame_path(Path::new("a#b_##.exr"), 123), PathBuf::from("a#b_123.exr"));
        assert_eq!(frame_path(Path::new("dir#/x.png"), 3), PathBuf::from("dir#/x.png"));
        assert_eq!(frame_path(Path::new("#"), 42), PathBuf::from("42"));
    }

    #[test]
    fn ranges_read_as_written() {
        assert_eq!(parse_range("0..120"), Ok((0, 120)));
        assert_eq!(parse_range("5..=9"), Ok((5, 9)));
        assert_eq!(parse_range("12"), Ok((12, 12)));
        assert!(parse_range("9..2").unwrap_err().contains("backwards"));
        assert!(parse_range("a..2").is_err());
    }
}

//! A real render process killed with SIGKILL goes on with `--resume` and writes the
//! image an uninterrupted render writes, bit for bit; NaN samples are reported once.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn glint() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glint"))
}

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

/// A fresh directory for one test's files.
fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-checkpoint-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A path-traced Cornell box that takes a few seconds on one thread.
const RENDER: [&str; 9] = ["render", "--integrator", "path", "--spp", "64", "--width", "128", "--height", "96"];

fn run(command: &mut Command) -> Output {
    let output = command.output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    output
}

/// Starts a one-thread render that checkpoints every 0.1 s, and kills it with SIGKILL
/// once a checkpoint holds some tiles; returns the checkpoint.
fn killed_render(dir: &Path) -> PathBuf {
    let checkpoint = dir.join("render.ckpt");
    let mut child = glint()
        .args(RENDER)
        .args(["-j", "1", "-q", "--checkpoint-every", "0.1", "--checkpoint"])
        .arg(&checkpoint)
        .arg("-o")
        .arg(dir.join("killed.exr"))
        .arg(scene("cornell-path.glint"))
        .spawn()
        .unwrap();
    let start = Instant::now();
    while std::fs::metadata(&checkpoint).map_or(true, |m| m.len() < 1000) {
        assert!(child.try_wait().unwrap().is_none(), "the render ended before its first checkpoint");
        assert!(start.elapsed() < Duration::from_secs(60), "no checkpoint after a minute");
        std::thread::sleep(Duration::from_millis(10));
    }
    child.kill().unwrap(); // SIGKILL: no handler runs, nothing is flushed.
    child.wait().unwrap();
    assert!(!dir.join("killed.exr").exists(), "a killed render left an image behind");
    checkpoint
}

/// Which tiles the resumed run found done: "resuming: K of N tiles were done".
fn resumed_tiles(stderr: &[u8]) -> (u32, u32) {
    let text = String::from_utf8_lossy(stderr);
    let line = text.lines().find(|l| l.contains("resuming:")).unwrap_or_else(|| panic!("no resume line in {text}"));
    let words: Vec<&str> = line.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "of").unwrap();
    (words[at - 1].parse().unwrap(), words[at + 1].parse().unwrap())
}

#[test]
fn a_killed_render_resumes_to_the_uninterrupted_image() {
    let dir = workdir("kill");
    run(glint().args(RENDER).args(["-q", "-o"]).arg(dir.join("whole.exr")).arg(scene("cornell-path.glint")));
    let checkpoint = killed_render(&dir);
    // A power cut mid-append leaves a torn record: it is cut off and its tile retraced.
    let mut torn = std::fs::OpenOptions::new().append(true).open(&checkpoint).unwrap();
    std::io::Write::write_all(&mut torn, &[0x40, 0x1f, 0, 0, 7, 0, 0]).unwrap();
    drop(torn);
    let resumed = run(glint()
        .args(RENDER)
        .arg("--resume")
        .arg(&checkpoint)
        .arg("-o")
        .arg(dir.join("resumed.exr"))
        .arg(scene("cornell-path.glint")));
    let (done, total) = resumed_tiles(&resumed.stderr);
    assert!(done > 0 && done < total, "{done} of {total} tiles were saved");
    let whole = std::fs::read(dir.join("whole.exr")).unwrap();
    assert!(whole == std::fs::read(dir.join("resumed.exr")).unwrap(), "the resumed image differs");
    assert!(!checkpoint.exists(), "the checkpoint outlived its image");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_checkpoint_of_other_settings_is_refused_by_name() {
    let dir = workdir("other");
    let checkpoint = killed_render(&dir);
    let output = glint()
        .args(["render", "--integrator", "path", "--spp", "32", "--width", "128", "--height", "96", "--resume"])
        .arg(&checkpoint)
        .arg("-o")
        .arg(dir.join("other.exr"))
        .arg(scene("cornell-path.glint"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("render.ckpt") && stderr.contains("another scene or other settings"), "{stderr}");
    assert!(!dir.join("other.exr").exists());
    assert!(checkpoint.exists(), "a refused checkpoint must be kept");
    std::fs::write(&checkpoint, b"GLINTCKP\x02\0\0\0 cut").unwrap();
    let output =
        glint().args(RENDER).arg("--resume").arg(&checkpoint).arg(scene("cornell-path.glint")).output().unwrap();
    assert!(String::from_utf8_lossy(&output.stderr).contains("damaged"), "{output:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn nan_samples_are_reported_once_with_their_surface() {
    let dir = workdir("nan");
    // An EXR texture can hold NaN: the sphere wearing it poisons its samples.
    let texels = |_x: usize, _y: usize| (f32::NAN, 0.5f32, 0.5f32);
    exr::prelude::write_rgb_file(dir.join("bad.exr"), 2, 2, texels).unwrap();
    std::fs::write(
        dir.join("nan.glint"),
        "settings { width 32 height 24 }\n\
         camera { eye [0 0 6] look_at [0 0 0] fov 40 }\n\
         texture \"bad\" image { file \"bad.exr\" }\n\
         material \"poisoned\" { diffuse 1 texture \"bad\" blend 1 }\n\
         material \"grey\" { diffuse 0.5 }\n\
         light directional { direction [-1 -1 -1] color [1 1 1] }\n\
         sphere { material \"poisoned\" }\n\
         plane { material \"grey\" rotate [1 0 0] 90 translate [0 0 -2] }\n",
    )
    .unwrap();
    let output = run(glint().args(["render", "-q", "-o"]).arg(dir.join("nan.png")).arg(dir.join("nan.glint")));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let warning = stderr.lines().find(|l| l.contains("NaN or infinite")).unwrap_or_else(|| panic!("{stderr}"));
    let count: u64 = warning.split_whitespace().nth(2).unwrap().parse().unwrap();
    assert!(count > 10 && count < 32 * 24 / 2, "{warning}");
    assert!(stderr.contains("from a sphere") && stderr.contains("material 'poisoned'"), "{stderr}");
    assert_eq!(stderr.matches("NaN or infinite").count(), 1, "reported more than once: {stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

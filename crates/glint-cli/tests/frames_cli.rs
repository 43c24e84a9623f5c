//! `glint render --frames`: an animated scene rendered frame by frame into numbered
//! files, each frame the scene at its own time.

use std::path::PathBuf;
use std::process::Command;

fn glint() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glint"))
}

fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-frames-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn bounce() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bounce.glint")
}

fn run(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    glint()
        .args(["render", "--width", "48", "--height", "27"])
        .args(args)
        .arg(bounce())
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn frames_go_to_numbered_files_and_differ() {
    let dir = workdir("numbered");
    let output = run(&["-q", "--frames", "10..12", "-o", "f_###.png"], &dir);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let frames: Vec<Vec<u8>> = (10..=12).map(|f| std::fs::read(dir.join(format!("f_{f:03}.png"))).unwrap()).collect();
    assert!(frames[0] != frames[1] && frames[1] != frames[2], "the ball does not move");
    assert!(!dir.join("f_009.png").exists() && !dir.join("f_013.png").exists());
    // A single frame rendered alone is the same image as in the sequence.
    let alone = run(&["-q", "--frames", "11", "-o", "alone.png"], &dir);
    assert!(alone.status.success());
    assert!(std::fs::read(dir.join("alone.png")).unwrap() == frames[1]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_scenes_own_frames_are_rendered_for_a_numbered_output() {
    let dir = workdir("scene-range");
    let output = run(&["-q", "--spp", "1", "-o", "b_##.png"], &dir);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    // settings { frames [0 47] }
    assert!(dir.join("b_00.png").exists() && dir.join("b_47.png").exists() && !dir.join("b_48.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn many_frames_need_a_place_for_the_number() {
    let dir = workdir("no-hash");
    let output = run(&["--frames", "0..3", "-o", "same.png"], &dir);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("put a run of # in the output"));
    assert!(!dir.join("same.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

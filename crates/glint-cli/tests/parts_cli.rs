//! `glint render --part I/N` and `glint merge`: the merged image is the file one
//! `glint render` writes, byte for byte; incomplete or mixed sets of parts are refused.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn glint() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glint"))
}

fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-parts-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

fn run(command: &mut Command) -> Output {
    let output = command.output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    output
}

/// Renders every part of `count` with `settings` and returns the files.
fn render_parts(dir: &Path, settings: &[&str], count: u32) -> Vec<PathBuf> {
    (0..count)
        .map(|i| {
            let out = dir.join(format!("part_{i}_of_{count}.exr"));
            run(glint().args(["render", "-q", "--part", &format!("{i}/{count}"), "-o"]).arg(&out).args(settings));
            out
        })
        .collect()
}

#[test]
fn merged_parts_are_the_single_render_byte_for_byte() {
    let dir = workdir("merge");
    let soft = scene("soft-shadows.glint");
    let cornell = scene("cornell-path.glint");
    let cases: [Vec<&str>; 2] = [
        vec!["--width", "64", "--height", "40", "--filter", "mitchell", "--filter-radius", "2", soft.to_str().unwrap()],
        vec!["--width", "48", "--height", "40", "--spp", "8", cornell.to_str().unwrap()],
    ];
    for settings in &cases {
        for (ext, counts) in [("exr", &[1, 2, 5][..]), ("png", &[3][..])] {
            let whole = dir.join(format!("whole.{ext}"));
            run(glint().args(["render", "-q", "-o"]).arg(&whole).args(settings));
            for &count in counts {
                let mut parts = render_parts(&dir, settings, count);
                parts.rotate_left(1); // any order
                let merged = dir.join(format!("merged.{ext}"));
                run(glint().args(["merge", "-q", "-o"]).arg(&merged).args(&parts));
                let same = std::fs::read(&whole).unwrap() == std::fs::read(&merged).unwrap();
                assert!(same, "{count} parts of {settings:?} merge to another {ext} than one render");
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn incomplete_or_mixed_parts_are_refused_by_name() {
    let dir = workdir("refuse");
    let settings = ["--width", "48", "--height", "32"];
    let parts = render_parts(&dir, &settings, 3);
    let merge = |parts: &[PathBuf]| {
        let output = glint().args(["merge", "-o"]).arg(dir.join("out.png")).args(parts).output().unwrap();
        assert_eq!(output.status.code(), Some(1));
        assert!(!dir.join("out.png").exists(), "a refused merge wrote an image");
        String::from_utf8_lossy(&output.stderr).into_owned()
    };
    assert!(merge(&parts[..2]).contains("part 2 of 3 is missing"));
    assert!(merge(&[parts[0].clone(), parts[1].clone(), parts[1].clone()]).contains("part 1 of 3 is given twice"));
    let elsewhere = dir.join("other");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let other = render_parts(&elsewhere, &["--width", "48", "--height", "32", "--seed", "9"], 3);
    let message = merge(&[parts[0].clone(), parts[1].clone(), other[2].clone()]);
    assert!(message.contains("different renders") && message.contains("part_2_of_3.exr"), "{message}");
    std::fs::write(dir.join("fake.exr"), b"not an exr").unwrap();
    assert!(merge(&[dir.join("fake.exr")]).contains("fake.exr"));
    let wrong = glint().args(["render", "--part", "0/2", "-o"]).arg(dir.join("p.png")).args(settings).output().unwrap();
    assert!(String::from_utf8_lossy(&wrong.stderr).contains("--part needs an .exr output"));
    let many =
        glint().args(["render", "--part", "0/1000", "-o"]).arg(dir.join("p.exr")).args(settings).output().unwrap();
    assert!(String::from_utf8_lossy(&many.stderr).contains("more than the image's 6 tiles"), "{many:?}");
    assert!(!dir.join("p.exr").exists() && !dir.join("p.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

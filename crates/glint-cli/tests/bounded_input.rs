//! Bounded input: a file that is too large or not a file at all (a sparse 10 GiB scene,
//! `/dev/zero`, a FIFO, a directory) is refused with one message naming it, at once and
//! in little memory, whether it is the scene itself, an include, a texture or a mesh.
#![cfg(unix)]

use std::ffi::OsStr;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A folder of its own for each test, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("glint-bounded-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    /// A file of `len` bytes that takes no disk space.
    fn sparse(&self, name: &str, len: u64) -> PathBuf {
        let path = self.join(name);
        std::fs::File::create(&path).unwrap().set_len(len).unwrap();
        path
    }

    fn fifo(&self, name: &str) -> PathBuf {
        let path = self.join(name);
        let status = Command::new("mkfifo").arg(&path).status().expect("mkfifo runs");
        assert!(status.success());
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// How a run of glint ended.
struct Run {
    success: bool,
    stderr: String,
    elapsed: Duration,
    /// Peak resident memory of the glint process, in KiB.
    max_rss_kib: i64,
}

/// Runs glint with `args`, killing it if it runs past 20 s (a FIFO opened for reading
/// would block forever), and measures its time and peak memory.
#[expect(clippy::zombie_processes, reason = "the child is reaped by wait4, which also gives its peak memory")]
fn glint<I, S>(args: I) -> Run
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        pipe.read_to_string(&mut text).unwrap();
        text
    });
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: rusage is plain data, for which all zeros is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: pid is our own child, not yet reaped; status and usage are valid for writes.
        let reaped = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if reaped == pid {
            break;
        }
        assert_eq!(reaped, 0, "wait4 failed");
        if start.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("glint was still running after 20 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let elapsed = start.elapsed();
    let success = libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0;
    Run { success, stderr: reader.join().unwrap(), elapsed, max_rss_kib: usage.ru_maxrss }
}

/// Asserts that glint failed at once, in under 100 MB, with one message that holds
/// every one of `expected`.
fn assert_refused(run: &Run, expected: &[&str]) {
    assert!(!run.success, "glint succeeded: {}", run.stderr);
    assert!(run.stderr.starts_with("glint: error: "), "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "one message: {}", run.stderr);
    for part in expected {
        assert!(run.stderr.contains(part), "'{part}' missing from: {}", run.stderr);
    }
    assert!(run.elapsed < Duration::from_secs(2), "took {:?}: {}", run.elapsed, run.stderr);
    assert!(run.max_rss_kib > 0, "peak memory was measured");
    assert!(run.max_rss_kib < 100 * 1024, "peak memory {} KiB: {}", run.max_rss_kib, run.stderr);
}

fn render(scene: &Path, out: &TempDir) -> Run {
    glint([
        OsStr::new("render"),
        scene.as_os_str(),
        OsStr::new("-q"),
        OsStr::new("-o"),
        out.join("out.png").as_os_str(),
    ])
}

#[test]
fn a_sparse_10_gib_scene_file_is_refused_without_being_read() {
    let dir = TempDir::new("sparse");
    let scene = dir.sparse("scene.glint", 10 << 30);
    let run = render(&scene, &dir);
    let name = scene.display().to_string();
    assert_refused(&run, &[&name, "10 GiB", "256 MiB", "--input-limit scene=SIZE"]);
    assert!(!dir.join("out.png").exists());
}

#[test]
fn dev_zero_is_refused_as_a_device() {
    let dir = TempDir::new("zero");
    let run = render(Path::new("/dev/zero"), &dir);
    assert_refused(&run, &["/dev/zero", "character device, not a regular file"]);
}

#[test]
fn a_fifo_is_refused_without_waiting_for_a_writer() {
    let dir = TempDir::new("fifo");
    let fifo = dir.fifo("scene.glint");
    let run = render(&fifo, &dir);
    assert_refused(&run, &[&fifo.display().to_string(), "FIFO (named pipe), not a regular file"]);
    // A mesh file goes through its own reader: the same refusal.
    let fifo = dir.fifo("model.obj");
    let run = render(&fifo, &dir);
    assert_refused(&run, &[&fifo.display().to_string(), "cannot read mesh file", "FIFO"]);
}

#[test]
fn a_directory_is_refused_as_one() {
    let dir = TempDir::new("directory");
    let folder = dir.join("scene.glint");
    std::fs::create_dir(&folder).unwrap();
    let run = render(&folder, &dir);
    assert_refused(&run, &[&folder.display().to_string(), "is a directory, not a regular file"]);
}

#[test]
fn includes_textures_and_meshes_are_bounded_too() {
    let dir = TempDir::new("nested");
    dir.sparse("huge.glint", 10 << 30);
    dir.sparse("huge.png", 10 << 30);
    dir.fifo("pipe.obj");
    let cases = [
        ("include.glint", "include \"huge.glint\"\n", vec!["include.glint:1:9", "huge.glint", "10 GiB"]),
        (
            "texture.glint",
            "texture \"t\" image { file \"huge.png\" }\n",
            vec!["texture.glint:1:", "huge.png", "1 GiB allowed for an image file", "--input-limit image=SIZE"],
        ),
        ("device.glint", "texture \"t\" image { file \"/dev/zero\" }\n", vec!["/dev/zero", "character device"]),
        ("mesh.glint", "mesh \"m\" { file \"pipe.obj\" }\n", vec!["pipe.obj", "FIFO"]),
    ];
    for (name, text, expected) in cases {
        let scene = dir.write(name, text);
        let run = render(&scene, &dir);
        println!("{}", run.stderr.trim_end());
        assert_refused(&run, &expected);
    }
}

#[test]
fn input_limit_lowers_and_raises_the_limits() {
    let dir = TempDir::new("option");
    // A valid scene of a little more than 2 KiB.
    let text = format!("{}\nsphere {{}}\n", "# padding\n".repeat(220));
    let scene = dir.write("scene.glint", &text);
    let out = dir.join("out.glint");
    let convert = |limit: &str| {
        let limit = ["--input-limit", limit].map(OsStr::new);
        glint(
            [OsStr::new("convert"), scene.as_os_str(), OsStr::new("-q"), OsStr::new("-o"), out.as_os_str()]
                .into_iter()
                .chain(limit),
        )
    };
    assert_refused(&convert("scene=2K"), &["scene.glint", "2 KiB allowed for a scene file"]);
    let run = convert("scene=4K");
    assert!(run.success, "{}", run.stderr);
    assert!(out.exists());
}

#[test]
fn the_pixel_limit_refuses_a_large_texture_and_can_be_raised() {
    let dir = TempDir::new("pixels");
    let png = dir.join("tex.png");
    let args = ["render", "--width", "4", "--height", "2", "-q", "-o"].map(OsStr::new);
    let run = glint(args.into_iter().chain([png.as_os_str()]));
    assert!(run.success, "{}", run.stderr);
    let scene = dir.write("scene.glint", "texture \"t\" image { file \"tex.png\" }\nsphere {}\n");
    let out = dir.join("out.glint");
    let convert = |limit: &str| {
        let limit = ["--input-limit", limit].map(OsStr::new);
        glint(
            [OsStr::new("convert"), scene.as_os_str(), OsStr::new("-q"), OsStr::new("-o"), out.as_os_str()]
                .into_iter()
                .chain(limit),
        )
    };
    assert_refused(&convert("pixels=7"), &["tex.png", "4x2 pixels, more than the 7 pixels allowed", "pixels=N"]);
    let run = convert("pixels=4x2");
    assert!(run.success, "{}", run.stderr);
}

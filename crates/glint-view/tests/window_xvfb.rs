//! The viewer's window under Xvfb, driven by xdotool and photographed by ImageMagick's
//! `import`: it shows the scene as `glint render` renders it, a drag orbits the camera,
//! `S` saves the image, and saving the scene file updates the window.
//!
//! Skips (passing) when Xvfb, xdotool or import is missing, unless
//! GLINT_REQUIRE_DISPLAY=1 (as in CI) makes that a failure.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use glint_core::film::{Image, Transfer};
use glint_core::render::render;
use glint_view::viewer::{Input, Toggle, Viewer};

const WIDTH: u32 = 200;
const HEIGHT: u32 = 120;
/// Mean difference per 8-bit channel allowed between the window and a reference.
const TOLERANCE: f64 = 2.0;

/// Kills the process when the test ends, however it ends.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn tools_present() -> bool {
    ["Xvfb", "xdotool", "import"].iter().all(|tool| {
        Command::new("sh").arg("-c").arg(format!("command -v {tool}")).output().is_ok_and(|o| o.status.success())
    })
}

/// Starts Xvfb on a free display it picks itself; returns it and the DISPLAY value.
fn start_xvfb() -> (Killed, String) {
    let mut xvfb = Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", "640x480x24", "-nolisten", "tcp"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("Xvfb starts");
    let mut line = String::new();
    BufReader::new(xvfb.stdout.take().unwrap()).read_line(&mut line).expect("Xvfb names its display");
    (Killed(xvfb), format!(":{}", line.trim()))
}

fn xdotool(display: &str, args: &[&str]) -> String {
    let out = Command::new("xdotool").args(args).env("DISPLAY", display).output().expect("xdotool runs");
    assert!(out.status.success(), "xdotool {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// The window's pixels as 8-bit RGB, via `import -window ID ppm:-`.
fn screenshot(display: &str, window: &str) -> Vec<u8> {
    let out = Command::new("import")
        .args(["-window", window, "-depth", "8", "ppm:-"])
        .env("DISPLAY", display)
        .output()
        .expect("import runs");
    assert!(out.status.success(), "import: {}", String::from_utf8_lossy(&out.stderr));
    ppm_pixels(&out.stdout)
}

/// The pixel bytes of a binary PPM with a maxval of 255.
fn ppm_pixels(ppm: &[u8]) -> Vec<u8> {
    let mut fields = 0;
    let mut at = 0;
    while fields < 4 {
        while ppm[at].is_ascii_whitespace() {
            at += 1;
        }
        while !ppm[at].is_ascii_whitespace() {
            at += 1;
        }
        fields += 1;
    }
    ppm[at + 1..].to_vec()
}

fn mean_difference(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len(), "image sizes differ");
    a.iter().zip(b).map(|(&x, &y)| (f64::from(x) - f64::from(y)).abs()).sum::<f64>() / a.len() as f64
}

/// Screenshots until one is within TOLERANCE of `expected` (or 8 s pass); the last one and its difference.
fn await_picture(display: &str, window: &str, expected: &[u8]) -> (Vec<u8>, f64) {
    let start = Instant::now();
    loop {
        let shot = screenshot(display, window);
        let difference = mean_difference(&shot, expected);
        if difference < TOLERANCE || start.elapsed() > Duration::from_secs(8) {
            return (shot, difference);
        }
        std::thread::sleep(Duration::from_millis(150));
    }
}

/// What the viewer shows for `scene` after `inputs`, without a window: one pass at
/// pixel centres — `glint render`'s image when there are no inputs.
fn expected(scene: &Path, inputs: &[Input]) -> Vec<u8> {
    let desc = glint_scene::load_any(scene).unwrap().scene;
    let mut viewer = Viewer::new(desc, Some((WIDTH, HEIGHT))).unwrap();
    viewer.handle(Input::Toggle(Toggle::AntiAliasing));
    inputs.iter().for_each(|&i| viewer.handle(i));
    while viewer.step() {}
    viewer.image().encode8(Transfer::Srgb)
}

/// `glint render --samples 1`'s image of `scene` at the test's size: one sample per
/// pixel centre.
fn rendered(scene: &Path) -> Vec<u8> {
    let mut desc = glint_scene::load_any(scene).unwrap().scene;
    (desc.settings.width, desc.settings.height) = (WIDTH, HEIGHT);
    (desc.settings.samples_per_axis, desc.settings.spp, desc.settings.adaptive) = (1, None, None);
    let scene = glint_core::scene::compile(&desc).unwrap();
    let image: Image = render(&scene, &|_, _| {}, &AtomicBool::new(false)).unwrap().0;
    image.encode8(Transfer::Srgb)
}

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-view-xvfb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_window_shows_the_scene_orbits_on_a_drag_saves_on_s_and_follows_edits() {
    if !tools_present() {
        assert!(
            std::env::var("GLINT_REQUIRE_DISPLAY").as_deref() != Ok("1"),
            "GLINT_REQUIRE_DISPLAY=1 but Xvfb, xdotool or ImageMagick's import is missing: apt-get install xvfb xdotool imagemagick"
        );
        eprintln!("skipped: Xvfb, xdotool or ImageMagick's import is not installed");
        return;
    }
    let dir = scratch();
    let scene = dir.join("scene.glint");
    std::fs::write(&scene, glint_scene::DEFAULT_SCENE_SOURCE).unwrap();
    let saved = dir.join("saved.png");
    let (_xvfb, display) = start_xvfb();
    let size = [WIDTH.to_string(), HEIGHT.to_string()];
    let viewer = Command::new(env!("CARGO_BIN_EXE_glint-view"))
        .arg(&scene)
        .args(["--width", &size[0], "--height", &size[1], "--no-aa", "--no-hud", "-o"])
        .arg(&saved)
        .env("DISPLAY", &display)
        .stderr(Stdio::null())
        .spawn()
        .expect("the viewer starts");
    let _viewer = Killed(viewer);
    let window = xdotool(&display, &["search", "--sync", "--onlyvisible", "--name", "glint view"]);
    let window = window.lines().next().unwrap().to_string();

    // It opens and shows what `glint render` renders.
    let reference = rendered(&scene);
    let (first, difference) = await_picture(&display, &window, &reference);
    assert!(difference < TOLERANCE, "the window differs from glint render by {difference:.2} per channel");

    // A drag of 50 pixels to the right orbits the camera as the viewer's Orbit input does.
    let (x0, x1, y) = ((WIDTH / 2 - 25).to_string(), (WIDTH / 2 + 25).to_string(), (HEIGHT / 2).to_string());
    xdotool(&display, &["mousemove", "--window", &window, &x0, &y, "mousedown", "1"]);
    xdotool(&display, &["mousemove", "--window", &window, &x1, &y, "mouseup", "1"]);
    let orbited = expected(&scene, &[Input::Orbit { dx: 50.0, dy: 0.0 }]);
    let (shot, difference) = await_picture(&display, &window, &orbited);
    assert!(difference < TOLERANCE, "after the drag the window differs from the orbited view by {difference:.2}");
    assert!(mean_difference(&shot, &first) > 4.0 * TOLERANCE, "the drag did not change the picture");

    // S saves the image the window shows.
    xdotool(&display, &["windowfocus", "--sync", &window]);
    xdotool(&display, &["key", "s"]);
    let start = Instant::now();
    while !saved.exists() && start.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(100));
    }
    let png = image::open(&saved).expect("S writes a readable PNG").to_rgb8();
    assert_eq!(png.dimensions(), (WIDTH, HEIGHT));
    assert!(mean_difference(png.as_raw(), &shot) < TOLERANCE, "the saved image is not the window's");

    // Saving the scene file with a red sky updates the window, camera kept.
    let red = glint_scene::DEFAULT_SCENE_SOURCE.replace("background [0.05 0.08 0.22]", "background [1 0 0]");
    assert_ne!(red, glint_scene::DEFAULT_SCENE_SOURCE, "the default scene's background line moved");
    std::fs::write(&scene, &red).unwrap();
    let reloaded = expected(&scene, &[Input::Orbit { dx: 50.0, dy: 0.0 }]);
    let (_, difference) = await_picture(&display, &window, &reloaded);
    assert!(difference < TOLERANCE, "after the edit the window differs from the edited scene by {difference:.2}");
    std::fs::remove_dir_all(&dir).unwrap();
}

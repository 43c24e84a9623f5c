//! Every reader as a fuzz target calls it: bytes in, and whatever comes back must be an
//! answer (a scene or an error), never a panic. A scene a reader accepts is compiled
//! too, since a reader that lets through what the renderer cannot take is as wrong as
//! one that panics.
//!
//! Files a fuzzed input names (includes, MTL libraries, glTF buffers, textures) are
//! looked for in a folder that does not exist, so they fail cleanly.

use std::path::{Path, PathBuf};
use std::sync::Once;

use glint_core::desc::{SceneDesc, Transfer};
use glint_scene::SceneError;
use glint_scene::course::CourseOptions;
use glint_scene::input::{InputLimits, set_limits};

/// Where a fuzzed scene pretends to live: a folder that does not exist.
const NOWHERE: &str = "/nonexistent-glint-fuzz";

/// A reader as a target calls it.
pub type Target = fn(&[u8]);

/// Every target with its name, as `fuzz/run.sh` and the regression folders name them.
pub const TARGETS: &[(&str, Target)] = &[
    ("native", native),
    ("course_xml", course_xml),
    ("course_json", course_json),
    ("challenge_yaml", challenge_yaml),
    ("mitsuba_xml", mitsuba_xml),
    ("pbrt", pbrt),
    ("obj", obj),
    ("ply", ply),
    ("gltf", gltf),
    ("image", image),
];

/// The native `.glint` reader.
pub fn native(data: &[u8]) {
    with_text(data, |text| compile_if_read(glint_scene::parse_scene(text, "fuzz.glint", Path::new(NOWHERE))));
}

/// The CS123 `<scenefile>` XML reader.
pub fn course_xml(data: &[u8]) {
    with_text(data, |text| {
        let loaded = glint_scene::course::parse_xml(text, "fuzz.xml", Path::new(NOWHERE), CourseOptions::default());
        compile_if_read(loaded.map(|l| l.scene));
    });
}

/// The CS1230 JSON reader.
pub fn course_json(data: &[u8]) {
    with_text(data, |text| {
        let loaded = glint_scene::course::parse_json(text, "fuzz.json", Path::new(NOWHERE), CourseOptions::default());
        compile_if_read(loaded.map(|l| l.scene));
    });
}

/// The Ray Tracer Challenge YAML reader.
pub fn challenge_yaml(data: &[u8]) {
    let name = format!("{NOWHERE}/fuzz.yml");
    with_text(data, |text| compile_if_read(glint_scene::challenge::parse_challenge(text, &name).map(|(s, _)| s)));
}

/// The Mitsuba 3 XML reader.
pub fn mitsuba_xml(data: &[u8]) {
    with_text(data, |text| {
        let loaded = glint_scene::mitsuba::parse_mitsuba(text, "fuzz.xml", Path::new(NOWHERE));
        compile_if_read(loaded.map(|l| l.scene));
    });
}

/// The pbrt-v4 reader.
pub fn pbrt(data: &[u8]) {
    with_text(data, |text| {
        let loaded = glint_scene::pbrt::parse_pbrt(text, "fuzz.pbrt", Path::new(NOWHERE));
        compile_if_read(loaded.map(|l| l.scene));
    });
}

/// The Wavefront OBJ reader.
pub fn obj(data: &[u8]) {
    mesh(data, "obj");
}

/// The PLY reader.
pub fn ply(data: &[u8]) {
    mesh(data, "ply");
}

/// The glTF reader; the first bytes decide between JSON and binary glTF, as they do
/// for a file.
pub fn gltf(data: &[u8]) {
    mesh(data, "glb");
}

/// The texture decoder (PNG, JPEG, OpenEXR, Radiance HDR) within glint's size limits.
pub fn image(data: &[u8]) {
    bounded_pixels();
    let path = Path::new(NOWHERE).join("fuzz.img");
    if let Ok(glint_core::desc::TextureDesc::Image { width, height, texels, .. }) =
        glint_scene::texture_io::decode_image("fuzz", &path, data, Transfer::Srgb, true)
    {
        assert_eq!(texels.len() as u64, u64::from(width) * u64::from(height), "texel count");
    }
}

/// A mesh file with extension `ext`, shown as `glint render model.ext` would show it.
fn mesh(data: &[u8], ext: &str) {
    bounded_pixels();
    let path: PathBuf = Path::new(NOWHERE).join(format!("fuzz.{ext}"));
    let import = glint_scene::mesh::parse_mesh(&path, data.to_vec());
    compile_if_read(import.map(glint_scene::mesh::model_scene));
}

/// Runs `read` on `data` if it is UTF-8: scene files that are not are refused before
/// any reader sees them.
fn with_text(data: &[u8], read: impl FnOnce(&str)) {
    bounded_pixels();
    if let Ok(text) = std::str::from_utf8(data) {
        read(text);
    }
}

/// Holds decoded images to 2²⁰ pixels (as `--input-limit pixels=` does), so that a tiny
/// header claiming a huge image is refused rather than exhausting the fuzzer's memory.
fn bounded_pixels() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| set_limits(InputLimits { image_pixels: 1 << 20, ..InputLimits::DEFAULT }));
}

/// Compiles a scene a reader accepted; compile may refuse it, but must not panic.
fn compile_if_read(read: Result<SceneDesc, SceneError>) {
    if let Ok(desc) = read {
        let _ = glint_core::scene::compile(&desc);
    }
}

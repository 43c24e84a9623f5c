//! The native `.glint` scene format, written by hand (see `docs/scene-format.md`).
//!
//! Reading happens in three separate steps so each can report its own kind of mistake:
//! [`lexer`] (characters → tokens with line and column), [`tree`] (tokens → a generic
//! node tree, syntax only) and the builder (nodes → [`SceneDesc`], meaning only).

pub mod animation;
mod args;
mod bsdf;
mod builder;
pub mod data;
mod integrator;
pub mod lexer;
mod lights;
mod materials;
mod meshes;
mod objects;
mod settings;
mod solids;
pub mod tree;
pub mod writer;

use std::path::Path;

use glint_core::desc::SceneDesc;

use crate::error::SceneError;
use crate::input::InputKind;
use animation::Clock;
use builder::{Builder, Source, parent_dir};

pub use builder::MAX_NODES;
pub use integrator::MAX_PATH_DEPTH;
pub use settings::{MAX_DEPTH, MAX_FRAME, MAX_IMAGE_SIDE, MAX_SAMPLES_PER_AXIS, MAX_SPP};

/// The text of `scenes/default.glint`, compiled in so that glint can render something
/// with no files at all.
pub const DEFAULT_SCENE_SOURCE: &str = include_str!("../../../../scenes/default.glint");

/// The file name the default scene's errors and node origins carry.
pub const DEFAULT_SCENE_NAME: &str = "<default scene>";

/// Reads a `.glint` file; includes and texture files are found relative to it.
///
/// # Errors
///
/// A [`SceneError`] naming the file, line and column of the first problem: a syntax or
/// meaning error, or an included or texture file that cannot be read. A missing scene
/// file itself is reported with line 0.
pub fn load_scene(path: &Path) -> Result<SceneDesc, SceneError> {
    load_text(path, &crate::input::read_text(path, InputKind::Scene)?, 0.0)
}

/// Reads native scene text that came from `path` (for [`crate::load_any_at`], which has
/// read the file already to tell its format), keyed properties taken at `frame`.
pub(crate) fn load_text(path: &Path, text: &str, frame: f64) -> Result<SceneDesc, SceneError> {
    let src = Source { name: path.display().to_string(), dir: parent_dir(path) };
    let mut builder = Builder::at(Clock { frame, fps: scene_fps(text) });
    builder.file(&src, text, std::fs::canonicalize(path).ok())?;
    Ok(builder.finish())
}

/// The `fps` of the file's own `settings`, or the default: what keys in seconds are
/// read at. Text that does not parse gives the default; the builder then reports it.
fn scene_fps(text: &str) -> f64 {
    let Some(nodes) = lexer::tokenize(text).ok().and_then(|tokens| tree::parse(&tokens).ok()) else {
        return animation::DEFAULT_FPS;
    };
    let settings = nodes.iter().filter(|n| n.name == "settings").flat_map(|n| n.children());
    settings
        .filter(|p| p.name == "fps")
        .find_map(|p| match p.args.as_slice() {
            // Read as the builder reads it (f32), so the two agree exactly.
            [tree::Value { kind: tree::ValueKind::Number(x), .. }] => Some(f64::from(*x as f32)),
            _ => None,
        })
        .unwrap_or(animation::DEFAULT_FPS)
}

/// Parses scene text that did not necessarily come from a file: `file_name` is used in
/// errors and node origins, `base_dir` is where relative includes and textures are found.
///
/// # Errors
///
/// As [`load_scene`], with errors in the text itself reported under `file_name`.
pub fn parse_scene(source: &str, file_name: &str, base_dir: &Path) -> Result<SceneDesc, SceneError> {
    parse_scene_at(source, file_name, base_dir, 0.0)
}

/// [`parse_scene`] with keyed properties taken at `frame` (fractional between frames).
///
/// # Errors
///
/// As [`parse_scene`].
pub fn parse_scene_at(source: &str, file_name: &str, base_dir: &Path, frame: f64) -> Result<SceneDesc, SceneError> {
    let src = Source { name: file_name.to_owned(), dir: base_dir.to_path_buf() };
    // If the text is a file on disk, knowing it lets an include of it back be a cycle.
    let canonical = std::fs::canonicalize(base_dir.join(file_name)).ok();
    let mut builder = Builder::at(Clock { frame, fps: scene_fps(source) });
    builder.file(&src, source, canonical)?;
    Ok(builder.finish())
}

/// The classic Whitted composition (mirror and glass spheres over a checkered floor),
/// built from [`DEFAULT_SCENE_SOURCE`]; it needs no files.
///
/// # Panics
///
/// Never in a released build: the compiled-in text is checked by the test suite, and a
/// failure here would be a bug in glint, not in anything the user did.
pub fn default_scene() -> SceneDesc {
    match parse_scene(DEFAULT_SCENE_SOURCE, DEFAULT_SCENE_NAME, Path::new("")) {
        Ok(scene) => scene,
        Err(e) => panic!("the built-in default scene is invalid: {e}"),
    }
}

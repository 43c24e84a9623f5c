//! The scenefiles of Brown's CS123/CSCI 1230 ray tracer: the XML format (`<scenefile>`,
//! used until 2022) and the JSON format (2023 on). See `docs/course-formats.md`.
//!
//! Both readers build the same small course model ([`model`]: the course's own
//! materials, groups with transforms, templates, lights), and [`build`] turns that into
//! a [`glint_core::desc::SceneDesc`] with the course's meaning: unit primitives inside
//! [−0.5, 0.5]³, the global `k` coefficients folded into the colours, texture blending
//! as the course does it, and display-referred colours (no sRGB decoding or encoding).
//!
//! Harmless oddities (an unknown element, a mesh glint cannot draw yet, a texture found
//! only through a fallback path) are returned as warnings; malformed input is a
//! [`SceneError`] at the file, line and column of the problem.

mod build;
mod json;
pub mod json_value;
mod model;
mod textures;
mod xml;

use std::collections::HashSet;
use std::path::Path;

use crate::detect::{Loaded, SceneFormat};
use crate::error::SceneError;

pub use build::{COURSE_HEIGHT, COURSE_MAX_DEPTH, COURSE_WIDTH, DEPTH_OF_FIELD_SAMPLES_PER_AXIS, MAX_NODES};

pub use crate::source::{Pos, Source};

/// How to read a course scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CourseOptions {
    /// When true (the default) a texture file that cannot be found or decoded is an
    /// error. When false it is a warning and the material is rendered untextured, which
    /// is what the course's own renderer does (it loads textures only while rendering).
    pub strict_textures: bool,
}

impl Default for CourseOptions {
    fn default() -> Self {
        Self { strict_textures: true }
    }
}

/// Reads a CS123/CS1230 XML scenefile.
///
/// # Errors
///
/// A [`SceneError`] at the file, line and column of the first problem.
pub fn load_xml(path: &Path, options: CourseOptions) -> Result<Loaded> {
    let (text, src) = read(path)?;
    parse(&text, &src, SceneFormat::CourseXml, options)
}

/// Reads a CS1230 JSON scenefile.
///
/// # Errors
///
/// A [`SceneError`] at the file, line and column of the first problem.
pub fn load_json(path: &Path, options: CourseOptions) -> Result<Loaded> {
    let (text, src) = read(path)?;
    parse(&text, &src, SceneFormat::CourseJson, options)
}

/// Reads XML scene text that did not necessarily come from a file. `file_name` names
/// it in messages; `scene_dir` is the folder the scene would live in (textures are
/// found relative to its parent, as the course does).
///
/// # Errors
///
/// As [`load_xml`].
pub fn parse_xml(text: &str, file_name: &str, scene_dir: &Path, options: CourseOptions) -> Result<Loaded> {
    let src = Source { name: file_name.to_owned(), dir: scene_dir.to_path_buf() };
    parse(text, &src, SceneFormat::CourseXml, options)
}

/// Reads JSON scene text that did not necessarily come from a file; see [`parse_xml`]
/// (JSON textures and meshes are found relative to the parent of `scene_dir`).
///
/// # Errors
///
/// As [`load_json`].
pub fn parse_json(text: &str, file_name: &str, scene_dir: &Path, options: CourseOptions) -> Result<Loaded> {
    let src = Source { name: file_name.to_owned(), dir: scene_dir.to_path_buf() };
    parse(text, &src, SceneFormat::CourseJson, options)
}

/// Reads course scene text that came from `path` (for [`crate::load_any`], which has
/// read the file already to tell its format).
pub(crate) fn load_text(path: &Path, text: &str, format: SceneFormat, options: CourseOptions) -> Result<Loaded> {
    parse(text, &source_of(path), format, options)
}

fn read(path: &Path) -> Result<(String, Source)> {
    let text = crate::input::read_text(path, crate::input::InputKind::Scene)?;
    Ok((text, source_of(path)))
}

fn source_of(path: &Path) -> Source {
    Source { name: path.display().to_string(), dir: path.parent().map(Path::to_path_buf).unwrap_or_default() }
}

fn parse(text: &str, src: &Source, format: SceneFormat, options: CourseOptions) -> Result<Loaded> {
    let mut warnings = Warnings::default();
    let model = match format {
        SceneFormat::CourseXml => xml::read(src, text, &mut warnings)?,
        _ => json::read(src, text, &mut warnings)?,
    };
    let scene = build::build(&model, src, options, &mut warnings)?;
    Ok(Loaded { scene, format, warnings: warnings.into_vec() })
}

/// Warnings in the order met, each given once (a template used many times would
/// otherwise repeat its warnings).
#[derive(Default)]
pub(crate) struct Warnings {
    list: Vec<String>,
    seen: HashSet<String>,
}

impl Warnings {
    /// Adds `file:line:col: message`.
    pub fn at(&mut self, src: &Source, pos: Pos, message: impl AsRef<str>) {
        let text = format!("{}: {}", src.origin(pos), message.as_ref());
        if self.seen.insert(text.clone()) {
            self.list.push(text);
        }
    }

    pub fn into_vec(self) -> Vec<String> {
        self.list
    }
}

type Result<T> = std::result::Result<T, SceneError>;

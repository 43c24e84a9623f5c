//! `glint convert`: any scene file → a native `.glint` file that renders the same image.
//!
//! The written text is read back and compared with the loaded scene before anything is
//! saved, so a scene the writer cannot reproduce is an error instead of a file that
//! quietly renders something else; the file is then saved atomically.

use std::path::{Path, PathBuf};

use crate::detect::{SceneFormat, load_any};
use crate::error::SceneError;
use crate::native::parse_scene;
use crate::native::writer::{WriteError, WriteOptions, difference, save_atomically, write_scene};

/// Why a conversion failed; nothing was written.
#[derive(Debug, thiserror::Error)]
pub enum ConvertError {
    /// The output name does not end in `.glint`.
    #[error("the output of convert is a .glint scene; name it '{}'", .suggested.display())]
    NotGlint {
        /// The output path with the `.glint` extension.
        suggested: PathBuf,
    },
    /// The input could not be loaded.
    #[error(transparent)]
    Load(#[from] SceneError),
    /// The scene holds something a `.glint` file cannot say.
    #[error("cannot write '{}': {source}", .path.display())]
    Write {
        /// The output file.
        path: PathBuf,
        /// What cannot be written.
        source: WriteError,
    },
    /// The written text does not read back to the same scene (a bug in the writer).
    #[error(
        "the scene written for '{}' does not read back the same ({detail}); nothing was written. \
         This is a bug in glint; please report it with the input file",
        .path.display()
    )]
    ReadBack {
        /// The output file.
        path: PathBuf,
        /// The first difference or the error reading it back.
        detail: String,
    },
    /// The file could not be saved.
    #[error("cannot write '{}': {source}", .path.display())]
    Io {
        /// The output file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
}

/// What a conversion read and what it could not carry over.
#[derive(Clone, Debug)]
pub struct Converted {
    /// The format the input was recognised as.
    pub format: SceneFormat,
    /// Warnings from loading (skipped or approximated parts) and from writing (settings
    /// the `.glint` format cannot hold yet).
    pub warnings: Vec<String>,
}

/// Loads `input` (any format) and writes it to `output` as `.glint`.
///
/// # Errors
///
/// A [`ConvertError`]; on every error nothing is left written (mesh files saved for
/// the scene are removed again).
pub fn convert(input: &Path, output: &Path) -> Result<Converted, ConvertError> {
    let is_glint = output.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("glint"));
    if !is_glint {
        return Err(ConvertError::NotGlint { suggested: output.with_extension("glint") });
    }
    let mut loaded = load_any(input)?;
    let dir = output.parent().map(Path::to_path_buf).unwrap_or_default();
    let saved_meshes = save_inline_meshes(&mut loaded.scene, output)?;
    let result = write_checked(input, output, &dir, loaded);
    if result.is_err() {
        for file in &saved_meshes {
            let _ = std::fs::remove_file(file);
        }
        // Only when empty: a folder that held other files stays.
        let _ = std::fs::remove_dir(output.with_extension("meshes"));
    }
    result
}

/// Writes `loaded` as `.glint` text to `output` after checking that it reads back.
fn write_checked(
    input: &Path,
    output: &Path,
    dir: &Path,
    loaded: crate::detect::Loaded,
) -> Result<Converted, ConvertError> {
    let dir = dir.to_path_buf();
    let options = WriteOptions {
        base_dir: Some(dir.clone()),
        comment: Some(format!("Converted by `glint convert` from {}.", input.display())),
    };
    let written = write_scene(&loaded.scene, &options)
        .map_err(|source| ConvertError::Write { path: output.to_path_buf(), source })?;
    let read_back = |detail: String| ConvertError::ReadBack { path: output.to_path_buf(), detail };
    let file_name =
        output.file_name().map_or_else(|| output.display().to_string(), |n| n.to_string_lossy().into_owned());
    let back = parse_scene(&written.text, &file_name, &dir).map_err(|e| read_back(e.to_string()))?;
    if let Some(detail) = difference(&loaded.scene, &back) {
        return Err(read_back(detail));
    }
    save_atomically(output, &written.text).map_err(|source| ConvertError::Io { path: output.to_path_buf(), source })?;
    let mut warnings = loaded.warnings;
    warnings.extend(written.warnings);
    Ok(Converted { format: loaded.format, warnings })
}

/// Saves each mesh that was built in the scene rather than read from a file (pbrt's
/// inline `trianglemesh`, a tessellated cylinder) as a PLY file beside `output`
/// (`OUT.meshes/N.ply`), so the `.glint` file can name it; returns the files written.
fn save_inline_meshes(scene: &mut glint_core::desc::SceneDesc, output: &Path) -> Result<Vec<PathBuf>, ConvertError> {
    let mut written = Vec::new();
    if scene.meshes.iter().all(|m| !m.path.is_empty()) {
        return Ok(written);
    }
    let folder = output.with_extension("meshes");
    let io = |source| ConvertError::Io { path: folder.clone(), source };
    std::fs::create_dir_all(&folder).map_err(io)?;
    for (index, mesh) in scene.meshes.iter_mut().enumerate().filter(|(_, m)| m.path.is_empty()) {
        let file = folder.join(format!("{index}.ply"));
        if let Err(source) = std::fs::write(&file, crate::ply_out::ply_bytes(mesh)) {
            for f in &written {
                let _ = std::fs::remove_file(f);
            }
            return Err(ConvertError::Io { path: file, source });
        }
        mesh.path = file.display().to_string();
        written.push(file);
    }
    Ok(written)
}

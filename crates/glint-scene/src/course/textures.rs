//! Finding the files a scene names (textures, meshes) the way the course does, with
//! fallbacks for the paths that course scenes commonly get wrong, and loading each
//! texture once.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

use glint_core::desc::{TextureDesc, Transfer};

use super::{Pos, Result, Source, Warnings};
use crate::error::SceneErrorKind;
use crate::texture_io;

/// Folders where course repositories keep their images, tried by file name when the
/// written path does not lead to the file.
const ASSET_FOLDERS: [&str; 4] = ["textures", "image", "images", "texture"];

/// The folder the course resolves a scene's relative asset paths against: the parent of
/// the scene file's folder (the course repositories keep `textures/`, `image/` and
/// `meshes/` beside the folders of scenes).
pub fn asset_base(scene_dir: &Path) -> PathBuf {
    scene_dir.parent().map(Path::to_path_buf).unwrap_or_else(|| scene_dir.join(".."))
}

/// Where `written` is found: the course's own resolution first, then fallbacks (the
/// scene's folder, the path without a leading `/` or `file:` prefix, the file name in
/// the usual asset folders near the scene). `None` when nothing exists; the first
/// candidate is the course's path, for messages.
pub fn resolve(scene_dir: &Path, written: &str) -> (PathBuf, Option<PathBuf>) {
    let base = asset_base(scene_dir);
    let primary = base.join(written);
    let mut candidates = vec![primary.clone()];
    let cleaned = written.trim_start_matches("file:").trim_start_matches(['/', '\\']);
    let relative = Path::new(cleaned);
    candidates.push(base.join(relative));
    candidates.push(scene_dir.join(relative));
    // A path that climbs out (`../../image_source/x.png`) usually meant a copy nearby.
    let climbs = relative.components().any(|c| c == Component::ParentDir);
    if let Some(file_name) = relative.file_name() {
        let mut dirs = vec![scene_dir.to_path_buf(), base.clone()];
        dirs.extend(base.parent().map(Path::to_path_buf));
        for dir in &dirs {
            for folder in ASSET_FOLDERS {
                candidates.push(dir.join(folder).join(file_name));
            }
            if climbs {
                candidates.push(dir.join(file_name));
            }
        }
    }
    let found = candidates.into_iter().find(|p| p.is_file());
    (primary, found)
}

/// Textures loaded so far, by the file they came from.
#[derive(Default)]
pub struct TextureCache {
    pub textures: Vec<TextureDesc>,
    by_path: HashMap<PathBuf, usize>,
    /// What each path as written came to, so a texture used by many primitives is
    /// resolved (and warned about) once.
    by_written: HashMap<String, Option<usize>>,
}

impl TextureCache {
    /// The index of the texture `written` at `pos`, loading it on first use. `Ok(None)`
    /// when it cannot be loaded and `strict` is false (a warning at its first use says
    /// why).
    pub fn get(
        &mut self,
        src: &Source,
        pos: Pos,
        written: &str,
        strict: bool,
        warnings: &mut Warnings,
    ) -> Result<Option<usize>> {
        if let Some(&known) = self.by_written.get(written) {
            return Ok(known);
        }
        let result = self.load(src, pos, written, strict, warnings)?;
        self.by_written.insert(written.to_owned(), result);
        Ok(result)
    }

    fn load(
        &mut self,
        src: &Source,
        pos: Pos,
        written: &str,
        strict: bool,
        warnings: &mut Warnings,
    ) -> Result<Option<usize>> {
        let (primary, found) = resolve(&src.dir, written);
        let Some(path) = found else {
            let message = format!(
                "texture file '{written}' not found: looked for '{}' (course paths are relative to the \
                 folder above the scene's folder) and for '{}' in the folders {} near the scene",
                primary.display(),
                Path::new(written).file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                ASSET_FOLDERS.join(", "),
            );
            return self.fail(src, pos, message, strict, warnings);
        };
        if path != primary {
            warnings.at(
                src,
                pos,
                format!(
                    "texture file '{written}' is not at '{}' where the course looks; using '{}'",
                    primary.display(),
                    path.display()
                ),
            );
        }
        if let Some(&index) = self.by_path.get(&path) {
            return Ok(Some(index));
        }
        let name = path.display().to_string();
        // Course images are display values shaded as they are stored: no sRGB decoding.
        match texture_io::load_texture_encoded(&name, &path, Transfer::Identity) {
            Ok(texture) => {
                let index = self.textures.len();
                self.textures.push(texture);
                self.by_path.insert(path, index);
                Ok(Some(index))
            }
            Err(e) => self.fail(src, pos, e.to_string(), strict, warnings),
        }
    }

    fn fail(
        &mut self,
        src: &Source,
        pos: Pos,
        message: String,
        strict: bool,
        warnings: &mut Warnings,
    ) -> Result<Option<usize>> {
        if strict {
            return Err(src.error(SceneErrorKind::Io, pos, message));
        }
        warnings.at(src, pos, format!("{message}; the surface is rendered without its texture"));
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn asset_base_is_the_parent_of_the_scene_folder() {
        assert_eq!(asset_base(Path::new("a/b")), PathBuf::from("a"));
        assert_eq!(asset_base(Path::new("")), PathBuf::from("").join(".."));
    }
}

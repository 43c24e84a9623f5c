//! Noticing that a scene changed on disk, by polling modification times.
//!
//! Polling a handful of files every 200 ms costs microseconds, needs no dependency and
//! works the same on every file system (network mounts and editors that save by
//! renaming included), which is why it is used here instead of OS notifications. The
//! files watched are the scene, the files it includes (found by reading `include "…"`
//! lines, recursively), and the meshes and textures the loaded scene names.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use glint_core::desc::{SceneDesc, TextureDesc};

/// How deep `include` chains are followed (the native reader stops at 32 too).
const MAX_INCLUDE_DEPTH: usize = 32;

/// The files a scene is made of and when each last changed.
#[derive(Debug, Default)]
pub struct Watcher {
    stamps: BTreeMap<PathBuf, Option<SystemTime>>,
}

impl Watcher {
    /// Watches `scene` and everything it draws on, as `desc` (its latest good load) names it.
    pub fn new(scene: &Path, desc: Option<&SceneDesc>) -> Self {
        let mut files = vec![scene.to_path_buf()];
        includes(scene, &mut files, 0);
        if let Some(desc) = desc {
            files.extend(assets(scene, desc));
        }
        Self { stamps: files.into_iter().map(|f| (f.clone(), modified(&f))).collect() }
    }

    /// True once after any watched file was written, created or removed.
    pub fn changed(&mut self) -> bool {
        let mut changed = false;
        for (path, stamp) in &mut self.stamps {
            let now = modified(path);
            if now != *stamp {
                *stamp = now;
                changed = true;
            }
        }
        changed
    }

    /// The files watched.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.stamps.keys().map(PathBuf::as_path)
    }
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

/// Files named by `include "…"` lines of `file`, relative to its folder, and theirs.
fn includes(file: &Path, found: &mut Vec<PathBuf>, depth: usize) {
    let Ok(text) = std::fs::read_to_string(file) else { return };
    let dir = file.parent().unwrap_or(Path::new(""));
    for line in text.lines() {
        let Some(rest) = line.trim_start().strip_prefix("include") else { continue };
        let Some(name) = rest.trim_start().strip_prefix('"').and_then(|r| r.split('"').next()) else { continue };
        let path = dir.join(name);
        if depth < MAX_INCLUDE_DEPTH && !found.contains(&path) {
            found.push(path.clone());
            includes(&path, found, depth + 1);
        }
    }
}

/// Mesh and texture files of `desc`, as written or relative to the scene's folder.
fn assets(scene: &Path, desc: &SceneDesc) -> Vec<PathBuf> {
    let meshes = desc.meshes.iter().map(|m| m.path.as_str());
    let textures = desc.textures.iter().filter_map(|t| match t {
        TextureDesc::Image { path, .. } => Some(path.as_str()),
        _ => None,
    });
    let dir = scene.parent().unwrap_or(Path::new(""));
    meshes
        .chain(textures)
        .filter(|p| !p.is_empty())
        .map(|p| if Path::new(p).exists() { PathBuf::from(p) } else { dir.join(p) })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_included_file_is_watched_and_its_change_noticed_once() {
        let dir = std::env::temp_dir().join(format!("glint-view-watch-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (scene, part) = (dir.join("a.glint"), dir.join("b.glint"));
        std::fs::write(&scene, "include \"b.glint\"\n").unwrap();
        std::fs::write(&part, "# nothing\n").unwrap();
        let mut watcher = Watcher::new(&scene, None);
        assert!(watcher.files().any(|f| f == part));
        assert!(!watcher.changed());
        std::fs::remove_file(&part).unwrap();
        assert!(watcher.changed());
        assert!(!watcher.changed());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

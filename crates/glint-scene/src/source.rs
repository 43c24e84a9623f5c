//! Where scene text comes from: one position type and one file handle shared by every
//! text importer, so all of them locate errors and node origins the same way.

use std::path::PathBuf;

use crate::error::{SceneError, SceneErrorKind};

/// A 1-based line and column (in characters; a tab is one column) in a source file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Pos {
    /// 1-based line number.
    pub line: u32,
    /// 1-based column, counted in characters.
    pub column: u32,
}

/// The file being read: its name for messages and its folder for relative paths.
pub struct Source {
    /// The file as it appears in messages and node origins.
    pub name: String,
    /// Folder that relative paths (includes, textures, meshes) in this file start from.
    pub dir: PathBuf,
}

impl Source {
    /// An error located in this file.
    pub fn error(&self, kind: SceneErrorKind, pos: Pos, message: impl Into<String>) -> SceneError {
        SceneError::new(kind, self.name.clone(), pos.line, pos.column, message)
    }

    /// A scene-meaning error located in this file.
    pub fn invalid(&self, pos: Pos, message: impl Into<String>) -> SceneError {
        self.error(SceneErrorKind::Invalid, pos, message)
    }

    /// `file:line:col`, the origin recorded on scene nodes and the prefix of warnings.
    pub fn origin(&self, pos: Pos) -> String {
        format!("{}:{}:{}", self.name, pos.line, pos.column)
    }
}

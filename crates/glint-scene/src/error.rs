//! The one error type of scene loading.
//!
//! A person who wrote a scene by hand needs to know where the mistake is and what would
//! have been accepted, so every error carries the file, line and column it is about and
//! a message that names both the problem and the allowed alternatives.

/// Which stage rejected the scene, for callers that react differently to each (an editor
/// might re-read a file on [`SceneErrorKind::Io`] but not on a syntax error).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneErrorKind {
    /// The text is not a well-formed node tree (bad token, missing brace, …).
    Syntax,
    /// The tree is well formed but does not describe a valid scene (unknown property,
    /// wrong number of values, unknown material, value out of range, include cycle, …).
    Invalid,
    /// A file (the scene, an included file or a texture) could not be read or decoded.
    Io,
}

/// An error while reading a scene, located at `file:line:column`.
///
/// `Display` gives `FILE:LINE:COL: MESSAGE`, the form editors and terminals turn into a
/// link. `line` and `column` are 1-based; both are 0 when the error concerns a whole file
/// (e.g. the scene file itself is missing), and `Display` then prints `FILE: MESSAGE`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}{message}", location_prefix(.file, .line, .column))]
pub struct SceneError {
    /// Which stage rejected the scene.
    pub kind: SceneErrorKind,
    /// The file the error points into, as the user named it (or a pseudo-name such as
    /// `<default scene>` for text that did not come from a file).
    pub file: String,
    /// 1-based line, or 0 when the error concerns the whole file.
    pub line: u32,
    /// 1-based column in characters, or 0 when the error concerns the whole file.
    pub column: u32,
    /// What is wrong and what would be allowed instead.
    pub message: String,
}

impl SceneError {
    /// Builds an error at a position; the single constructor keeps every error located.
    pub fn new(
        kind: SceneErrorKind,
        file: impl Into<String>,
        line: u32,
        column: u32,
        message: impl Into<String>,
    ) -> Self {
        Self { kind, file: file.into(), line, column, message: message.into() }
    }

    /// The 1-based line the error points at (0 for whole-file errors), for tests and tools
    /// that jump to the mistake.
    pub fn line(&self) -> u32 {
        self.line
    }

    /// The 1-based column the error points at (0 for whole-file errors).
    pub fn column(&self) -> u32 {
        self.column
    }

    /// `file:line:column` (or just `file` for whole-file errors), the prefix of `Display`.
    pub fn location(&self) -> String {
        if self.line == 0 { self.file.clone() } else { format!("{}:{}:{}", self.file, self.line, self.column) }
    }
}

/// The `FILE:LINE:COL: ` prefix of [`SceneError`]'s `Display`.
fn location_prefix(file: &str, line: &u32, column: &u32) -> String {
    if *line == 0 { format!("{file}: ") } else { format!("{file}:{line}:{column}: ") }
}

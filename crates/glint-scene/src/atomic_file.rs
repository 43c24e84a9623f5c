//! Files replaced whole or not at all: written beside their place, then renamed into it.

use std::path::{Path, PathBuf};

/// Writes the file at `path` through a temporary sibling that `write` fills and a rename
/// puts in place (atomic on one file system), so a failed or interrupted write never
/// leaves a half-written file at `path`. `io_error` turns the rename's error into `E`.
///
/// # Errors
///
/// What `write` or the rename returned, after removing the temporary file.
pub(crate) fn write_atomically<E>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
    io_error: impl FnOnce(std::io::Error) -> E,
) -> Result<(), E> {
    let tmp = temp_sibling(path);
    let result = write(&tmp).and_then(|()| std::fs::rename(&tmp, path).map_err(io_error));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// A hidden name in the same directory, unique to this process.
fn temp_sibling(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

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

/// Writes `bytes` to `path` so that after a crash or a power cut the file holds either
/// its old content or all of `bytes`: the data is flushed to the disk before the rename
/// puts it in place, and the rename before this returns. For state a later run depends
/// on (render checkpoints), where an image can simply be written again.
///
/// # Errors
///
/// Creating, writing, flushing or renaming failed; no temporary file is left behind.
pub fn write_durably(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    write_atomically(
        path,
        |tmp| {
            let mut file = std::fs::File::create(tmp)?;
            file.write_all(bytes)?;
            file.sync_all()
        },
        |e| e,
    )?;
    // The rename lives in the directory: flush it too (not possible on every platform).
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if let Ok(dir) = std::fs::File::open(dir) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// A hidden name in the same directory, unique to this process.
fn temp_sibling(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

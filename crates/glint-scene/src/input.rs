//! Bounded input: every file glint reads comes through here.
//!
//! A file is checked before it is opened — it must be a regular file (a directory, a
//! FIFO or a device such as `/dev/zero` is refused by name, and a FIFO is never opened,
//! since opening one blocks until a writer comes) no larger than the limit for its
//! [`InputKind`] — and then read through a bound of one byte past that limit, so a file
//! that grows after the check, or one whose reported size is wrong (`/proc`), is still
//! refused. No input can therefore make glint hold more than its limit in file bytes.
//!
//! The limits are process-wide ([`set_limits`]; the CLI's `--input-limit KIND=SIZE`), so
//! that every loader, however deep (a texture of a material of an included file), obeys
//! the same ones without a context threaded through each of them.

use std::fs::File;
use std::io::{self, Read};
use std::path::{Path, PathBuf};
use std::sync::{PoisonError, RwLock};

use crate::error::{SceneError, SceneErrorKind};

/// What a file is read as; each kind has its own size limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InputKind {
    /// Scene text in any format, and the files it includes.
    Scene,
    /// A mesh file: OBJ with its MTL libraries, PLY, glTF/GLB with its buffers (and the
    /// `glint bench --input` file, which is a mesh and its rays).
    Mesh,
    /// An image file: a texture or an environment map.
    Image,
}

impl InputKind {
    /// The name of the kind in `--input-limit KIND=SIZE`.
    pub fn key(self) -> &'static str {
        match self {
            InputKind::Scene => "scene",
            InputKind::Mesh => "mesh",
            InputKind::Image => "image",
        }
    }

    /// "scene file", … for messages.
    fn noun(self) -> &'static str {
        match self {
            InputKind::Scene => "scene file",
            InputKind::Mesh => "mesh file",
            InputKind::Image => "image file",
        }
    }
}

/// The largest inputs glint accepts. The defaults are far beyond any scene glint
/// targets and small enough that a mistaken path (a disk image, a video) is refused
/// before it is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputLimits {
    /// Largest scene file or included file, in bytes (default 256 MiB).
    pub scene_bytes: u64,
    /// Largest mesh file, MTL library or glTF buffer, in bytes (default 4 GiB).
    pub mesh_bytes: u64,
    /// Largest texture or environment map file, in bytes (default 1 GiB).
    pub image_bytes: u64,
    /// Most pixels a decoded image may have (default 2²⁶ = 8192 × 8192, or 16384 ×
    /// 4096). Decoding needs up to 16 bytes a pixel and the texture 12 more.
    pub image_pixels: u64,
}

impl InputLimits {
    /// The limits glint starts with.
    pub const DEFAULT: InputLimits =
        InputLimits { scene_bytes: 256 << 20, mesh_bytes: 4 << 30, image_bytes: 1 << 30, image_pixels: 1 << 26 };

    /// The byte limit for files of `kind`.
    pub fn bytes(&self, kind: InputKind) -> u64 {
        match kind {
            InputKind::Scene => self.scene_bytes,
            InputKind::Mesh => self.mesh_bytes,
            InputKind::Image => self.image_bytes,
        }
    }
}

impl Default for InputLimits {
    fn default() -> Self {
        InputLimits::DEFAULT
    }
}

static LIMITS: RwLock<InputLimits> = RwLock::new(InputLimits::DEFAULT);

/// The limits every loader obeys now.
pub fn limits() -> InputLimits {
    *LIMITS.read().unwrap_or_else(PoisonError::into_inner)
}

/// Replaces the limits for every later read in this process.
pub fn set_limits(limits: InputLimits) {
    *LIMITS.write().unwrap_or_else(PoisonError::into_inner) = limits;
}

/// A file that could not be read; `Display` names it, its kind and the reason.
#[derive(Debug, thiserror::Error)]
#[error("cannot read {} '{}': {problem}", kind.noun(), path.display())]
pub struct InputError {
    /// The file as it was named.
    pub path: PathBuf,
    /// What it was to be read as.
    pub kind: InputKind,
    /// Why it was refused, without the file's name (for messages that name it already).
    pub problem: InputProblem,
}

/// Why a file was refused.
#[derive(Debug, thiserror::Error)]
pub enum InputProblem {
    /// The operating system's reason (missing, no permission, …).
    #[error("{0}")]
    Io(#[from] io::Error),
    /// A directory, FIFO, device or socket.
    #[error("it is {0}, not a regular file")]
    NotAFile(&'static str),
    /// Larger than the limit for its kind: `size` is its size, or `None` when it grew
    /// past the limit while being read.
    #[error("{}", too_large(.size, .limit, .kind))]
    TooLarge {
        /// The size the file reported.
        size: Option<u64>,
        /// The limit it broke.
        limit: u64,
        /// The kind whose limit it is.
        kind: InputKind,
    },
    /// Scene text that is not UTF-8.
    #[error("it is not UTF-8 text (byte {0} starts an invalid sequence)")]
    NotText(usize),
}

fn too_large(size: &Option<u64>, limit: &u64, kind: &InputKind) -> String {
    let (limit, kind) = (*limit, *kind);
    let what = match size {
        Some(size) => format!("it is {}, more than", human_size(*size)),
        None => "it grew past".to_owned(),
    };
    format!(
        "{what} the {} allowed for {} {}; raise the limit with --input-limit {}=SIZE",
        human_size(limit),
        if kind == InputKind::Image { "an" } else { "a" },
        kind.noun(),
        kind.key()
    )
}

/// `bytes` in the largest binary unit that keeps it at or above 1, e.g. "256 MiB".
pub fn human_size(bytes: u64) -> String {
    const UNITS: [&str; 6] = ["KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut value = bytes as f64;
    let mut unit = "";
    for u in UNITS {
        if value < 1024.0 {
            break;
        }
        value /= 1024.0;
        unit = u;
    }
    let text = format!("{value:.1}");
    format!("{} {unit}", text.strip_suffix(".0").unwrap_or(&text))
}

impl From<InputError> for SceneError {
    /// An error about the whole file (line 0).
    fn from(e: InputError) -> Self {
        let message = format!("cannot read {}: {}", e.kind.noun(), e.problem);
        SceneError::new(SceneErrorKind::Io, e.path.display().to_string(), 0, 0, message)
    }
}

/// An open file that yields at most one byte more than its kind's limit.
pub struct Bounded {
    reader: io::Take<File>,
    path: PathBuf,
    kind: InputKind,
    limit: u64,
    /// The size the file reported when it was opened.
    size: u64,
}

impl Bounded {
    /// The size the file reported when it was opened (at most the limit).
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Reads the rest of the file onto `bytes` (what was read from it already, if any).
    ///
    /// # Errors
    ///
    /// An [`InputError`] when reading fails or the file holds more than the limit.
    pub fn finish(mut self, mut bytes: Vec<u8>) -> Result<Vec<u8>, InputError> {
        bytes.reserve(usize::try_from(self.size).unwrap_or(0).saturating_sub(bytes.len()));
        self.reader.read_to_end(&mut bytes).map_err(|e| self.error(e.into()))?;
        // The bound is limit + 1: all of it used means the file is larger than the limit.
        if self.reader.limit() == 0 {
            return Err(self.error(InputProblem::TooLarge { size: None, limit: self.limit, kind: self.kind }));
        }
        Ok(bytes)
    }

    fn error(&self, problem: InputProblem) -> InputError {
        InputError { path: self.path.clone(), kind: self.kind, problem }
    }
}

impl Read for Bounded {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.reader.read(buf)
    }
}

/// Opens `path` as a file of `kind` under the current [`limits`].
///
/// # Errors
///
/// An [`InputError`] when the file is missing, is not a regular file, or is larger
/// than the limit for `kind`.
pub fn open(path: &Path, kind: InputKind) -> Result<Bounded, InputError> {
    open_with(path, kind, &limits())
}

/// Opens `path` as a file of `kind` under `limits`.
///
/// # Errors
///
/// As [`open`].
pub fn open_with(path: &Path, kind: InputKind, limits: &InputLimits) -> Result<Bounded, InputError> {
    let error = |problem| InputError { path: path.to_path_buf(), kind, problem };
    // Look before opening: opening a FIFO for reading waits for a writer, maybe forever.
    let meta = std::fs::metadata(path).map_err(|e| error(e.into()))?;
    check_regular(&meta).map_err(error)?;
    let limit = limits.bytes(kind);
    if meta.len() > limit {
        return Err(error(InputProblem::TooLarge { size: Some(meta.len()), limit, kind }));
    }
    let file = open_nonblocking(path).map_err(|e| error(e.into()))?;
    // The path may have been replaced since the look: check what was opened.
    let meta = file.metadata().map_err(|e| error(e.into()))?;
    check_regular(&meta).map_err(error)?;
    let size = meta.len().min(limit);
    Ok(Bounded { reader: file.take(limit.saturating_add(1)), path: path.to_path_buf(), kind, limit, size })
}

/// Opens for reading without waiting for a FIFO's writer (reading a regular file is
/// unaffected by `O_NONBLOCK`).
fn open_nonblocking(path: &Path) -> io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path)
}

/// Refuses anything but a regular file, naming what it is.
fn check_regular(meta: &std::fs::Metadata) -> Result<(), InputProblem> {
    let kind = meta.file_type();
    if kind.is_file() {
        return Ok(());
    }
    let what = if kind.is_dir() { "a directory" } else { special_file(&kind) };
    Err(InputProblem::NotAFile(what))
}

#[cfg(unix)]
fn special_file(kind: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_fifo() {
        "a FIFO (named pipe)"
    } else if kind.is_char_device() {
        "a character device"
    } else if kind.is_block_device() {
        "a block device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_file(_: &std::fs::FileType) -> &'static str {
    "a special file"
}

/// Reads the whole file `path` of `kind` under the current [`limits`].
///
/// # Errors
///
/// As [`open`], and when reading fails or the file grows past the limit.
pub fn read_bytes(path: &Path, kind: InputKind) -> Result<Vec<u8>, InputError> {
    open(path, kind)?.finish(Vec::new())
}

/// Reads the whole file `path` of `kind` as UTF-8 text under the current [`limits`].
///
/// # Errors
///
/// As [`read_bytes`], and when the file is not UTF-8.
pub fn read_text(path: &Path, kind: InputKind) -> Result<String, InputError> {
    text(path, kind, read_bytes(path, kind)?)
}

fn text(path: &Path, kind: InputKind, bytes: Vec<u8>) -> Result<String, InputError> {
    String::from_utf8(bytes).map_err(|e| InputError {
        path: path.to_path_buf(),
        kind,
        problem: InputProblem::NotText(e.utf8_error().valid_up_to()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("glint-input-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_raised_limit_lets_a_file_through() {
        let dir = folder("raise");
        let path = dir.join("scene.glint");
        std::fs::write(&path, vec![b'#'; 3000]).unwrap();
        let small = InputLimits { scene_bytes: 2048, ..InputLimits::DEFAULT };
        let e = open_with(&path, InputKind::Scene, &small).err().expect("over the limit");
        let message = e.to_string();
        assert!(message.contains("scene.glint") && message.contains("2 KiB"), "{message}");
        assert!(message.contains("--input-limit scene=SIZE"), "{message}");
        let raised = InputLimits { scene_bytes: 3000, ..small };
        let bytes = open_with(&path, InputKind::Scene, &raised).unwrap().finish(Vec::new()).unwrap();
        assert_eq!(bytes.len(), 3000);
        // Limits are per kind: the same file is a small mesh.
        assert!(open_with(&path, InputKind::Mesh, &small).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_larger_than_it_reports_is_cut_at_the_limit() {
        // /proc files report size 0 and hold more.
        let path = Path::new("/proc/self/status");
        if !path.exists() {
            return;
        }
        let tiny = InputLimits { scene_bytes: 16, ..InputLimits::DEFAULT };
        let e = open_with(path, InputKind::Scene, &tiny).unwrap().finish(Vec::new()).unwrap_err();
        assert!(e.to_string().contains("grew past the 16 bytes allowed"), "{e}");
    }

    #[test]
    fn directories_and_devices_are_refused_by_name() {
        let dir = folder("kinds");
        let e = read_bytes(&dir, InputKind::Image).unwrap_err();
        assert!(e.to_string().ends_with("is a directory, not a regular file"), "{e}");
        if Path::new("/dev/zero").exists() {
            let e = read_text(Path::new("/dev/zero"), InputKind::Scene).unwrap_err();
            assert_eq!(
                e.to_string(),
                "cannot read scene file '/dev/zero': it is a character device, not a regular file"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn sizes_read_in_binary_units() {
        assert_eq!(human_size(1023), "1023 bytes");
        assert_eq!(human_size(256 << 20), "256 MiB");
        assert_eq!(human_size(10 << 30), "10 GiB");
        assert_eq!(human_size(1536), "1.5 KiB");
    }
}

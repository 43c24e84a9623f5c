//! `--checkpoint` and `--resume`: a CPU render's finished tiles saved to a file every
//! few seconds, so a render killed by a signal or a power cut goes on where it was
//! and still writes the image an uninterrupted render writes.

use std::collections::BTreeSet;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::mpsc;
use std::time::Duration;

use glint_core::desc::SceneDesc;
use glint_core::fnv::Fnv1a;
use glint_core::render::{TileStore, checkpoint_header, max_checkpoint_len};
use glint_core::scene::RenderScene;
use glint_scene::atomic_file::write_durably;

/// Seconds between checkpoints unless `--checkpoint-every` says otherwise.
pub const DEFAULT_INTERVAL_SECONDS: f64 = 5.0;

/// The finished tiles of one render and the journal they are appended to.
pub struct Checkpointer {
    path: PathBuf,
    every: Duration,
    store: TileStore,
    journal: Mutex<Journal>,
    /// The first save that failed: the render goes on, and the caller warns.
    failure: Mutex<Option<String>>,
}

/// The open checkpoint file, its length, and the tiles already in it.
struct Journal {
    file: File,
    len: u64,
    written: BTreeSet<u32>,
}

impl Checkpointer {
    /// A render that starts afresh and saves to `path`, replacing what is there.
    ///
    /// # Errors
    ///
    /// The file cannot be written.
    pub fn fresh(scene: &RenderScene, desc: &SceneDesc, path: PathBuf, every: Duration) -> Result<Self, String> {
        Self::start(scene, desc, path, every, TileStore::default())
    }

    /// A render that goes on from the checkpoint at `from` and saves to `path` (which
    /// may be `from`: then the tiles after a record torn by the interruption are cut
    /// off, and saving appends where the last whole record ends).
    ///
    /// # Errors
    ///
    /// A sentence naming `from`: it is missing, not a regular file, too large for this
    /// scene's checkpoint, damaged, or made for another scene or other settings; or
    /// `path` cannot be written.
    pub fn resume(
        scene: &RenderScene,
        desc: &SceneDesc,
        from: &Path,
        path: PathBuf,
        every: Duration,
    ) -> Result<Self, String> {
        let bytes = read_checkpoint(from, scene)?;
        let restored = TileStore::from_checkpoint(&bytes, scene, fingerprint(scene, desc))
            .map_err(|e| format!("cannot resume from '{}': {e}", from.display()))?;
        if same_file(from, &path) {
            let cannot = |e: std::io::Error| format!("cannot append to the checkpoint '{}': {e}", path.display());
            let file = std::fs::OpenOptions::new().append(true).open(&path).map_err(cannot)?;
            file.set_len(restored.valid_len as u64).and_then(|()| file.sync_all()).map_err(cannot)?;
            let journal = Journal { file, len: restored.valid_len as u64, written: restored.store.indices() };
            return Ok(Self::with(path, every, restored.store, journal));
        }
        Self::start(scene, desc, path, every, restored.store)
    }

    /// Writes a new journal at `path` holding the header and `store`'s tiles.
    fn start(
        scene: &RenderScene,
        desc: &SceneDesc,
        path: PathBuf,
        every: Duration,
        store: TileStore,
    ) -> Result<Self, String> {
        let mut written = BTreeSet::new();
        let mut bytes = checkpoint_header(scene, fingerprint(scene, desc));
        bytes.extend(store.new_records(&mut written));
        let cannot = |e: std::io::Error| format!("cannot write the checkpoint '{}': {e}", path.display());
        write_durably(&path, &bytes).map_err(cannot)?;
        let file = std::fs::OpenOptions::new().append(true).open(&path).map_err(cannot)?;
        Ok(Self::with(path, every, store, Journal { file, len: bytes.len() as u64, written }))
    }

    fn with(path: PathBuf, every: Duration, store: TileStore, journal: Journal) -> Self {
        Self { path, every, store, journal: Mutex::new(journal), failure: Mutex::new(None) }
    }

    /// The tiles the render fills (and, when resuming, starts from).
    pub fn store(&self) -> &TileStore {
        &self.store
    }

    /// Runs `render`, saving every interval meanwhile and once more when it returns
    /// (finished or cancelled).
    pub fn run<R: Send>(&self, render: impl FnOnce() -> R + Send) -> R {
        let (done, wait) = mpsc::channel::<()>();
        let result = std::thread::scope(|scope| {
            scope.spawn(move || {
                while let Err(mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(self.every) {
                    self.save();
                }
            });
            let result = render();
            drop(done);
            result
        });
        self.save();
        result
    }

    /// Appends the tiles finished since the last save and flushes them to the disk.
    fn save(&self) {
        let mut journal = self.journal.lock().unwrap_or_else(|p| p.into_inner());
        let Journal { file, len, written } = &mut *journal;
        let before = written.clone();
        let records = self.store.new_records(written);
        if records.is_empty() {
            return;
        }
        match file.write_all(&records).and_then(|()| file.sync_data()) {
            Ok(()) => *len += records.len() as u64,
            Err(e) => {
                // Cut off what was half written; those tiles are tried again next time.
                *written = before;
                let _ = file.set_len(*len);
                let mut failure = self.failure.lock().unwrap_or_else(|p| p.into_inner());
                failure.get_or_insert_with(|| format!("could not save the checkpoint '{}': {e}", self.path.display()));
            }
        }
    }

    /// The file the tiles are saved to.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Why a save failed, if one did.
    pub fn failure(&self) -> Option<String> {
        self.failure.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }

    /// Deletes the file once the image it was for is written: it has served.
    pub fn remove(&self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Everything that decides the image: the scene after the command line's changes, the
/// AOVs kept, and this glint's version (another build may trace differently). Parts and
/// checkpoints carry it, so only pieces of one render are put together.
pub fn fingerprint(scene: &RenderScene, desc: &SceneDesc) -> u64 {
    let mut hash = Fnv1a::default();
    hash.update(&desc.fingerprint().to_le_bytes());
    hash.update(&[u8::from(scene.settings.aovs)]);
    hash.update(env!("CARGO_PKG_VERSION").as_bytes());
    hash.finish()
}

/// The checkpoint's bytes, after checking it is a regular file no larger than any
/// checkpoint of `scene` can be.
fn read_checkpoint(path: &Path, scene: &RenderScene) -> Result<Vec<u8>, String> {
    let fail = |why: String| format!("cannot resume from '{}': {why}", path.display());
    let meta = std::fs::metadata(path).map_err(|e| fail(e.to_string()))?;
    if !meta.is_file() {
        return Err(fail("not a regular file".into()));
    }
    if meta.len() > max_checkpoint_len(scene) {
        return Err(fail(format!("{} bytes is more than any checkpoint of this scene holds", meta.len())));
    }
    std::fs::read(path).map_err(|e| fail(e.to_string()))
}

/// Whether `a` and `b` name the same file (`b` may not exist yet).
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

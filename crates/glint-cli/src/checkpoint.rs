//! `--checkpoint` and `--resume`: a CPU render's finished tiles saved to a file every
//! few seconds, so a render killed by a signal or a power cut goes on where it was
//! and still writes the image an uninterrupted render writes.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::mpsc;
use std::time::Duration;

use glint_core::desc::SceneDesc;
use glint_core::fnv::Fnv1a;
use glint_core::render::{TileStore, max_checkpoint_len};
use glint_core::scene::RenderScene;
use glint_scene::atomic_file::write_durably;

/// Seconds between checkpoints unless `--checkpoint-every` says otherwise.
pub const DEFAULT_INTERVAL_SECONDS: f64 = 5.0;

/// The finished tiles of one render and the file they are saved to.
pub struct Checkpointer<'a> {
    scene: &'a RenderScene,
    path: PathBuf,
    every: Duration,
    fingerprint: u64,
    store: TileStore,
    /// Tiles in the file as last saved: an unchanged store is not written again.
    saved: Mutex<usize>,
    /// The first save that failed: the render goes on, and the caller warns.
    failure: Mutex<Option<String>>,
}

impl<'a> Checkpointer<'a> {
    /// A render that starts afresh and saves to `path`, replacing what is there.
    pub fn fresh(scene: &'a RenderScene, desc: &SceneDesc, path: PathBuf, every: Duration) -> Self {
        Self::with_store(scene, desc, path, every, TileStore::default())
    }

    /// A render that goes on from the checkpoint at `from` and saves to `path`.
    ///
    /// # Errors
    ///
    /// A sentence naming `from`: it is missing, not a regular file, too large for this
    /// scene's checkpoint, damaged, or made for another scene or other settings.
    pub fn resume(
        scene: &'a RenderScene,
        desc: &SceneDesc,
        from: &Path,
        path: PathBuf,
        every: Duration,
    ) -> Result<Self, String> {
        let fingerprint = fingerprint(scene, desc);
        let bytes = read_checkpoint(from, scene)?;
        let store = TileStore::from_checkpoint(&bytes, scene, fingerprint)
            .map_err(|e| format!("cannot resume from '{}': {e}", from.display()))?;
        Ok(Self::with_store(scene, desc, path, every, store))
    }

    fn with_store(scene: &'a RenderScene, desc: &SceneDesc, path: PathBuf, every: Duration, store: TileStore) -> Self {
        let saved = Mutex::new(store.len());
        Self { scene, path, every, fingerprint: fingerprint(scene, desc), store, saved, failure: Mutex::new(None) }
    }

    /// The tiles the render fills (and, when resuming, starts from).
    pub fn store(&self) -> &TileStore {
        &self.store
    }

    /// Runs `render`, saving the store every interval meanwhile and once more when it
    /// returns (finished or cancelled).
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

    /// Writes the store to the file, durably, unless it is as last saved.
    fn save(&self) {
        let mut saved = self.saved.lock().unwrap_or_else(|p| p.into_inner());
        let tiles = self.store.len();
        if tiles == *saved && self.path.exists() {
            return;
        }
        let bytes = self.store.to_checkpoint(self.scene, self.fingerprint);
        match write_durably(&self.path, &bytes) {
            Ok(()) => *saved = tiles,
            Err(e) => {
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
/// AOVs kept, and this glint's version (another build may trace differently).
fn fingerprint(scene: &RenderScene, desc: &SceneDesc) -> u64 {
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

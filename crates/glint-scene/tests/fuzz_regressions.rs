//! Replays the inputs the fuzz targets found, and a few seeds, on stable Rust: every
//! file under `tests/fuzz_regressions/<target>/` goes through the very call its target
//! makes (the code in `fuzz/src/` is included here), and must come back — a scene or an
//! error — without a panic and within a time bound.

#[allow(dead_code)]
#[path = "../../../fuzz/src/readers.rs"]
mod readers;
#[path = "../../../fuzz/src/scene_gen.rs"]
mod scene_gen;

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use arbitrary::{Arbitrary, Unstructured};

/// The longest one input may take: the fuzzers' own `-timeout`.
const TIME_BOUND: Duration = Duration::from_secs(10);

/// The structure-aware render target, decoding its input as `libfuzzer-sys` does.
fn render_scene(data: &[u8]) {
    if let Ok(scene) = scene_gen::FuzzScene::arbitrary_take_rest(Unstructured::new(data)) {
        scene_gen::render_checked(&scene);
    }
}

/// The saved inputs of `target`, sorted so failures are listed in a stable order.
fn inputs(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions").join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("readable folder").path())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "{} holds no inputs: the harness would test nothing", dir.display());
    files
}

/// Runs `read` on the bytes of `file` on its own thread; `Err` says how it failed.
fn replay(read: readers::Target, file: &Path) -> Result<(), String> {
    let data = std::fs::read(file).map_err(|e| format!("cannot read it: {e}"))?;
    let (done, finished) = mpsc::channel();
    std::thread::spawn(move || {
        read(&data);
        let _ = done.send(());
    });
    match finished.recv_timeout(TIME_BOUND) {
        Ok(()) => Ok(()),
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!("took more than {TIME_BOUND:?}")),
        Err(mpsc::RecvTimeoutError::Disconnected) => Err("panicked".to_owned()),
    }
}

/// Replays every input of every target, then lists all the failures at once.
#[test]
fn saved_fuzz_inputs_are_read_without_panic_or_hang() {
    let targets = readers::TARGETS.iter().copied().chain([("render_scene", render_scene as readers::Target)]);
    let mut failures = Vec::new();
    for (target, read) in targets {
        for file in inputs(target) {
            if let Err(why) = replay(read, &file) {
                failures.push(format!("{target}: {}: {why}", file.display()));
            }
        }
    }
    assert!(failures.is_empty(), "{} inputs failed:\n{}", failures.len(), failures.join("\n"));
}

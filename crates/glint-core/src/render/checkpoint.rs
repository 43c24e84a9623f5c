//! A render's resumable state: its finished tiles, kept as they finish and saved bit
//! for bit, so a render killed midway resumes and still gives the uninterrupted image.
//!
//! A checkpoint is a journal in little-endian binary: a header (magic, version, image
//! and tile counts, scene fingerprint, checksum), then one record per finished tile
//! (length, index, film sums, sample counts, rays, non-finite tallies, checksum),
//! appended as tiles finish. Each tile is written once, so saving costs the same for a
//! huge image as for a small one, and a record torn by a crash mid-append only loses
//! the tiles from it on. The core makes and reads the bytes; the caller writes them.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Mutex;

use glam::Vec3;

use super::{NonFiniteSamples, SourceTally, tile_count, tile_rects};
use crate::film::FilmTile;
use crate::fnv::fnv1a;
use crate::integrator::SurfaceId;
use crate::scene::RenderScene;

const MAGIC: &[u8; 8] = b"GLINTCKP";
const VERSION: u32 = 2;
const HEADER_LEN: usize = 8 + 5 * 4 + 8 + 8;

/// One tile's share of the render: everything needed never to trace it again.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishedTile {
    /// The tile's pixels `(x0, y0, x1, y1)`.
    pub bounds: (u32, u32, u32, u32),
    /// Its samples' weighted sums over the tile and the filter's halo around it.
    pub film: FilmTile,
    /// Camera samples each pixel took, row by row.
    pub samples: Vec<u32>,
    pub rays: u64,
    pub non_finite: NonFiniteSamples,
}

/// Finished tiles by index, filled from worker threads as a render goes.
#[derive(Debug, Default)]
pub struct TileStore {
    tiles: Mutex<BTreeMap<u32, FinishedTile>>,
}

/// Why a checkpoint cannot be resumed from.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CheckpointError {
    #[error("not a glint checkpoint")]
    NotACheckpoint,
    #[error("written by checkpoint format {0}; this glint reads format {VERSION}")]
    Version(u32),
    #[error("made for another scene or other settings; render without --resume to start over")]
    OtherScene,
    #[error("its header is damaged; render without --resume to start over")]
    Damaged,
}

/// A checkpoint read back: its tiles, and how many of its bytes held whole records
/// (a crash mid-append leaves a torn record after them, to be cut off before appending).
#[derive(Debug)]
pub struct Restored {
    pub store: TileStore,
    pub valid_len: usize,
}

/// The journal's header, for a render of `scene` whose description and settings hash
/// to `fingerprint`: the file starts with it, and tile records follow.
pub fn checkpoint_header(scene: &RenderScene, fingerprint: u64) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_LEN);
    out.extend_from_slice(MAGIC);
    let (width, height, aovs) = (scene.settings.width, scene.settings.height, u32::from(scene.settings.aovs));
    for word in [VERSION, width, height, tile_count(scene), aovs] {
        put_u32(&mut out, word);
    }
    put_u64(&mut out, fingerprint);
    let checksum = fnv1a(&out);
    put_u64(&mut out, checksum);
    out
}

impl TileStore {
    /// Tiles finished so far.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub(super) fn contains(&self, index: u32) -> bool {
        self.lock().contains_key(&index)
    }

    pub(super) fn insert(&self, index: u32, tile: FinishedTile) {
        self.lock().insert(index, tile);
    }

    /// Runs `f` over the finished tiles in index order.
    pub(super) fn with_tiles<R>(&self, f: impl FnOnce(&mut dyn Iterator<Item = &FinishedTile>) -> R) -> R {
        f(&mut self.lock().values())
    }

    /// Runs `f` over the finished tiles and their indices, in index order.
    pub(super) fn with_indexed_tiles<R>(
        &self,
        f: impl FnOnce(&mut dyn Iterator<Item = (u32, &FinishedTile)>) -> R,
    ) -> R {
        f(&mut self.lock().iter().map(|(&i, t)| (i, t)))
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, BTreeMap<u32, FinishedTile>> {
        // A worker that panicked mid-insert leaves the map whole: insert is one call.
        self.tiles.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Journal records of every finished tile not in `written`, which they join: what
    /// to append to the checkpoint since the last save.
    pub fn new_records(&self, written: &mut BTreeSet<u32>) -> Vec<u8> {
        // Copy out under the lock, encode outside it: workers keep inserting meanwhile.
        let fresh: Vec<(u32, FinishedTile)> = {
            let tiles = self.lock();
            tiles.iter().filter(|(i, _)| !written.contains(i)).map(|(&i, t)| (i, t.clone())).collect()
        };
        let mut out = Vec::with_capacity(fresh.iter().map(|(_, t)| tile_size_hint(t)).sum());
        for (index, tile) in fresh {
            put_record(&mut out, index, &tile);
            written.insert(index);
        }
        out
    }

    /// Indices of the finished tiles.
    pub fn indices(&self) -> BTreeSet<u32> {
        self.lock().keys().copied().collect()
    }

    /// The tiles a checkpoint holds, checked against `scene` and `fingerprint`: one
    /// made for anything else, or with a damaged header, is refused; records after a
    /// torn or damaged one are dropped (those tiles are traced again).
    pub fn from_checkpoint(bytes: &[u8], scene: &RenderScene, fingerprint: u64) -> Result<Restored, CheckpointError> {
        if bytes.len() < MAGIC.len() + 4 || &bytes[..MAGIC.len()] != MAGIC {
            return Err(CheckpointError::NotACheckpoint);
        }
        let version = u32::from_le_bytes(bytes[MAGIC.len()..MAGIC.len() + 4].try_into().expect("4 bytes"));
        if version != VERSION {
            return Err(CheckpointError::Version(version));
        }
        let header = bytes.get(..HEADER_LEN).ok_or(CheckpointError::Damaged)?;
        if fnv1a(&header[..HEADER_LEN - 8]) != u64::from_le_bytes(header[HEADER_LEN - 8..].try_into().expect("8")) {
            return Err(CheckpointError::Damaged);
        }
        if header != checkpoint_header(scene, fingerprint) {
            return Err(CheckpointError::OtherScene);
        }
        let mut map = BTreeMap::new();
        let mut valid_len = HEADER_LEN;
        while let Some((index, tile, len)) = take_record(&bytes[valid_len..], scene) {
            map.insert(index, tile);
            valid_len += len;
        }
        Ok(Restored { store: Self { tiles: Mutex::new(map) }, valid_len })
    }
}

/// The largest checkpoint a render of `scene` can make (every tile finished, AOVs
/// kept, a tally for every sample): a bound to check a file's size against before
/// reading it.
pub fn max_checkpoint_len(scene: &RenderScene) -> u64 {
    // A tally names a surface (instance and material) or none.
    let sources = (scene.instances.len() as u64 + 1) * (scene.materials.len() as u64 + 1);
    let per_tile = |index| {
        let ([x0, y0, x1, y1], [fx0, fy0, fx1, fy1]) = tile_rects(scene, index);
        let (film, pixels) = (((fx1 - fx0) * (fy1 - fy0)) as u64, ((x1 - x0) * (y1 - y0)) as u64);
        64 + film * 52 + pixels * 4 + sources * 32
    };
    64 + (0..tile_count(scene)).map(per_tile).sum::<u64>()
}

fn tile_size_hint(tile: &FinishedTile) -> usize {
    let (sums, _, aovs) = tile.film.raw();
    sums.len() * 16 + aovs.len() * 36 + tile.samples.len() * 4 + 64
}

/// One tile's record: its length, the tile, and the checksum of both.
fn put_record(out: &mut Vec<u8>, index: u32, tile: &FinishedTile) {
    let start = out.len();
    put_u32(out, 0); // the length, filled in below
    put_tile(out, index, tile);
    let len = (out.len() - start - 4) as u32;
    out[start..start + 4].copy_from_slice(&len.to_le_bytes());
    let checksum = fnv1a(&out[start..]);
    put_u64(out, checksum);
}

/// The record at the start of `bytes` and the bytes it took, or `None` when it is
/// torn, damaged or does not fit `scene`.
fn take_record(bytes: &[u8], scene: &RenderScene) -> Option<(u32, FinishedTile, usize)> {
    let len = u32::from_le_bytes(bytes.get(..4)?.try_into().ok()?) as usize;
    let end = 4usize.checked_add(len)?;
    let checksum = u64::from_le_bytes(bytes.get(end..end.checked_add(8)?)?.try_into().ok()?);
    if fnv1a(&bytes[..end]) != checksum {
        return None;
    }
    let mut input = Input { bytes: &bytes[4..end] };
    let (index, tile) = take_tile(&mut input, scene)?;
    input.bytes.is_empty().then_some((index, tile, end + 8))
}

fn put_tile(out: &mut Vec<u8>, index: u32, tile: &FinishedTile) {
    let (sums, weights, aov_sums) = tile.film.raw();
    put_u32(out, index);
    sums.iter().for_each(|v| put_vec3(out, *v));
    weights.iter().for_each(|&w| put_u32(out, w.to_bits()));
    aov_sums.iter().flatten().for_each(|v| put_vec3(out, *v));
    tile.samples.iter().for_each(|&n| put_u32(out, n));
    put_u64(out, tile.rays);
    let sources = tile.non_finite.by_source();
    put_u32(out, sources.len() as u32);
    for (source, tally) in sources {
        let id = source.unwrap_or(SurfaceId { instance: u32::MAX, material: u32::MAX });
        for word in [u32::from(source.is_some()), id.instance, id.material] {
            put_u32(out, word);
        }
        put_u64(out, tally.count);
        put_u32(out, tally.example_pixel.0);
        put_u32(out, tally.example_pixel.1);
    }
}

/// One tile, its size taken from the scene (never from the file), so a tile that
/// does not fit is refused rather than a panic or a huge allocation.
fn take_tile(input: &mut Input, scene: &RenderScene) -> Option<(u32, FinishedTile)> {
    let index = input.u32().filter(|&i| i < tile_count(scene))?;
    let ([x0, y0, x1, y1], [fx0, fy0, fx1, fy1]) = tile_rects(scene, index);
    let n = ((fx1 - fx0) * (fy1 - fy0)) as usize;
    let aov_count = if scene.settings.aovs { n } else { 0 };
    let pixels = ((x1 - x0) * (y1 - y0)) as usize;
    if input.bytes.len() < n * 16 + aov_count * 36 + pixels * 4 {
        return None;
    }
    let sums = (0..n).map(|_| input.vec3()).collect::<Option<_>>()?;
    let weights = (0..n).map(|_| input.f32()).collect::<Option<_>>()?;
    let aov_sums =
        (0..aov_count).map(|_| Some([input.vec3()?, input.vec3()?, input.vec3()?])).collect::<Option<_>>()?;
    let samples = (0..pixels).map(|_| input.u32()).collect::<Option<_>>()?;
    let rays = input.u64()?;
    let mut non_finite = NonFiniteSamples::default();
    for _ in 0..input.u32()? {
        let (known, instance, material) = (input.u32()?, input.u32()?, input.u32()?);
        let source = (known == 1).then_some(SurfaceId { instance, material });
        let count = input.u64()?;
        let example_pixel = (input.u32()?, input.u32()?);
        non_finite.add(source, SourceTally { count, example_pixel });
    }
    let film = FilmTile::from_raw((fx0, fy0, fx1 - fx0, fy1 - fy0), sums, weights, aov_sums)?;
    Some((index, FinishedTile { bounds: (x0, y0, x1, y1), film, samples, rays, non_finite }))
}

fn put_u32(out: &mut Vec<u8>, word: u32) {
    out.extend_from_slice(&word.to_le_bytes());
}

fn put_u64(out: &mut Vec<u8>, word: u64) {
    out.extend_from_slice(&word.to_le_bytes());
}

fn put_vec3(out: &mut Vec<u8>, v: Vec3) {
    v.to_array().iter().for_each(|c| put_u32(out, c.to_bits()));
}

/// Reads little-endian words off the front of a byte slice.
struct Input<'a> {
    bytes: &'a [u8],
}

impl Input<'_> {
    fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let (head, rest) = self.bytes.split_first_chunk::<N>()?;
        self.bytes = rest;
        Some(*head)
    }

    fn u32(&mut self) -> Option<u32> {
        self.take().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Option<u64> {
        self.take().map(u64::from_le_bytes)
    }

    fn f32(&mut self) -> Option<f32> {
        self.u32().map(f32::from_bits)
    }

    fn vec3(&mut self) -> Option<Vec3> {
        Some(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }
}

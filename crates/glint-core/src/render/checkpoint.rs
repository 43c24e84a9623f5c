//! A render's resumable state: its finished tiles, kept as they finish and saved bit
//! for bit, so a render killed midway resumes and still gives the uninterrupted image.
//!
//! A checkpoint is little-endian binary: a header (magic, version, scene fingerprint,
//! image and tile counts), each finished tile (index, film sums, sample counts, rays,
//! non-finite tallies) and an FNV-1a checksum of all that precedes it. The core only
//! makes and reads the bytes; the caller writes them atomically.

use std::collections::BTreeMap;
use std::sync::Mutex;

use glam::Vec3;

use super::{NonFiniteSamples, SourceTally, tile_count, tile_rects};
use crate::film::FilmTile;
use crate::fnv::fnv1a;
use crate::integrator::SurfaceId;
use crate::scene::RenderScene;

const MAGIC: &[u8; 8] = b"GLINTCKP";
const VERSION: u32 = 1;

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
    #[error("damaged ({0}); render without --resume to start over")]
    Damaged(&'static str),
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

    fn lock(&self) -> std::sync::MutexGuard<'_, BTreeMap<u32, FinishedTile>> {
        // A worker that panicked mid-insert leaves the map whole: insert is one call.
        self.tiles.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// The finished tiles as checkpoint bytes, for a render of `scene` whose
    /// description and settings hash to `fingerprint`.
    pub fn to_checkpoint(&self, scene: &RenderScene, fingerprint: u64) -> Vec<u8> {
        let tiles = self.lock();
        let mut out = Vec::with_capacity(64 + tiles.values().map(tile_size_hint).sum::<usize>());
        out.extend_from_slice(MAGIC);
        for word in [VERSION, scene.settings.width, scene.settings.height, tile_count(scene), tiles.len() as u32] {
            put_u32(&mut out, word);
        }
        put_u64(&mut out, fingerprint);
        for (&index, tile) in tiles.iter() {
            put_tile(&mut out, index, tile);
        }
        let checksum = fnv1a(&out);
        put_u64(&mut out, checksum);
        out
    }

    /// The tiles a checkpoint holds, checked against `scene` and `fingerprint`: a
    /// damaged file, or one made for anything else, is refused rather than merged.
    pub fn from_checkpoint(bytes: &[u8], scene: &RenderScene, fingerprint: u64) -> Result<Self, CheckpointError> {
        if bytes.len() < MAGIC.len() + 4 || &bytes[..MAGIC.len()] != MAGIC {
            return Err(CheckpointError::NotACheckpoint);
        }
        let mut input = Input { bytes: &bytes[MAGIC.len()..] };
        let version = input.u32()?;
        if version != VERSION {
            return Err(CheckpointError::Version(version));
        }
        let (body, checksum) = bytes.split_at(bytes.len().checked_sub(8).ok_or(CheckpointError::Damaged("cut short"))?);
        if fnv1a(body) != u64::from_le_bytes(checksum.try_into().expect("8 bytes")) {
            return Err(CheckpointError::Damaged("its checksum does not match: cut short or overwritten"));
        }
        let mut input = Input { bytes: &body[MAGIC.len() + 4..] };
        let (width, height, tiles, finished) = (input.u32()?, input.u32()?, input.u32()?, input.u32()?);
        let same_image = (width, height, tiles) == (scene.settings.width, scene.settings.height, tile_count(scene));
        if input.u64()? != fingerprint || !same_image {
            return Err(CheckpointError::OtherScene);
        }
        let mut map = BTreeMap::new();
        for _ in 0..finished {
            let (index, tile) = take_tile(&mut input, scene)?;
            map.insert(index, tile);
        }
        if !input.bytes.is_empty() {
            return Err(CheckpointError::Damaged("bytes after the last tile"));
        }
        Ok(Self { tiles: Mutex::new(map) })
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

fn put_tile(out: &mut Vec<u8>, index: u32, tile: &FinishedTile) {
    let (sums, weights, aov_sums) = tile.film.raw();
    put_u32(out, index);
    out.push(u8::from(!aov_sums.is_empty()));
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
/// does not fit is an error and not a panic or a huge allocation.
fn take_tile(input: &mut Input, scene: &RenderScene) -> Result<(u32, FinishedTile), CheckpointError> {
    let index = input.u32()?;
    if index >= tile_count(scene) {
        return Err(CheckpointError::Damaged("a tile index beyond the image"));
    }
    let ([x0, y0, x1, y1], [fx0, fy0, fx1, fy1]) = tile_rects(scene, index);
    let has_aovs = match input.u8()? {
        0 => false,
        1 => true,
        _ => return Err(CheckpointError::Damaged("a tile flag that is neither 0 nor 1")),
    };
    if has_aovs != scene.settings.aovs {
        return Err(CheckpointError::OtherScene);
    }
    let n = ((fx1 - fx0) * (fy1 - fy0)) as usize;
    let aov_count = if has_aovs { n } else { 0 };
    let needed = n * 16 + aov_count * 36 + ((x1 - x0) * (y1 - y0)) as usize * 4;
    if input.bytes.len() < needed {
        return Err(CheckpointError::Damaged("cut short"));
    }
    let sums = (0..n).map(|_| input.vec3()).collect::<Result<_, _>>()?;
    let weights = (0..n).map(|_| input.f32()).collect::<Result<_, _>>()?;
    let aov_sums =
        (0..aov_count).map(|_| Ok([input.vec3()?, input.vec3()?, input.vec3()?])).collect::<Result<_, _>>()?;
    let samples = (0..(x1 - x0) * (y1 - y0)).map(|_| input.u32()).collect::<Result<_, _>>()?;
    let rays = input.u64()?;
    let mut non_finite = NonFiniteSamples::default();
    for _ in 0..input.u32()? {
        let (known, instance, material) = (input.u32()?, input.u32()?, input.u32()?);
        let source = (known == 1).then_some(SurfaceId { instance, material });
        let count = input.u64()?;
        let example_pixel = (input.u32()?, input.u32()?);
        non_finite.add(source, SourceTally { count, example_pixel });
    }
    let film = FilmTile::from_raw((fx0, fy0, fx1 - fx0, fy1 - fy0), sums, weights, aov_sums)
        .ok_or(CheckpointError::Damaged("a tile's film of the wrong size"))?;
    Ok((index, FinishedTile { bounds: (x0, y0, x1, y1), film, samples, rays, non_finite }))
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
    fn take<const N: usize>(&mut self) -> Result<[u8; N], CheckpointError> {
        let (head, rest) = self.bytes.split_first_chunk::<N>().ok_or(CheckpointError::Damaged("cut short"))?;
        self.bytes = rest;
        Ok(*head)
    }

    fn u8(&mut self) -> Result<u8, CheckpointError> {
        Ok(self.take::<1>()?[0])
    }

    fn u32(&mut self) -> Result<u32, CheckpointError> {
        self.take().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64, CheckpointError> {
        self.take().map(u64::from_le_bytes)
    }

    fn f32(&mut self) -> Result<f32, CheckpointError> {
        self.u32().map(f32::from_bits)
    }

    fn vec3(&mut self) -> Result<Vec3, CheckpointError> {
        Ok(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }
}

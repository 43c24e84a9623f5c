//! Rendering a compiled scene on all cores, tile by tile.
//!
//! Every sample is a pure function of the scene, its pixel, its index and the seed;
//! tiles splat into their own buffers (tile plus filter halo) that are merged in a
//! fixed order, so the image is bit-identical for any thread count — and for a render
//! resumed from a checkpoint of its finished tiles ([`TileStore`]).

mod checkpoint;
pub mod inspect;
mod lane_incidence;
mod non_finite;
mod parts;
mod streaming;
mod waves;
mod whitted_waves;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::accel::PACKET;
use crate::desc::AdaptiveDesc;
use crate::desc::IntegratorDesc;
use crate::film::{Aov, AovImages, FilmTile, Image, linear_to_srgb};
use crate::integrator::{Counters, SurfaceId, TraceContext, path, whitted};
use crate::math::Ray;
use crate::sampling::{PathSampler, PixelSampler, PixelStream, Rng, SamplePattern, hash};
use crate::scene::RenderScene;
pub use checkpoint::{CheckpointError, FinishedTile, Restored, TileStore, checkpoint_header, max_checkpoint_len};
pub use non_finite::{NonFiniteSamples, SourceTally};
pub use parts::{Part, PartError, PartMerger, PartialFilm, merge_parts, render_part};

/// Side of the square tiles the image is cut into.
pub const TILE_SIZE: u32 = 16;

/// What a finished render reports besides the image.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Rays traced: camera, reflected, refracted and shadow rays.
    pub rays: u64,
    /// Camera samples taken in each pixel, row by row: an AOV that shows where adaptive
    /// sampling spent its effort.
    pub samples_per_pixel: Vec<u32>,
    /// Albedo, normal and depth images, when the scene's settings ask for them.
    pub aovs: Option<AovImages>,
    /// Samples left out of the film because they came back NaN or infinite.
    pub non_finite: NonFiniteSamples,
}

/// Why a render returned no image.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    #[error("render cancelled")]
    Cancelled,
}

/// Renders on the current rayon pool. `progress(done, total)` is called after each
/// tile (from worker threads); setting `cancel` stops the render between tiles.
///
/// Tiles are merged into the image band by band as they finish and then dropped, so
/// the render holds the image and a few rows of tiles, not every tile's film.
pub fn render(
    scene: &RenderScene,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(Image, RenderStats), RenderError> {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let mut image = Image::new(width, height);
    let mut counts = vec![0; (width * height) as usize];
    let merge = streaming::StreamingMerge::new(scene, &mut image.pixels, &mut counts);
    let all: Vec<u32> = (0..tile_count(scene)).collect();
    trace_tiles(scene, &all, |_| false, |index, tile| merge.add(index, tile), progress, cancel);
    if cancel.load(Ordering::Relaxed) {
        return Err(RenderError::Cancelled);
    }
    let merged = merge.finish();
    let stats =
        RenderStats { rays: merged.rays, samples_per_pixel: counts, aovs: merged.aovs, non_finite: merged.non_finite };
    Ok((image, stats))
}

/// [`render`] that keeps each finished tile in `store` and traces only the tiles it
/// lacks: a store restored from a checkpoint resumes an interrupted render, and the
/// image is bit-identical to an uninterrupted one. A cancelled render leaves its
/// finished tiles in the store.
pub fn render_resumable(
    scene: &RenderScene,
    store: &TileStore,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(Image, RenderStats), RenderError> {
    let all: Vec<u32> = (0..tile_count(scene)).collect();
    render_tiles(scene, store, &all, progress, cancel)?;
    Ok(store.with_tiles(|tiles| merge_tiles(scene, tiles)))
}

/// Traces the tiles of `tiles` that `store` lacks into it, on the current rayon pool;
/// `progress(done, total)` counts the tiles of `tiles`.
fn render_tiles(
    scene: &RenderScene,
    store: &TileStore,
    tiles: &[u32],
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(), RenderError> {
    trace_tiles(scene, tiles, |index| store.contains(index), |index, tile| store.insert(index, tile), progress, cancel);
    if cancel.load(Ordering::Relaxed) || tiles.iter().any(|&t| !store.contains(t)) {
        return Err(RenderError::Cancelled);
    }
    Ok(())
}

/// Traces the tiles of `tiles` that `done` does not already hold and hands each to
/// `finish` as it completes, on the current rayon pool, until `cancel` is set; the one
/// tile loop behind both the streaming and the resumable render. `progress(done,
/// total)` counts the tiles of `tiles`, those held beforehand included.
fn trace_tiles(
    scene: &RenderScene,
    tiles: &[u32],
    done: impl Fn(u32) -> bool + Sync,
    finish: impl Fn(u32, FinishedTile) + Sync,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) {
    let finished = AtomicUsize::new(tiles.iter().filter(|&&t| done(t)).count());
    tiles.par_iter().for_each(|&index| {
        if cancel.load(Ordering::Relaxed) || done(index) {
            return;
        }
        finish(index, render_tile(scene, index));
        progress(finished.fetch_add(1, Ordering::Relaxed) + 1, tiles.len());
    });
}

/// The image and its statistics from every tile's share, merged in tile order. Bands
/// of rows merge and resolve in parallel (serial, the merge was a sixth of a Whitted
/// render on two threads): each pixel still adds the tiles' sums in tile order, so the
/// image is bit for bit the serial merge's.
fn merge_tiles<'a>(scene: &RenderScene, tiles: impl Iterator<Item = &'a FinishedTile>) -> (Image, RenderStats) {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let tiles: Vec<&FinishedTile> = tiles.collect();
    let mut stats = RenderStats::default();
    for tile in &tiles {
        stats.rays += tile.rays;
        stats.non_finite.merge(&tile.non_finite);
    }
    let mut image = Image::new(width, height);
    let mut counts = vec![0; (width * height) as usize];
    let band_rows = TILE_SIZE as usize;
    let band_len = (width as usize * band_rows).max(1);
    let band_aovs: Vec<Option<AovImages>> = image
        .pixels
        .par_chunks_mut(band_len)
        .zip(counts.par_chunks_mut(band_len))
        .enumerate()
        // One film per worker, reset for each band it merges.
        .map_init(
            || FilmTile::new(0, 0, 0, 0),
            |film, (band, (pixels, counts))| {
                let y0 = (band * band_rows) as u32;
                merge_band(scene, film, y0, tiles.iter().copied(), pixels, counts)
            },
        )
        .collect();
    stats.aovs = AovImages::stacked(band_aovs);
    stats.samples_per_pixel = counts;
    (image, stats)
}

/// Merges into `pixels` and `counts`, the rows from `y0` of the image's pixels and
/// samples per pixel, the tiles of `tiles` (in tile order) whose films reach them, on
/// `film` (reset here, so a worker can reuse one); returns the band's AOVs.
fn merge_band<'a>(
    scene: &RenderScene,
    film: &mut FilmTile,
    y0: u32,
    tiles: impl Iterator<Item = &'a FinishedTile>,
    pixels: &mut [Vec3],
    counts: &mut [u32],
) -> Option<AovImages> {
    let width = scene.settings.width;
    let rows = (pixels.len() / width as usize) as u32;
    film.reset((0, y0, width, rows), scene.settings.aovs);
    let overlaps = |t: &&FinishedTile| t.film.y0 < y0 + rows && t.film.y0 + t.film.height > y0;
    for tile in tiles.filter(overlaps) {
        film.merge(&tile.film);
        copy_sample_counts(tile, (y0, y0 + rows), width, counts);
    }
    film.resolve_into(pixels);
    film.resolve_aovs()
}

/// The sample counts of `tile`'s rows within `rows` into `counts`, the counts of those
/// rows of an image `width` pixels wide.
fn copy_sample_counts(tile: &FinishedTile, rows: (u32, u32), width: u32, counts: &mut [u32]) {
    let (x0, y0, x1, _) = tile.bounds;
    let tile_width = (x1 - x0) as usize;
    for (row, row_counts) in tile.samples.chunks(tile_width.max(1)).enumerate() {
        let y = y0 + row as u32;
        if (rows.0..rows.1).contains(&y) {
            let start = ((y - rows.0) * width + x0) as usize;
            counts[start..start + row_counts.len()].copy_from_slice(row_counts);
        }
    }
}

/// How many tiles the image is cut into.
pub fn tile_count(scene: &RenderScene) -> u32 {
    scene.settings.width.div_ceil(TILE_SIZE) * scene.settings.height.div_ceil(TILE_SIZE)
}

/// Tile `index`'s pixels `(x0, y0, x1, y1)` (row by row from the top left), and the
/// larger rectangle its samples splat into: the filter reaches beyond the tile by up
/// to ⌊r + ½⌋ pixels on either side, as a sample lies in [0, 1] from its pixel's corner
/// (the corners pattern puts some on the far edge, shared with the next pixel).
fn tile_rects(scene: &RenderScene, index: u32) -> ([u32; 4], [u32; 4]) {
    let s = &scene.settings;
    let tiles_x = s.width.div_ceil(TILE_SIZE);
    let (x0, y0) = ((index % tiles_x) * TILE_SIZE, (index / tiles_x) * TILE_SIZE);
    let (x1, y1) = ((x0 + TILE_SIZE).min(s.width), (y0 + TILE_SIZE).min(s.height));
    let halo = (s.filter.radius + 0.5).floor() as u32;
    let film = [x0.saturating_sub(halo), y0.saturating_sub(halo), (x1 + halo).min(s.width), (y1 + halo).min(s.height)];
    ([x0, y0, x1, y1], film)
}

fn new_film(scene: &RenderScene, x0: u32, y0: u32, width: u32, height: u32) -> FilmTile {
    let film = FilmTile::new(x0, y0, width, height);
    if scene.settings.aovs { film.with_aovs() } else { film }
}

/// One traced camera sample: where it lies on the film, what it brought back, what
/// its first hit looks like, and which surface to blame if its value is not finite.
#[derive(Clone, Copy)]
struct Traced {
    fx: f32,
    fy: f32,
    value: Vec3,
    aov: Aov,
    culprit: Option<SurfaceId>,
}

impl Traced {
    /// A sample at film position (`fx`, `fy`) that has gathered nothing yet.
    #[inline(always)]
    fn at(fx: f32, fy: f32) -> Traced {
        Traced { fx, fy, value: Vec3::ZERO, aov: Aov::default(), culprit: None }
    }
}

/// A tile's film, as its samples are splatted: non-finite ones are counted instead.
struct TileFilm<'a> {
    scene: &'a RenderScene,
    film: FilmTile,
    non_finite: NonFiniteSamples,
}

impl TileFilm<'_> {
    #[inline(always)]
    fn splat(&mut self, traced: &Traced) {
        if traced.value.is_finite() {
            let filter = &self.scene.settings.filter;
            self.film.splat_with(filter, traced.fx, traced.fy, traced.value, Some(&traced.aov));
        } else {
            self.count_if_non_finite(traced);
        }
    }

    /// Records a sample whose value is not finite (and nothing else).
    fn count_if_non_finite(&mut self, traced: &Traced) {
        if !traced.value.is_finite() {
            self.non_finite.record(traced.culprit, (traced.fx as u32, traced.fy as u32));
        }
    }
}

fn render_tile(scene: &RenderScene, index: u32) -> FinishedTile {
    let s = &scene.settings;
    let ([x0, y0, x1, y1], [fx0, fy0, fx1, fy1]) = tile_rects(scene, index);
    let mut film =
        TileFilm { scene, film: new_film(scene, fx0, fy0, fx1 - fx0, fy1 - fy0), non_finite: Default::default() };
    let mut counters = Counters::default();
    let samples = match s.adaptive {
        None => {
            match s.integrator {
                IntegratorDesc::Whitted => uniform_tile(scene, (x0, y0, x1, y1), &mut film, &mut counters),
                IntegratorDesc::Path(_) => path_tile(scene, (x0, y0, x1, y1), &mut film, &mut counters),
            }
            vec![s.spp; ((x1 - x0) * (y1 - y0)) as usize]
        }
        Some(adaptive) => adaptive_tile(scene, &adaptive, (x0, y0, x1, y1), &mut film, &mut counters),
    };
    FinishedTile {
        bounds: (x0, y0, x1, y1),
        film: film.film,
        samples,
        rays: counters.rays,
        non_finite: film.non_finite,
    }
}

/// Adaptive sampling of one tile, in two passes. First every pixel takes the minimum
/// (and so does a one-pixel ring around the tile, traced only to know the neighbours:
/// those samples belong to other tiles and are not splatted here). Then a pixel goes on,
/// doubling its samples up to the maximum, while the standard error of its samples is
/// above the threshold; a pixel whose mean differs from a neighbour's by more than twice
/// the threshold first takes four times the minimum — an edge can fall between the first
/// few samples of a pixel, but rarely between those of two neighbours.
///
/// Positions are Sobol points: every power-of-two prefix is stratified, so a pixel can
/// stop after any doubling and still be evenly covered.
fn adaptive_tile(
    scene: &RenderScene,
    adaptive: &AdaptiveDesc,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
    film: &mut TileFilm,
    counters: &mut Counters,
) -> Vec<u32> {
    let s = &scene.settings;
    let sampler = PixelSampler { pattern: SamplePattern::Sobol, ..s.sampler };
    let (rx0, ry0) = (x0.saturating_sub(1), y0.saturating_sub(1));
    let (rx1, ry1) = ((x1 + 1).min(s.width), (y1 + 1).min(s.height));
    let ring_width = (rx1 - rx0) as usize;
    let at = |px: u32, py: u32| (py - ry0) as usize * ring_width + (px - rx0) as usize;
    let mut spreads = vec![Spread::default(); ring_width * (ry1 - ry0) as usize];
    let min = adaptive.min_samples;
    // A pixel that starts from a pilot at its centre ([`RenderScene::adaptive_pilot`])
    // keeps it only where it settles there; one that goes on drops it and takes its own
    // stratified samples, at least four.
    let pilot = scene.adaptive_pilot();
    let first_sampler =
        if pilot { PixelSampler { pattern: SamplePattern::Grid, per_axis: 1, ..sampler } } else { sampler };
    let mut pilots = Vec::new();
    let first: Vec<(u32, u32, u32)> =
        (ry0..ry1).flat_map(|py| (rx0..rx1).flat_map(move |px| (0..min).map(move |index| (px, py, index)))).collect();
    trace_samples(scene, &first_sampler, &first, counters, &mut |(px, py, _), traced| {
        spreads[at(px, py)].add(display_luminance(traced.value));
        if (x0..x1).contains(&px) && (y0..y1).contains(&py) {
            if pilot {
                pilots.push(*traced);
            } else {
                film.splat(traced);
            }
        }
    });
    // Each of the tile's pixels: its samples' spread, the count it goes on to, and
    // whether one sample that its neighbours agree with settles it.
    let mut pixels: Vec<Refined> = (y0..y1)
        .flat_map(|py| (x0..x1).map(move |px| (px, py)))
        .map(|(px, py)| {
            let spread = spreads[at(px, py)].clone();
            let neighbours = [(px.wrapping_sub(1), py), (px + 1, py), (px, py.wrapping_sub(1)), (px, py + 1)];
            let contrast = neighbours
                .iter()
                .filter(|&&(x, y)| (rx0..rx1).contains(&x) && (ry0..ry1).contains(&y))
                .map(|&(x, y)| (spreads[at(x, y)].mean - spread.mean).abs() as f32)
                .fold(0.0, f32::max);
            let forced = if contrast > 2.0 * adaptive.threshold { 4 * adaptive.min_samples } else { 0 };
            // One sample tells nothing of a pixel's spread: where its neighbours agree
            // with it, the pixel is taken to be flat and stops (POV-Ray's anti-aliasing
            // supersamples only pixels that differ from their neighbours, too).
            let settled = spread.count == 1 && (contrast <= adaptive.threshold || adaptive.max_samples == 1);
            Refined { pixel: (px, py), spread, target: forced.min(adaptive.max_samples), settled, done: false }
        })
        .collect();
    if pilot {
        keep_or_drop_pilots(&mut pixels, &pilots, film, adaptive.max_samples);
    }
    // In rounds, so each round's samples trace together: every pixel not done takes
    // its samples up to its target, then stops or doubles the target.
    let mut requests = Vec::new();
    loop {
        requests.clear();
        for p in pixels.iter().filter(|p| !p.done) {
            requests.extend((p.spread.count..p.target).map(|index| (p.pixel.0, p.pixel.1, index)));
        }
        let tile_width = (x1 - x0) as usize;
        let index_of = |(px, py): (u32, u32)| (py - y0) as usize * tile_width + (px - x0) as usize;
        trace_samples(scene, &sampler, &requests, counters, &mut |(px, py, _), traced| {
            film.splat(traced);
            pixels[index_of((px, py))].spread.add(display_luminance(traced.value));
        });
        let mut any_left = false;
        for p in pixels.iter_mut().filter(|p| !p.done) {
            let (count, flat) = (p.spread.count, p.settled && p.spread.count == 1);
            p.done = count >= adaptive.max_samples || flat || p.spread.standard_error() <= adaptive.threshold;
            p.target = (count * 2).min(adaptive.max_samples);
            any_left |= !p.done;
        }
        if !any_left {
            return pixels.iter().map(|p| p.spread.count).collect();
        }
    }
}

/// Splats the pilots of the pixels that settle on them (`pilots` in the order of
/// `pixels`); the others drop theirs and go on to at least four samples of their own.
fn keep_or_drop_pilots(pixels: &mut [Refined], pilots: &[Traced], film: &mut TileFilm, max_samples: u32) {
    for (p, traced) in pixels.iter_mut().zip(pilots) {
        if p.settled {
            film.splat(traced);
        } else {
            // Off the film, but a NaN it brought is still counted, as every backend
            // counts every sample it traced.
            film.count_if_non_finite(traced);
            p.spread = Spread::default();
            p.target = p.target.max(4).min(max_samples);
        }
    }
}

/// A pixel of an adaptive tile as it is refined.
struct Refined {
    pixel: (u32, u32),
    spread: Spread,
    /// The count its next round takes it to.
    target: u32,
    /// Whether its single sample agrees with its neighbours, which settles it.
    settled: bool,
    done: bool,
}

/// What takes each traced sample, with the request `(px, py, index)` it answers.
type SampleDone<'a> = dyn FnMut((u32, u32, u32), &Traced) + 'a;

/// Traces the samples `(px, py, index)` of `requests` at `sampler`'s positions and hands
/// each to `done` in order: in waves where the scene is a handful of analytic objects
/// shaded by the lighting equation, else one by one.
fn trace_samples(
    scene: &RenderScene,
    sampler: &PixelSampler,
    requests: &[(u32, u32, u32)],
    counters: &mut Counters,
    done: &mut SampleDone,
) {
    if let (Some(few), IntegratorDesc::Whitted) = (&scene.few_objects, scene.settings.integrator) {
        return crate::accel::lanes::on_avx2_or!(
            |_avx| trace_samples_in_waves_avx2(scene, few, sampler, requests, counters, done),
            whitted_waves::trace_samples_in_waves(scene, few, sampler, requests, counters, done)
        );
    }
    for &(px, py, index) in requests {
        done((px, py, index), &trace_sample(scene, sampler, px, py, index, counters));
    }
}

/// [`whitted_waves::trace_samples_in_waves`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn trace_samples_in_waves_avx2(
    scene: &RenderScene,
    few: &crate::scene::FewObjects,
    sampler: &PixelSampler,
    requests: &[(u32, u32, u32)],
    counters: &mut Counters,
    done: &mut SampleDone,
) {
    whitted_waves::trace_samples_in_waves(scene, few, sampler, requests, counters, done)
}

/// Every sample of every pixel of the tile `(x0, y0, x1, y1)`, splatted into `film` in
/// pixel order. Camera rays go out in packets: sample `index` of up to [`PACKET`]
/// neighbouring pixels of a row at once ([`RenderScene::intersect_packet`]); each is
/// then shaded on its own.
fn uniform_tile(scene: &RenderScene, tile: (u32, u32, u32, u32), film: &mut TileFilm, counters: &mut Counters) {
    if let Some(few) = &scene.few_objects {
        return crate::accel::lanes::on_avx2_or!(
            |_avx| whitted_tile_in_waves_avx2(scene, few, tile, film, counters),
            whitted_waves::whitted_tile_in_waves(scene, few, tile, film, counters)
        );
    }
    let (x0, y0, x1, y1) = tile;
    let s = &scene.settings;
    let count = s.spp as usize;
    // Per pixel of a run, per sample: film position, value and AOVs.
    let mut values: Vec<Traced> = (0..PACKET * count)
        .map(|_| Traced { fx: 0.0, fy: 0.0, value: Vec3::ZERO, aov: Aov::default(), culprit: None })
        .collect();
    for py in y0..y1 {
        for run_x in (x0..x1).step_by(PACKET) {
            let run = (x1 - run_x).min(PACKET as u32) as usize;
            for index in 0..count as u32 {
                let mut samples: [CameraSample; PACKET] =
                    std::array::from_fn(|k| camera_sample(scene, &s.sampler, run_x + k.min(run - 1) as u32, py, index));
                let rays: [Ray; PACKET] = std::array::from_fn(|k| samples[k].ray);
                let mut hits = [None; PACKET];
                scene.intersect_packet(&rays[..run], &mut hits[..run]);
                for (k, sample) in samples.iter_mut().enumerate().take(run) {
                    let value = whitted::shade(scene, &sample.ray, hits[k], 0, Vec3::ONE, &mut sample.ctx);
                    counters.rays += sample.ctx.counters.rays;
                    let aov = whitted_aov(scene, &sample.ray, hits[k].as_ref(), sample.ctx.footprint_scale);
                    let culprit = sample.ctx.counters.non_finite_at;
                    values[k * count + index as usize] = Traced { fx: sample.fx, fy: sample.fy, value, aov, culprit };
                }
            }
            for traced in &values[..run * count] {
                film.splat(traced);
            }
        }
    }
}

/// [`whitted_waves::whitted_tile_in_waves`] compiled for AVX2, so the lanes of its
/// waves fill AVX2 registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn whitted_tile_in_waves_avx2(
    scene: &RenderScene,
    few: &crate::scene::FewObjects,
    tile: (u32, u32, u32, u32),
    film: &mut TileFilm,
    counters: &mut Counters,
) {
    whitted_waves::whitted_tile_in_waves(scene, few, tile, film, counters)
}

/// Every sample of every pixel of the tile, path-traced one at a time, splatted in
/// pixel order.
/// The path-traced samples of a tile. The whole path loop is inlined into an AVX2 twin
/// where the CPU has it: VEX encoding and wider registers take ~5% off its
/// instructions, with bit-identical results (no fused multiply-adds are introduced).
fn path_tile(scene: &RenderScene, rect: (u32, u32, u32, u32), film: &mut TileFilm, counters: &mut Counters) {
    crate::accel::lanes::on_avx2_or!(
        |_avx| path_tile_avx2(scene, rect, film, counters),
        path_tile_on(scene, rect, film, counters)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn path_tile_avx2(scene: &RenderScene, rect: (u32, u32, u32, u32), film: &mut TileFilm, counters: &mut Counters) {
    path_tile_on(scene, rect, film, counters)
}

#[inline(always)]
fn path_tile_on(
    scene: &RenderScene,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
    film: &mut TileFilm,
    counters: &mut Counters,
) {
    let s = &scene.settings;
    if let Some(few) = &scene.few_objects {
        return waves::path_tile_in_waves(scene, few, (x0, y0, x1, y1), film, counters);
    }
    for py in y0..y1 {
        for px in x0..x1 {
            let stream = pixel_stream(scene, px, py);
            for index in 0..s.spp {
                film.splat(&path_sample(scene, &stream, (px, py), index, counters));
            }
        }
    }
}

/// Sample `index` of pixel (`px`, `py`) path-traced: every number it uses comes from
/// its [`PathSampler`] — pixel position, lens, time, then the path's own dimensions.
#[inline(always)]
fn path_sample(
    scene: &RenderScene,
    stream: &PixelStream,
    pixel: (u32, u32),
    index: u32,
    counters: &mut Counters,
) -> Traced {
    let (mut sampler, (fx, fy), ray) = path_camera_ray(scene, stream, pixel, index);
    let mut aov = Aov::default();
    let value = path::radiance(scene, &ray, &mut sampler, counters, scene.settings.aovs.then_some(&mut aov));
    Traced { fx, fy, value, aov, culprit: counters.non_finite_at.take() }
}

/// The random streams of pixel (`px`, `py`) path-traced.
#[inline(always)]
fn pixel_stream(scene: &RenderScene, px: u32, py: u32) -> PixelStream {
    let s = &scene.settings;
    let kind = match s.integrator {
        IntegratorDesc::Path(p) => p.sampler,
        IntegratorDesc::Whitted => crate::desc::SamplerKind::Sobol,
    };
    PixelStream::new(kind, px, py, s.seed)
}

/// The start of sample `index` of pixel (`px`, `py`) path-traced, whose streams are
/// `stream`: its sampler, which has drawn the film position (`fx`, `fy` in pixels),
/// the lens and the time of its camera ray.
#[inline(always)]
fn path_camera_ray(
    scene: &RenderScene,
    stream: &PixelStream,
    (px, py): (u32, u32),
    index: u32,
) -> (PathSampler, (f32, f32), Ray) {
    let mut sampler = stream.sample(index);
    let offset = sampler.next_2d();
    // The lens and the shutter take dimensions only where they matter (the same for
    // every sample of a scene, so each later decision keeps a fixed dimension).
    let lens = if scene.camera.aperture_radius > 0.0 { sampler.next_2d() } else { Vec2::splat(0.5) };
    let (fx, fy) = (px as f32 + offset.x, py as f32 + offset.y);
    let mut ray = film_ray(scene, fx, fy, lens);
    if !scene.motions.is_empty() {
        ray.time = sampler.next_1d();
    }
    (sampler, (fx, fy), ray)
}

/// The AOVs of a Whitted camera ray from its first hit: the diffuse colour (textured as
/// the shading is); nothing unless the render keeps AOVs. Inlined, so that its caller's
/// hit need not be kept in memory for it.
#[inline(always)]
fn whitted_aov(scene: &RenderScene, ray: &Ray, hit: Option<&crate::scene::Hit>, footprint_scale: f32) -> Aov {
    let Some(hit) = hit.filter(|_| scene.settings.aovs) else { return Aov::default() };
    let m = &scene.materials[hit.material as usize];
    let texel = (scene.settings.features.textures && m.texture != crate::material::NO_TEXTURE)
        .then(|| scene.texture_at_hit(m.texture, hit, m.texture_repeat, ray.time, footprint_scale));
    Aov { albedo: m.diffuse_with(texel) * hit.color, normal: hit.normal, depth: hit.t * ray.dir.length() }
}

/// A camera sample ready to trace: its film position (pixels), its ray, and the
/// context whose random stream it has started to use.
struct CameraSample {
    fx: f32,
    fy: f32,
    ray: Ray,
    ctx: TraceContext,
}

/// Sample `index` of pixel (`px`, `py`), up to its camera ray.
#[inline(always)]
fn camera_sample(scene: &RenderScene, sampler: &PixelSampler, px: u32, py: u32, index: u32) -> CameraSample {
    let offset = sampler.offset(px, py, index);
    let (fx, fy) = (px as f32 + offset.x, py as f32 + offset.y);
    let mut ctx = sample_context(scene, px, py, index);
    let lens = if scene.camera.aperture_radius > 0.0 {
        Vec2::new(ctx.rng.next_f32(), ctx.rng.next_f32())
    } else {
        ctx.rng.skip(2);
        Vec2::ZERO
    };
    let ray = camera_ray(scene, fx, fy, lens, &mut ctx);
    CameraSample { fx, fy, ray, ctx }
}

/// The context of sample `index` of pixel (`px`, `py`), its random stream keyed to the
/// sample (so a sample's numbers do not depend on which thread or tile traces it) and
/// not yet drawn from.
#[inline(always)]
fn sample_context(scene: &RenderScene, px: u32, py: u32, index: u32) -> TraceContext {
    TraceContext {
        counters: Counters::default(),
        rng: Rng::keyed([px, py, index, scene.settings.seed]),
        footprint_scale: scene.settings.sample_footprint(index),
    }
}

/// Traces sample `index` of pixel (`px`, `py`): returns its film position (pixels) and
/// its value.
fn trace_sample(
    scene: &RenderScene,
    sampler: &PixelSampler,
    px: u32,
    py: u32,
    index: u32,
    counters: &mut Counters,
) -> Traced {
    if let IntegratorDesc::Path(_) = scene.settings.integrator {
        return path_sample(scene, &pixel_stream(scene, px, py), (px, py), index, counters);
    }
    let mut sample = camera_sample(scene, sampler, px, py, index);
    let hit = scene.intersect(&sample.ray, f32::INFINITY);
    let value = whitted::shade(scene, &sample.ray, hit, 0, Vec3::ONE, &mut sample.ctx);
    counters.rays += sample.ctx.counters.rays;
    let aov = whitted_aov(scene, &sample.ray, hit.as_ref(), sample.ctx.footprint_scale);
    Traced { fx: sample.fx, fy: sample.fy, value, aov, culprit: sample.ctx.counters.non_finite_at }
}

/// Radiance through film position (`fx`, `fy`) in pixels (y down).
fn trace_film_point(scene: &RenderScene, fx: f32, fy: f32, lens: Vec2, ctx: &mut TraceContext) -> Vec3 {
    let ray = camera_ray(scene, fx, fy, lens, ctx);
    finite_or_black(whitted::radiance(scene, &ray, 0, Vec3::ONE, ctx))
}

/// The camera ray through film position (`fx`, `fy`) in pixels (y down), through lens
/// point `lens`, at a moment of the shutter interval drawn from `ctx` where anything
/// moves.
fn camera_ray(scene: &RenderScene, fx: f32, fy: f32, lens: Vec2, ctx: &mut TraceContext) -> Ray {
    let mut ray = film_ray(scene, fx, fy, lens);
    if !scene.motions.is_empty() {
        // A moment in the shutter interval, for motion blur.
        ray.time = ctx.rng.next_f32();
    }
    ray
}

/// The camera's ray through film position (`fx`, `fy`) in pixels (y down) and lens
/// point `lens`, at shutter open.
fn film_ray(scene: &RenderScene, fx: f32, fy: f32, lens: Vec2) -> Ray {
    let s = &scene.settings;
    // Screen space to the film plane: x, y in [−1, 1], +y up.
    scene.camera.ray(2.0 * fx / s.width as f32 - 1.0, 1.0 - 2.0 * fy / s.height as f32, lens)
}

/// A non-finite value (a NaN from a degenerate configuration) becomes black in a preview,
/// which keeps no statistics.
fn finite_or_black(value: Vec3) -> Vec3 {
    if value.is_finite() { value } else { Vec3::ZERO }
}

/// Luminance after sRGB encoding: differences the eye sees equally weigh equally, so
/// dark regions are not undersampled.
fn display_luminance(c: Vec3) -> f32 {
    linear_to_srgb(c.dot(Vec3::new(0.2126, 0.7152, 0.0722)))
}

/// Running mean and variance (Welford), for the adaptive stopping rule.
#[derive(Clone, Default)]
struct Spread {
    count: u32,
    mean: f64,
    m2: f64,
}

impl Spread {
    fn add(&mut self, x: f32) {
        self.count += 1;
        let delta = x as f64 - self.mean;
        self.mean += delta / self.count as f64;
        self.m2 += delta * (x as f64 - self.mean);
    }

    /// Standard error of the mean, `√(s²/n)`.
    fn standard_error(&self) -> f32 {
        if self.count < 2 {
            return f32::INFINITY;
        }
        (self.m2 / (self.count - 1) as f64 / self.count as f64).sqrt() as f32
    }
}

/// A quick look: one sample at the centre of each `block`×`block` group of pixels,
/// filling the group — far fewer samples than pixels. [`render_progressive`] refines it.
pub fn render_preview(scene: &RenderScene, block: u32) -> Image {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let block = block.max(1);
    let rows: Vec<Vec<Vec3>> = (0..height.div_ceil(block))
        .into_par_iter()
        .map(|by| {
            (0..width.div_ceil(block))
                .map(|bx| {
                    let cx = ((bx * block) as f32 + 0.5 * block as f32).min(width as f32 - 0.5);
                    let cy = ((by * block) as f32 + 0.5 * block as f32).min(height as f32 - 0.5);
                    if let IntegratorDesc::Path(_) = scene.settings.integrator {
                        let mut counters = Counters::default();
                        let pixel = (cx as u32, cy as u32);
                        let stream = pixel_stream(scene, pixel.0, pixel.1);
                        return finite_or_black(path_sample(scene, &stream, pixel, 0, &mut counters).value);
                    }
                    // One sample stands for a block of pixels: filtered textures average
                    // over all of it.
                    let footprint_scale = block as f32;
                    let mut ctx =
                        TraceContext { counters: Counters::default(), rng: Rng::new(hash(&[bx, by])), footprint_scale };
                    trace_film_point(scene, cx, cy, Vec2::splat(0.5), &mut ctx)
                })
                .collect()
        })
        .collect();
    let mut image = Image::new(width, height);
    for y in 0..height {
        for x in 0..width {
            image.pixels[(y * width + x) as usize] = rows[(y / block) as usize][(x / block) as usize];
        }
    }
    image
}

/// Subsampled previews at halving block sizes, then the full render: [`render_resumable`]
/// into `store` when there is one (to checkpoint or resume), [`render`] when not.
/// `on_pass` sees each image as it is ready (a viewer shows it, the CLI rewrites the
/// output file).
pub fn render_progressive(
    scene: &RenderScene,
    store: Option<&TileStore>,
    first_block: u32,
    on_pass: &mut dyn FnMut(&Image, u32),
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(Image, RenderStats), RenderError> {
    let mut block = first_block.next_power_of_two();
    while block > 1 {
        if cancel.load(Ordering::Relaxed) {
            return Err(RenderError::Cancelled);
        }
        on_pass(&render_preview(scene, block), block);
        block /= 2;
    }
    let result = match store {
        Some(store) => render_resumable(scene, store, progress, cancel)?,
        None => render(scene, progress, cancel)?,
    };
    on_pass(&result.0, 1);
    Ok(result)
}

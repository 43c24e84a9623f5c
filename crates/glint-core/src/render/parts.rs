//! A render cut into parts for many machines: part `i` of `n` traces every `n`-th tile.
//!
//! A pixel near a tile's edge also gets samples from the neighbouring tiles (the
//! filter's halo), and a single render adds those contributions in tile order. Floating
//! point addition is not associative, so a part's film does not sum them: it keeps each
//! tile's contribution to a pixel apart, by where the tile lies relative to the pixel's
//! own tile. Merging then adds them in that same order, and the merged image is the
//! single render's, bit for bit, for any cut.

use std::sync::atomic::AtomicBool;

use glam::Vec3;

use super::{FinishedTile, NonFiniteSamples, RenderError, RenderStats, TILE_SIZE, TileStore, render_tiles, tile_count};
use crate::film::{FilmTile, Image};
use crate::scene::RenderScene;

/// Part `index` of `count`: the tiles whose index is `index` modulo `count`, so every
/// part gets tiles from all over the image and about the same work.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Part {
    pub index: u32,
    pub count: u32,
}

impl Part {
    /// Part `index` of `count`, if `index < count` and there are at least `count` tiles
    /// (a part with no tile would be a machine with nothing to do).
    pub fn new(index: u32, count: u32, scene: &RenderScene) -> Result<Self, PartError> {
        if index >= count {
            return Err(PartError::NoSuchPart { index, count });
        }
        let tiles = tile_count(scene);
        if count > tiles {
            return Err(PartError::TooManyParts { count, tiles });
        }
        Ok(Self { index, count })
    }

    /// Whether tile `tile` is this part's to trace.
    pub fn owns(self, tile: u32) -> bool {
        tile % self.count == self.index
    }
}

/// Why a part cannot be made or parts cannot be merged.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PartError {
    #[error("there is no part {index} of {count}: parts are numbered 0 to {}", count.saturating_sub(1))]
    NoSuchPart { index: u32, count: u32 },
    #[error("{count} parts is more than the image's {tiles} tiles of {TILE_SIZE}x{TILE_SIZE} pixels")]
    TooManyParts { count: u32, tiles: u32 },
    #[error("the parts are of different renders ({0})")]
    Mismatch(&'static str),
    #[error("part {index} of {count} is missing")]
    Missing { index: u32, count: u32 },
    #[error("part {index} of {count} is given twice")]
    Twice { index: u32, count: u32 },
}

/// What one part traced: each of its tiles' contributions to the pixels they reach,
/// kept apart by the tile's offset from the pixel's own tile.
#[derive(Clone, Debug, PartialEq)]
pub struct PartialFilm {
    pub width: u32,
    pub height: u32,
    pub part: Part,
    /// How many tiles away a tile's samples can reach: its filter halo in tiles.
    pub reach: u32,
    /// One layer per offset `(dx, dy)` in `−reach..=reach`, row-major by `dy` then `dx`
    /// (so in tile order); per pixel, row by row: the weighted colour sum and the weight.
    pub layers: Vec<Vec<[f32; 4]>>,
    /// Camera samples per pixel, where this part traced the pixel's tile (0 elsewhere).
    pub samples: Vec<u32>,
    pub rays: u64,
    pub non_finite: NonFiniteSamples,
}

impl PartialFilm {
    /// A film with no contributions yet.
    pub fn empty(width: u32, height: u32, part: Part, reach: u32) -> Self {
        let pixels = width as usize * height as usize;
        let offsets = (2 * reach as usize + 1).pow(2);
        Self {
            width,
            height,
            part,
            reach,
            layers: vec![vec![[0.0; 4]; pixels]; offsets],
            samples: vec![0; pixels],
            rays: 0,
            non_finite: NonFiniteSamples::default(),
        }
    }

    /// The part's own image: its tiles' pixels, for a quick look at one part.
    pub fn preview(&self) -> Image {
        let (sums, weights) = sum_in_tile_order(std::slice::from_ref(self));
        resolve(self.width, self.height, sums, weights)
    }

    /// Adds one of the part's finished tiles, tile `index`.
    fn add_tile(&mut self, index: u32, tile: &FinishedTile) {
        let tiles_x = self.width.div_ceil(TILE_SIZE);
        let (tx, ty) = ((index % tiles_x) as i64, (index / tiles_x) as i64);
        let side = 2 * self.reach as i64 + 1;
        let (sums, weights, _) = tile.film.raw();
        let film = &tile.film;
        for y in film.y0..film.y0 + film.height {
            for x in film.x0..film.x0 + film.width {
                let (dx, dy) = (tx - (x / TILE_SIZE) as i64, ty - (y / TILE_SIZE) as i64);
                let layer = ((dy + self.reach as i64) * side + dx + self.reach as i64) as usize;
                let j = ((y - film.y0) * film.width + (x - film.x0)) as usize;
                let s = sums[j];
                self.layers[layer][(y * self.width + x) as usize] = [s.x, s.y, s.z, weights[j]];
            }
        }
        let (x0, y0, x1, _) = tile.bounds;
        for (row, counts) in tile.samples.chunks((x1 - x0) as usize).enumerate() {
            let start = ((y0 + row as u32) * self.width + x0) as usize;
            self.samples[start..start + counts.len()].copy_from_slice(counts);
        }
        self.rays += tile.rays;
        self.non_finite.merge(&tile.non_finite);
    }
}

/// How many tiles away the filter of `scene` reaches.
fn reach(scene: &RenderScene) -> u32 {
    let halo = (scene.settings.filter.radius + 0.5).floor() as u32;
    halo.div_ceil(TILE_SIZE)
}

/// Renders the tiles of `part` on the current rayon pool; `progress(done, total)`
/// counts the part's tiles.
pub fn render_part(
    scene: &RenderScene,
    part: Part,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<PartialFilm, RenderError> {
    let tiles: Vec<u32> = (0..tile_count(scene)).filter(|&t| part.owns(t)).collect();
    let store = TileStore::default();
    render_tiles(scene, &store, &tiles, progress, cancel)?;
    let mut film = PartialFilm::empty(scene.settings.width, scene.settings.height, part, reach(scene));
    store.with_indexed_tiles(|tiles| tiles.for_each(|(index, tile)| film.add_tile(index, tile)));
    Ok(film)
}

/// The image and statistics of the whole render from all `count` of its parts (in any
/// order): bit-identical to rendering it on one machine.
pub fn merge_parts(parts: &[PartialFilm]) -> Result<(Image, RenderStats), PartError> {
    let mut merger: Option<PartMerger> = None;
    for part in parts {
        match &mut merger {
            None => merger = Some(PartMerger::new(part.clone())),
            Some(m) => m.add(part)?,
        }
    }
    merger.ok_or(PartError::Missing { index: 0, count: 1 })?.finish()
}

/// Parts merged as they arrive, in any order, holding one film's worth of memory: each
/// tile's contribution to a pixel lives in exactly one part, so adding a part's layers
/// to the sum so far is exact (the other parts add +0 there), and the final order of
/// addition — tile order, across the layers — is applied when the merge finishes.
#[derive(Clone, Debug)]
pub struct PartMerger {
    film: PartialFilm,
    seen: Vec<bool>,
}

impl PartMerger {
    /// A merge that starts with `first`.
    pub fn new(first: PartialFilm) -> Self {
        let mut seen = vec![false; first.part.count as usize];
        seen[first.part.index as usize] = true;
        Self { film: first, seen }
    }

    /// Adds a part of the same render.
    pub fn add(&mut self, part: &PartialFilm) -> Result<(), PartError> {
        let shape = |p: &PartialFilm| (p.width, p.height, p.reach, p.part.count, p.layers.len());
        if shape(part) != shape(&self.film) {
            return Err(PartError::Mismatch("sizes, filters or part counts differ"));
        }
        let (index, count) = (part.part.index, part.part.count);
        if std::mem::replace(&mut self.seen[index as usize], true) {
            return Err(PartError::Twice { index, count });
        }
        for (mine, theirs) in self.film.layers.iter_mut().zip(&part.layers) {
            for (m, t) in mine.iter_mut().zip(theirs) {
                *m = [0, 1, 2, 3].map(|k| m[k] + t[k]);
            }
        }
        // A pixel's tile belongs to one part; the others hold 0 there.
        for (total, &own) in self.film.samples.iter_mut().zip(&part.samples) {
            *total += own;
        }
        self.film.rays += part.rays;
        self.film.non_finite.merge(&part.non_finite);
        Ok(())
    }

    /// Parts added so far, of how many.
    pub fn progress(&self) -> (usize, usize) {
        (self.seen.iter().filter(|&&s| s).count(), self.seen.len())
    }

    /// The image and statistics, once every part is in.
    pub fn finish(self) -> Result<(Image, RenderStats), PartError> {
        if let Some(index) = self.seen.iter().position(|&s| !s) {
            return Err(PartError::Missing { index: index as u32, count: self.film.part.count });
        }
        let f = &self.film;
        let (sums, weights) = sum_in_tile_order(std::slice::from_ref(f));
        let stats = RenderStats {
            rays: f.rays,
            samples_per_pixel: f.samples.clone(),
            aovs: None,
            non_finite: f.non_finite.clone(),
        };
        Ok((resolve(f.width, f.height, sums, weights), stats))
    }
}

/// Per pixel, the contributions of the tiles around it added in tile order, as a single
/// render's film adds them. Of the parts, only the one that traced a tile holds its
/// contribution; the others hold +0, and adding +0 changes no sum's bits.
fn sum_in_tile_order(parts: &[PartialFilm]) -> (Vec<Vec3>, Vec<f32>) {
    let pixels = parts[0].samples.len();
    let mut sums = vec![Vec3::ZERO; pixels];
    let mut weights = vec![0.0f32; pixels];
    for layer in 0..parts[0].layers.len() {
        for i in 0..pixels {
            let mut contribution = [0.0f32; 4];
            for p in parts {
                let c = p.layers[layer][i];
                contribution = [0, 1, 2, 3].map(|k| contribution[k] + c[k]);
            }
            sums[i] += Vec3::new(contribution[0], contribution[1], contribution[2]);
            weights[i] += contribution[3];
        }
    }
    (sums, weights)
}

/// The weighted averages, by the film's own rule.
fn resolve(width: u32, height: u32, sums: Vec<Vec3>, weights: Vec<f32>) -> Image {
    FilmTile::from_raw((0, 0, width, height), sums, weights, Vec::new()).expect("one sum and weight a pixel").resolve()
}

//! Tiles merged into the image band by band while the render goes on, so a render
//! holds the image and a few rows of tiles rather than every tile's film.
//!
//! A band is a row of tiles' pixels. It can be merged once every tile row whose film
//! (tile plus filter halo) reaches into it has finished, and a tile row is dropped once
//! every band it reaches into has been merged. Tiles finish roughly in order on each
//! worker, so only the rows near each worker's place are held. Each band adds its
//! tiles' sums in tile order, as [`merge_tiles`](super::merge_tiles) does, so the image
//! is bit for bit the same as merging everything at the end.

use std::ops::Range;
use std::sync::{Arc, Mutex, MutexGuard};

use glam::Vec3;

use super::{FinishedTile, NonFiniteSamples, TILE_SIZE, merge_band, tile_rects};
use crate::film::{AovImages, FilmTile};
use crate::scene::RenderScene;

/// The merge of a render's tiles into its image, fed from worker threads.
pub(super) struct StreamingMerge<'a> {
    scene: &'a RenderScene,
    tiles_x: u32,
    /// For each band, the tile rows whose films reach into it.
    rows_of_band: Vec<Range<u32>>,
    /// For each tile row, the bands its films reach into.
    bands_of_row: Vec<Range<u32>>,
    state: Mutex<State>,
    bands: Vec<Mutex<Band<'a>>>,
    /// Band films to merge on, kept between merges: a fresh one each time was fresh
    /// memory each time.
    films: Mutex<Vec<FilmTile>>,
}

/// What the workers share: the finished tiles not yet dropped and the tallies.
struct State {
    tiles: Vec<Option<Arc<FinishedTile>>>,
    finished_in_row: Vec<u32>,
    band_claimed: Vec<bool>,
    rays: u64,
    /// Tiles' non-finite tallies by tile index, merged in tile order at the end (the
    /// first tile's example pixel is the one kept).
    non_finite: Vec<(u32, NonFiniteSamples)>,
}

/// One band's share of the image, written by the worker that merges it.
struct Band<'a> {
    pixels: &'a mut [Vec3],
    counts: &'a mut [u32],
    aovs: Option<AovImages>,
}

/// What is left once every band is merged, besides the pixels and counts.
pub(super) struct Merged {
    pub rays: u64,
    pub non_finite: NonFiniteSamples,
    pub aovs: Option<AovImages>,
}

impl<'a> StreamingMerge<'a> {
    /// A merge into `pixels` and `counts`, the image's pixels and its samples per
    /// pixel, row by row.
    pub fn new(scene: &'a RenderScene, pixels: &'a mut [Vec3], counts: &'a mut [u32]) -> Self {
        let (width, height) = (scene.settings.width, scene.settings.height);
        let tiles_x = width.div_ceil(TILE_SIZE);
        let rows = height.div_ceil(TILE_SIZE);
        // Every tile of a row has the same film rows; the bands are the tiles' rows.
        let film_rows = |row: u32| {
            let [_, y0, _, y1] = tile_rects(scene, row * tiles_x).1;
            y0..y1
        };
        let band_rows = |band: u32| band * TILE_SIZE..((band + 1) * TILE_SIZE).min(height);
        let overlap = |a: &Range<u32>, b: &Range<u32>| a.start < b.end && b.start < a.end;
        let within = |keep: &dyn Fn(u32) -> bool| {
            let hits: Vec<u32> = (0..rows).filter(|&i| keep(i)).collect();
            hits.first().map_or(0..0, |&first| first..hits[hits.len() - 1] + 1)
        };
        let rows_of_band = (0..rows).map(|band| within(&|row| overlap(&film_rows(row), &band_rows(band)))).collect();
        let bands_of_row = (0..rows).map(|row| within(&|band| overlap(&film_rows(row), &band_rows(band)))).collect();
        let band_len = (width * TILE_SIZE) as usize;
        let bands = pixels
            .chunks_mut(band_len)
            .zip(counts.chunks_mut(band_len))
            .map(|(pixels, counts)| Mutex::new(Band { pixels, counts, aovs: None }))
            .collect();
        let state = State {
            tiles: vec![None; (tiles_x * rows) as usize],
            finished_in_row: vec![0; rows as usize],
            band_claimed: vec![false; rows as usize],
            rays: 0,
            non_finite: Vec::new(),
        };
        let films = Mutex::new(Vec::new());
        StreamingMerge { scene, tiles_x, rows_of_band, bands_of_row, state: Mutex::new(state), bands, films }
    }

    /// Takes tile `index`, then merges the bands it completes and drops the tiles no
    /// band needs any more.
    pub fn add(&self, index: u32, mut tile: FinishedTile) {
        let row = index / self.tiles_x;
        let ready = {
            let mut state = self.lock();
            state.rays += tile.rays;
            if !tile.non_finite.is_empty() {
                state.non_finite.push((index, std::mem::take(&mut tile.non_finite)));
            }
            state.tiles[index as usize] = Some(Arc::new(tile));
            state.finished_in_row[row as usize] += 1;
            let ready = self.claim_ready_bands(&mut state, row);
            self.drop_spent_rows(&mut state, &ready);
            ready
        };
        for (band, tiles) in ready {
            self.merge(band, &tiles);
        }
    }

    /// Tile rows the merge holds tiles of now: what it keeps in memory.
    #[cfg(test)]
    fn rows_held(&self) -> usize {
        let state = self.lock();
        state.tiles.chunks(self.tiles_x as usize).filter(|row| row.iter().any(Option::is_some)).count()
    }

    /// The bands that tile row `row` was the last to complete, claimed, each with its
    /// tiles in tile order.
    fn claim_ready_bands(&self, state: &mut State, row: u32) -> Vec<(u32, Vec<Arc<FinishedTile>>)> {
        let mut ready = Vec::new();
        for band in self.bands_of_row[row as usize].clone() {
            let rows = self.rows_of_band[band as usize].clone();
            let complete = rows.clone().all(|r| state.finished_in_row[r as usize] == self.tiles_x);
            if state.band_claimed[band as usize] || !complete {
                continue;
            }
            state.band_claimed[band as usize] = true;
            let indices = rows.start * self.tiles_x..rows.end * self.tiles_x;
            let tiles = indices.map(|i| state.tiles[i as usize].clone().expect("its row is finished")).collect();
            ready.push((band, tiles));
        }
        ready
    }

    /// Drops the tiles of the rows every one of whose bands is claimed (a band being
    /// merged holds its own references).
    fn drop_spent_rows(&self, state: &mut State, claimed: &[(u32, Vec<Arc<FinishedTile>>)]) {
        for &(band, _) in claimed {
            for row in self.rows_of_band[band as usize].clone() {
                if self.bands_of_row[row as usize].clone().all(|b| state.band_claimed[b as usize]) {
                    let row_tiles = (row * self.tiles_x) as usize..((row + 1) * self.tiles_x) as usize;
                    state.tiles[row_tiles].fill(None);
                }
            }
        }
    }

    /// Merges band `band` from `tiles`, its tiles in tile order, on a spare film.
    fn merge(&self, band: u32, tiles: &[Arc<FinishedTile>]) {
        let mut band_out = self.bands[band as usize].lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let Band { pixels, counts, aovs } = &mut *band_out;
        let spare = self.films.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).pop();
        let mut film = spare.unwrap_or_else(|| FilmTile::new(0, 0, 0, 0));
        let y0 = band * TILE_SIZE;
        *aovs = merge_band(self.scene, &mut film, y0, tiles.iter().map(|t| &**t), pixels, counts);
        self.films.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push(film);
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// The tallies and AOVs, once every tile has been added.
    pub fn finish(self) -> Merged {
        let state = self.state.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner());
        assert!(state.band_claimed.iter().all(|&claimed| claimed), "every tile was added");
        let mut tallies = state.non_finite;
        tallies.sort_by_key(|&(index, _)| index);
        let mut non_finite = NonFiniteSamples::default();
        for (_, tally) in &tallies {
            non_finite.merge(tally);
        }
        let band_aovs =
            self.bands.into_iter().map(|band| band.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner()).aovs);
        let band_aovs = band_aovs.collect();
        Merged { rays: state.rays, non_finite, aovs: AovImages::stacked(band_aovs) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::desc::*;
    use crate::render::{render_tile, tile_count};
    use crate::scene::compile;

    /// Fed in tile order, the merge holds a few rows of tiles at a time, never the
    /// image's ten, and none at the end.
    #[test]
    fn holds_only_the_rows_near_the_last_tile() {
        let sphere = NodeDesc {
            transform: vec![],
            kind: NodeKind::Shape { shape: ShapeDesc::Sphere, material: 0 },
            origin: String::new(),
        };
        let desc = SceneDesc {
            settings: RenderSettings {
                width: 64,
                height: 160,
                filter: FilterDesc { kind: FilterKind::Gaussian, radius: 2.0 },
                ..Default::default()
            },
            camera: CameraDesc { eye: Vec3::new(0.0, 0.0, 5.0), look: Vec3::NEG_Z, up: Vec3::Y, ..Default::default() },
            materials: vec![MaterialDesc::default()],
            objects: vec![sphere],
            ..Default::default()
        };
        let scene = compile(&desc).expect("valid scene");
        let mut pixels = vec![Vec3::ZERO; 64 * 160];
        let mut counts = vec![0; 64 * 160];
        let merge = StreamingMerge::new(&scene, &mut pixels, &mut counts);
        let mut most_held = 0;
        for index in 0..tile_count(&scene) {
            merge.add(index, render_tile(&scene, index));
            most_held = most_held.max(merge.rows_held());
        }
        assert_eq!(merge.rows_held(), 0);
        assert!(most_held <= 3, "held {most_held} rows of tiles of 10");
        merge.finish();
        assert!(counts.iter().all(|&c| c == scene.settings.spp), "every pixel's count merged");
    }
}

//! Rendering a compiled scene on all cores, tile by tile.
//!
//! Every pixel is a pure function of the scene and its position, and tiles are
//! assembled in a fixed order, so the image is bit-identical for any thread count.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use crate::film::Image;
use crate::integrator::{Counters, whitted};
use crate::scene::RenderScene;

/// Side of the square tiles the image is cut into.
pub const TILE_SIZE: u32 = 16;

/// What a finished render reports besides the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    pub rays: u64,
}

/// Why a render returned no image.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    #[error("render cancelled")]
    Cancelled,
}

/// Renders on the current rayon pool. `progress(done, total)` is called after each
/// tile (from worker threads); setting `cancel` stops the render between tiles.
pub fn render(
    scene: &RenderScene,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(Image, RenderStats), RenderError> {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let tiles_x = width.div_ceil(TILE_SIZE);
    let tiles_y = height.div_ceil(TILE_SIZE);
    let total = (tiles_x * tiles_y) as usize;
    let done = AtomicUsize::new(0);
    let tiles: Vec<Option<(Vec<Vec3>, Counters)>> = (0..total)
        .into_par_iter()
        .map(|i| {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let x0 = (i as u32 % tiles_x) * TILE_SIZE;
            let y0 = (i as u32 / tiles_x) * TILE_SIZE;
            let tile = render_tile(scene, x0, y0);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            Some(tile)
        })
        .collect();
    if cancel.load(Ordering::Relaxed) || tiles.iter().any(Option::is_none) {
        return Err(RenderError::Cancelled);
    }
    let mut image = Image::new(width, height);
    let mut stats = RenderStats::default();
    for (i, (pixels, counters)) in tiles.into_iter().flatten().enumerate() {
        let x0 = (i as u32 % tiles_x) * TILE_SIZE;
        let y0 = (i as u32 / tiles_x) * TILE_SIZE;
        let tile_w = TILE_SIZE.min(width - x0);
        for (row, chunk) in pixels.chunks(tile_w as usize).enumerate() {
            let start = ((y0 + row as u32) * width + x0) as usize;
            image.pixels[start..start + chunk.len()].copy_from_slice(chunk);
        }
        stats.rays += counters.rays;
    }
    Ok((image, stats))
}

/// The pixels of one tile, row by row, each the box-filtered mean of an n×n grid of
/// sub-pixel samples.
fn render_tile(scene: &RenderScene, x0: u32, y0: u32) -> (Vec<Vec3>, Counters) {
    let s = &scene.settings;
    let x1 = (x0 + TILE_SIZE).min(s.width);
    let y1 = (y0 + TILE_SIZE).min(s.height);
    let n = s.samples_per_axis;
    let inv_samples = 1.0 / (n * n) as f32;
    let mut counters = Counters::default();
    let mut pixels = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
    for py in y0..y1 {
        for px in x0..x1 {
            let mut sum = Vec3::ZERO;
            for sy in 0..n {
                for sx in 0..n {
                    let fx = px as f32 + (sx as f32 + 0.5) / n as f32;
                    let fy = py as f32 + (sy as f32 + 0.5) / n as f32;
                    // Screen space to the film plane: x, y in [−1, 1], +y up.
                    let x = 2.0 * fx / s.width as f32 - 1.0;
                    let y = 1.0 - 2.0 * fy / s.height as f32;
                    let ray = scene.camera.ray(x, y);
                    sum += whitted::radiance(scene, &ray, 0, Vec3::ONE, &mut counters);
                }
            }
            pixels.push(sum * inv_samples);
        }
    }
    (pixels, counters)
}

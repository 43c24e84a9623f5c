//! A path-traced tile as waves of eight paths, for scenes of a handful of analytic
//! objects ([`FewObjects`]).
//!
//! Each of eight lanes owns one pixel at a time and traces its samples in order, one
//! path after another. Every step takes the rays each lane's path waits on — its pending
//! shadow ray and the closest-hit ray it traces next — as two waves, traces each with
//! the rays side by side, and hands each path its answers, the shadow's first; the
//! vertices found on plain diffuse surfaces are then shaded together in vector lanes
//! ([`DiffuseWave`]), the others each by its own path. A path's value is what tracing it
//! alone gives, and each pixel's samples reach the film in the same order, so the image
//! is the one the one-path-at-a-time loop renders: bit for bit with the one-pixel box
//! filter, but for a sample exactly on a pixel border (it reaches both pixels, and the
//! neighbour adds it in another order, as wider filters add their samples).

use std::array;

use super::{TileFilm, Traced, path_camera_ray, pixel_stream};
use crate::film::Aov;
use crate::integrator::path::{DiffuseWave, LanePath, PathState};
use crate::integrator::{Counters, SurfaceId};
use crate::sampling::{PathSampler, PixelStream};
use crate::scene::{FewObjects, NO_OBJECT, RayWave, RenderScene, WAVE};

/// One lane's sample in flight.
struct Lane {
    pixel: (u32, u32),
    /// The pixel's random streams, shared by its samples.
    stream: PixelStream,
    index: u32,
    film_point: (f32, f32),
    path: PathState,
    sampler: PathSampler,
    aov: Aov,
    /// Whether the path has not yet reached its first vertex (which the AOVs describe).
    at_camera: bool,
    counters: Counters,
}

impl Lane {
    /// The first sample of `pixel`, its camera ray ready to trace.
    #[inline(always)]
    fn start(scene: &RenderScene, pixel: (u32, u32)) -> Lane {
        Lane::start_with(scene, pixel_stream(scene, pixel.0, pixel.1), pixel, 0)
    }

    /// Sample `index` of `pixel`, whose streams are `stream`.
    #[inline(always)]
    fn start_with(scene: &RenderScene, stream: PixelStream, pixel: (u32, u32), index: u32) -> Lane {
        let (sampler, film_point, ray) = path_camera_ray(scene, &stream, pixel, index);
        let mut counters = Counters::default();
        let path = PathState::new(scene, &ray, &mut counters);
        Lane { pixel, stream, index, film_point, path, sampler, aov: Aov::default(), at_camera: true, counters }
    }

    /// The finished sample for the film.
    fn traced(&mut self) -> Traced {
        let (fx, fy) = self.film_point;
        Traced { fx, fy, value: self.path.radiance(), aov: self.aov, culprit: self.counters.non_finite_at.take() }
    }
}

/// Every sample of the tile `(x0, y0)`–`(x1, y1)`, traced in waves through `few`.
#[inline(always)]
pub(super) fn path_tile_in_waves(
    scene: &RenderScene,
    few: &FewObjects,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
    film: &mut TileFilm,
    counters: &mut Counters,
) {
    let spp = scene.settings.spp;
    if spp == 0 {
        return;
    }
    let mut pixels = (y0..y1).flat_map(|py| (x0..x1).map(move |px| (px, py)));
    let mut lanes: [Option<Lane>; WAVE] = array::from_fn(|_| pixels.next().map(|p| Lane::start(scene, p)));
    loop {
        // Each lane's pending shadow ray and the closest-hit ray it traces next, in two
        // waves traced together: a path's vertices then take one step each, and every
        // lane of the extension wave has a vertex to shade.
        let (mut shadows, mut rays) = (RayWave::default(), RayWave::default());
        let (mut busy, mut any_shadow) = (false, false);
        for (k, slot) in lanes.iter_mut().enumerate() {
            // Finished samples go to the film; the lane starts its pixel's next sample,
            // or the tile's next pixel.
            while let Some(lane) = slot.as_mut().filter(|lane| lane.path.is_done()) {
                film.splat(&lane.traced());
                counters.rays += lane.counters.rays;
                let (pixel, next) = (lane.pixel, lane.index + 1);
                if next < spp {
                    *lane = Lane::start_with(scene, lane.stream, pixel, next);
                } else if let Some(pixel) = pixels.next() {
                    *lane = Lane::start(scene, pixel);
                } else {
                    *slot = None;
                }
            }
            let Some(lane) = slot else { continue };
            busy = true;
            if let Some(shadow) = lane.path.shadow_ray() {
                shadows.set(k, &shadow.ray, shadow.t_max, true);
                any_shadow = true;
            }
            if let Some(ray) = lane.path.ray_after_shadow() {
                rays.set(k, &ray, f32::INFINITY, false);
            }
        }
        if !busy {
            return;
        }
        let blocked = any_shadow.then(|| few.blocked(&shadows));
        let hits = few.trace(&rays);
        // Vertices on plain diffuse surfaces are shaded together, the others each alone.
        let mut diffuse = DiffuseWave::default();
        for (k, slot) in lanes.iter_mut().enumerate() {
            let Some(lane) = slot else { continue };
            // The shadow ray first: the path adds its light before the next vertex's.
            if let Some(blocked) = &blocked
                && shadows.shadow[k] != 0
            {
                lane.path.resolve_shadow(blocked[k] != 0, &mut lane.counters);
            }
            if let Some(ray) = lane.path.next_ray() {
                let wants_aov = lane.at_camera && scene.settings.aovs;
                lane.at_camera = false;
                let object = hits.object[k];
                // (Few objects are analytic: the instance's material is the surface's.)
                let material = (object != NO_OBJECT).then(|| scene.instances[object as usize].material);
                match material {
                    Some(material) if !wants_aov && lane.path.shades_in_wave(scene, material) => {
                        let (point, normal) = scene.few_objects_surface(&ray, &hits, k);
                        let surface = SurfaceId { instance: object, material };
                        diffuse.add(scene, k, &lane.path, &mut lane.sampler, (surface, point, normal));
                    }
                    _ => {
                        let hit = scene.few_objects_hit(&ray, &hits, k);
                        let aov = wants_aov.then_some(&mut lane.aov);
                        lane.path.advance(scene, hit, &mut lane.sampler, &mut lane.counters, aov);
                    }
                }
            }
        }
        if !diffuse.is_empty() {
            diffuse.advance(lanes.iter_mut().map(|slot| {
                let lane = slot.as_mut()?;
                Some(LanePath { path: &mut lane.path, sampler: &mut lane.sampler, counters: &mut lane.counters })
            }));
        }
    }
}

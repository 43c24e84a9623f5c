//! A Whitted tile as waves of eight rays, for scenes of a handful of analytic objects
//! ([`FewObjects`]).
//!
//! The lighting equation is linear in what each ray brings back, so a sample's ray tree
//! need not be walked depth first: every ray can carry its weight in the pixel (the
//! product of the `k·O` factors above it) and add its hit's local light, weighted, to
//! its sample, in any order. The tile's rays wait on a stack, camera rays first; each
//! step traces eight of them side by side, shades each hit (ambient and lights), and
//! pushes the reflected and transmitted rays it spawns. Shadow rays wait apart with the
//! light they would add and are traced eight at a time too (the point lights' directions
//! for a wave's hits are worked out side by side first, [`LaneIncidence`]); an unblocked
//! one adds its light, one stopped by an opaque object nothing, and one that meets
//! transparent objects goes on past them, in waves too, filtered by each as
//! [`RenderScene::transmittance`] filters a single ray.
//!
//! A pinhole camera's rays are made a wave at a time too
//! ([`crate::camera::Camera::pinhole_directions`]), bit for bit the rays
//! [`camera_sample`] makes one by one.
//!
//! A sample sums the same terms as the recursion, in another order, so its value agrees
//! with it to rounding (the tests hold the two images to 1e-5); an area light's jitter
//! is drawn from the sample's stream in the order the waves reach its hits, so with
//! area lights the soft shadows' noise differs, not their mean.

use glam::{Vec2, Vec3};

use super::lane_incidence::LaneIncidence;
use super::{TileFilm, Traced, camera_sample, film_ray, sample_context, whitted_aov};
use crate::integrator::observe::NoObserver;
use crate::integrator::whitted::{Facing, ShadowRays, for_each_secondary, shade_vertex};
use crate::integrator::{Counters, SurfaceId, TraceContext};
use crate::math::{Ray, all_finite};
use crate::sampling::PixelSampler;
use crate::scene::{FewObjects, NO_OBJECT, RayWave, RenderScene, WAVE, WaveHits};

/// At least this many samples are traced together, whole pixels at a time: enough to
/// keep waves full while the trees thin out, few enough to stay in cache.
const BATCH_SAMPLES: usize = 256;

/// A camera sample whose tree is in flight: what it has gathered so far, kept as the
/// record `done` takes by reference at the end (built there, it was copied through
/// memory and stalled the loads that read it back).
struct Sample {
    traced: Traced,
    ctx: TraceContext,
}

/// A ray waiting to be traced: its sample, its weight in that sample and its depth.
struct Pending {
    sample: u32,
    ray: Ray,
    weight: Vec3,
    depth: u32,
}

/// A shadow ray waiting to be traced, with the light (already weighted) it adds to its
/// sample if nothing is in the way, and the surface it leaves (to blame for a NaN).
struct PendingShadow {
    sample: u32,
    ray: Ray,
    t_max: f32,
    light: Vec3,
    surface: SurfaceId,
}

/// The shadow rays one hit puts aside, weighted by its ray's weight.
struct Deferred<'a> {
    queue: &'a mut Vec<PendingShadow>,
    sample: u32,
    weight: Vec3,
    surface: SurfaceId,
    /// The wave's point lights as its hits see them, and this hit's lane.
    lit: &'a LaneIncidence,
    lane: usize,
}

impl ShadowRays for Deferred<'_> {
    #[inline(always)]
    fn filter(&mut self, _: &RenderScene, _: &Ray, _: f32, _: &mut u64) -> Option<Vec3> {
        None
    }

    #[inline(always)]
    fn incidence(
        &mut self,
        light_index: usize,
        light: &crate::light::Light,
        p: Vec3,
        index: u32,
        jitter: Vec2,
    ) -> crate::light::Incidence {
        self.lit.get(light_index, light, self.lane).unwrap_or_else(|| light.sample(p, index, jitter))
    }

    #[inline(always)]
    fn defer(&mut self, ray: &Ray, t_max: f32, light: Vec3) {
        let light = self.weight * light;
        self.queue.push(PendingShadow { sample: self.sample, ray: *ray, t_max, light, surface: self.surface });
    }
}

/// Every sample of the tile `(x0, y0)`–`(x1, y1)`, traced in waves through `few` and
/// splatted in pixel order.
#[inline(always)]
pub(super) fn whitted_tile_in_waves(
    scene: &RenderScene,
    few: &FewObjects,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
    film: &mut TileFilm,
    counters: &mut Counters,
) {
    let spp = scene.settings.spp;
    let mut requests = Vec::with_capacity(((x1 - x0) * (y1 - y0) * spp) as usize);
    for py in y0..y1 {
        for px in x0..x1 {
            requests.extend((0..spp).map(|index| (px, py, index)));
        }
    }
    let seen = seen_by_camera(scene, few, (x0, y0, x1, y1));
    let objects = Objects { all: few, seen_by_camera: seen.as_ref().unwrap_or(few) };
    trace_requests(scene, objects, &scene.settings.sampler, &requests, counters, |_, traced| film.splat(traced));
}

/// The objects a wave is traced against: all of them, or, for a wave of camera rays
/// only, those the tile's camera rays can meet.
#[derive(Clone, Copy)]
struct Objects<'a> {
    all: &'a FewObjects,
    seen_by_camera: &'a FewObjects,
}

/// The objects of `few` that the camera rays through the pixels `(x0, y0)`–`(x1, y1)`
/// can meet ([`FewObjects::seen_from`]), for a pinhole camera; `None` for a lens,
/// whose rays start anywhere on it.
fn seen_by_camera(scene: &RenderScene, few: &FewObjects, (x0, y0, x1, y1): (u32, u32, u32, u32)) -> Option<FewObjects> {
    if scene.camera.aperture_radius > 0.0 {
        return None;
    }
    // A pixel wider on every side than the samples reach.
    let (left, right) = (x0 as f32 - 1.0, x1 as f32 + 1.0);
    let (top, bottom) = (y0 as f32 - 1.0, y1 as f32 + 1.0);
    let direction = |fx: f32, fy: f32| film_ray(scene, fx, fy, Vec2::ZERO).dir;
    let corners = [direction(left, top), direction(right, top), direction(right, bottom), direction(left, bottom)];
    Some(few.seen_from(scene.camera.eye, corners))
}

/// Traces the samples `(px, py, index)` that `requests` names, at the positions
/// `sampler` gives, in waves through `few`, and hands each to `done` with its request,
/// in the order asked. Batches of whole pixels when the requests come pixel by pixel.
#[inline(always)]
pub(super) fn trace_samples_in_waves(
    scene: &RenderScene,
    few: &FewObjects,
    sampler: &PixelSampler,
    requests: &[(u32, u32, u32)],
    counters: &mut Counters,
    done: impl FnMut((u32, u32, u32), &Traced),
) {
    let objects = Objects { all: few, seen_by_camera: few };
    trace_requests(scene, objects, sampler, requests, counters, done);
}

/// [`trace_samples_in_waves`] against `objects`.
#[inline(always)]
fn trace_requests(
    scene: &RenderScene,
    objects: Objects,
    sampler: &PixelSampler,
    requests: &[(u32, u32, u32)],
    counters: &mut Counters,
    mut done: impl FnMut((u32, u32, u32), &Traced),
) {
    let (mut camera_rays, mut samples) = (Vec::with_capacity(BATCH_SAMPLES), Vec::with_capacity(BATCH_SAMPLES));
    let (mut rays, mut shadows) = (Vec::new(), Vec::new());
    let pinhole = scene.camera.aperture_radius <= 0.0 && scene.motions.is_empty();
    let mut start = 0;
    while start < requests.len() {
        // Up to the batch size, then on to the end of the pixel.
        let mut end = (start + BATCH_SAMPLES).min(requests.len());
        let same_pixel = |a: &(u32, u32, u32), b: &(u32, u32, u32)| (a.0, a.1) == (b.0, b.1);
        while end < requests.len() && same_pixel(&requests[end], &requests[end - 1]) {
            end += 1;
        }
        let batch = &requests[start..end];
        start = end;
        // The camera samples first, all of them: their rays are read long after they
        // were written (read at once, they stalled on the stores that returned them).
        // Loops, not `Vec::extend`, whose own function is built without AVX2.
        samples.clear();
        camera_rays.clear();
        if pinhole {
            for wave in batch.chunks(WAVE) {
                push_pinhole_samples(scene, sampler, wave, &mut samples, &mut camera_rays);
            }
        } else {
            for &(px, py, index) in batch {
                let camera = camera_sample(scene, sampler, px, py, index);
                samples.push(Sample { traced: Traced::at(camera.fx, camera.fy), ctx: camera.ctx });
                camera_rays.push(camera.ray);
            }
        }
        // Pushed in reverse and popped from the end: the batch's first rays go first.
        let pending = camera_rays.iter().enumerate().rev();
        rays.extend(pending.map(|(k, &ray)| Pending { sample: k as u32, ray, weight: Vec3::ONE, depth: 0 }));
        counters.rays += trace_batch(scene, objects, &mut samples, &mut rays, &mut shadows);
        for (&request, sample) in batch.iter().zip(&mut samples) {
            counters.rays += sample.ctx.counters.rays;
            sample.traced.culprit = sample.ctx.counters.non_finite_at;
            done(request, &sample.traced);
        }
    }
}

/// Pushes the samples `requests` (up to a wave of them) of a pinhole camera, which no
/// motion blur draws a moment for, and their camera rays: the film positions and the
/// rays' directions worked out side by side, bit for bit those [`camera_sample`] gives.
#[inline(always)]
fn push_pinhole_samples(
    scene: &RenderScene,
    sampler: &PixelSampler,
    requests: &[(u32, u32, u32)],
    samples: &mut Vec<Sample>,
    camera_rays: &mut Vec<Ray>,
) {
    let (mut fx, mut fy) = ([0.0; WAVE], [0.0; WAVE]);
    for (k, &(px, py, index)) in requests.iter().enumerate() {
        let offset = sampler.offset(px, py, index);
        (fx[k], fy[k]) = (px as f32 + offset.x, py as f32 + offset.y);
    }
    // Screen space to the film plane as `film_ray` maps it: x, y in [−1, 1], +y up.
    let (width, height) = (scene.settings.width as f32, scene.settings.height as f32);
    let x: [f32; WAVE] = std::array::from_fn(|k| 2.0 * fx[k] / width - 1.0);
    let y: [f32; WAVE] = std::array::from_fn(|k| 1.0 - 2.0 * fy[k] / height);
    let dir = scene.camera.pinhole_directions(&x, &y);
    for (k, &(px, py, index)) in requests.iter().enumerate() {
        let mut ctx = sample_context(scene, px, py, index);
        // The lens point a pinhole does not draw.
        ctx.rng.skip(2);
        samples.push(Sample { traced: Traced::at(fx[k], fy[k]), ctx });
        camera_rays.push(Ray::new(scene.camera.eye, Vec3::new(dir[0][k], dir[1][k], dir[2][k])));
    }
}

/// Traces `rays` and every ray they spawn, shadow rays included, adding what each
/// brings back to its sample; returns how many rays shadow rays traced past
/// transparent surfaces (the samples count the others).
#[inline(always)]
fn trace_batch(
    scene: &RenderScene,
    objects: Objects,
    samples: &mut [Sample],
    rays: &mut Vec<Pending>,
    shadows: &mut Vec<PendingShadow>,
) -> u64 {
    let mut crossing_rays = 0;
    let mut wave = Vec::with_capacity(WAVE);
    while !rays.is_empty() {
        // The last rays on the stack, the last first, moved in one copy.
        let from = rays.len().saturating_sub(WAVE);
        wave.clear();
        wave.extend(rays.drain(from..).rev());
        let mut lanes = RayWave::default();
        for (lane, pending) in wave.iter().enumerate() {
            lanes.set(lane, &pending.ray, f32::INFINITY, false);
        }
        let camera_rays_only = wave.iter().all(|pending| pending.depth == 0);
        let few = if camera_rays_only { objects.seen_by_camera } else { objects.all };
        let hits = few.trace(&lanes);
        let lit = LaneIncidence::of(scene, &lanes, &hits);
        for (lane, pending) in wave.iter().enumerate() {
            let sample = &mut samples[pending.sample as usize];
            sample.ctx.counters.rays += 1;
            let hit = scene.few_objects_hit_for_lighting(&pending.ray, &hits, lane);
            if pending.depth == 0 && scene.settings.aovs {
                sample.traced.aov = whitted_aov(scene, &pending.ray, hit.as_ref(), sample.ctx.footprint_scale);
            }
            // By reference: moved out of its option, the hit was copied through memory
            // and stalled the loads that read it back.
            let Some(hit) = hit.as_ref() else {
                sample.traced.value += pending.weight * scene.background(pending.ray.dir);
                continue;
            };
            let surface = SurfaceId::of(hit);
            let mut deferred =
                Deferred { queue: shadows, sample: pending.sample, weight: pending.weight, surface, lit: &lit, lane };
            let facing = Facing::of(&pending.ray, hit);
            let seen = (&pending.ray, hit, &facing);
            let local = shade_vertex(scene, seen, &mut sample.ctx, &mut deferred, &mut NoObserver);
            let local = pending.weight * local;
            if !all_finite(local) {
                sample.ctx.counters.blame(hit);
            }
            sample.traced.value += local;
            for_each_secondary(scene, seen, pending.depth, pending.weight, |ray, _, _, weight| {
                rays.push(Pending { sample: pending.sample, ray, weight, depth: pending.depth + 1 });
            });
        }
        while shadows.len() >= WAVE {
            let at = shadows.len() - WAVE;
            crossing_rays += resolve_shadows(scene, objects.all, samples, &shadows[at..]);
            shadows.truncate(at);
        }
    }
    if !shadows.is_empty() {
        crossing_rays += resolve_shadows(scene, objects.all, samples, shadows);
        shadows.clear();
    }
    crossing_rays
}

/// Traces up to [`WAVE`] shadow rays side by side and adds to each sample the light of
/// those that reach their light; returns how many rays they traced past transparent
/// surfaces, as [`RenderScene::transmittance_counted`] counts them.
#[inline(always)]
fn resolve_shadows(scene: &RenderScene, few: &FewObjects, samples: &mut [Sample], shadows: &[PendingShadow]) -> u64 {
    let mut lanes = RayWave::default();
    for (lane, shadow) in shadows.iter().enumerate() {
        lanes.set(lane, &shadow.ray, shadow.t_max, true);
    }
    let mut add = |shadow: &PendingShadow, filter: Vec3| {
        if filter == Vec3::ZERO {
            return;
        }
        let sample = &mut samples[shadow.sample as usize];
        let light = filter * shadow.light;
        if !all_finite(light) {
            sample.ctx.counters.blame_surface(shadow.surface);
        }
        sample.traced.value += light;
    };
    if !(scene.has_transmissive && scene.settings.features.transparent_shadows) {
        let blocked = few.blocked(&lanes);
        for (lane, shadow) in shadows.iter().enumerate() {
            if blocked[lane] == 0 {
                add(shadow, Vec3::ONE);
            }
        }
        return 0;
    }
    // Transparent occluders filter the light: each ray goes on past the transparent
    // surfaces it meets, in waves, until it reaches its light or an opaque surface.
    // The first wave reads the pending rays as they are; the few that go on are packed
    // at the front of a wave-sized array, not a vector, so the waves allocate nothing.
    let hits = few.trace(&lanes);
    let mut going = Going::default();
    for (lane, shadow) in shadows.iter().enumerate() {
        let crossing = Crossing { shadow, ray: shadow.ray, t_left: shadow.t_max, filter: Vec3::ONE };
        going.step(scene, &hits, lane, &crossing, &mut add);
    }
    // The bound only guards against pathological scenes, as in `transmittance`.
    let mut crossing_rays = 0;
    for _ in 1..64 {
        if going.count == 0 {
            break;
        }
        crossing_rays += going.count as u64;
        let hits = few.trace(&going.lanes);
        let crossings = std::mem::take(&mut going);
        for (lane, crossing) in crossings.crossings.iter().take(crossings.count).enumerate() {
            going.step(scene, &hits, lane, crossing.as_ref().expect("packed at the front"), &mut add);
        }
    }
    crossing_rays
}

/// The shadow rays that go on past a transparent surface, packed at the front.
#[derive(Default)]
struct Going<'a> {
    crossings: [Option<Crossing<'a>>; WAVE],
    lanes: RayWave,
    count: usize,
}

impl<'a> Going<'a> {
    /// Where `crossing`'s lane of `hits` leads: nothing more in the way (its light is
    /// added), an opaque surface (nothing is), or a transparent one (it goes on past it,
    /// filtered).
    #[inline(always)]
    fn step(
        &mut self,
        scene: &RenderScene,
        hits: &WaveHits,
        lane: usize,
        crossing: &Crossing<'a>,
        add: &mut impl FnMut(&PendingShadow, Vec3),
    ) {
        let object = hits.object[lane];
        if object == NO_OBJECT {
            add(crossing.shadow, crossing.filter);
            return;
        }
        let material = &scene.materials[scene.instances[object as usize].material as usize];
        let filter = crossing.filter * material.transmissive;
        if filter.max_element() <= 0.0 {
            return;
        }
        let beyond = crossing.past_surface(scene, hits, lane, filter);
        self.lanes.set(self.count, &beyond.ray, beyond.t_left, true);
        self.crossings[self.count] = Some(beyond);
        self.count += 1;
    }
}

/// A shadow ray on its way through transparent surfaces: what is left of its segment
/// and the filter of the surfaces crossed so far.
#[derive(Clone, Copy)]
struct Crossing<'a> {
    shadow: &'a PendingShadow,
    ray: Ray,
    t_left: f32,
    filter: Vec3,
}

impl Crossing<'_> {
    /// The same shadow ray, past the surface its lane of `hits` met, with `filter`: as
    /// [`RenderScene::transmittance`] steps on, the far end of the segment kept fixed.
    #[inline(always)]
    fn past_surface(&self, scene: &RenderScene, hits: &WaveHits, lane: usize, filter: Vec3) -> Self {
        let (point, normal) = scene.few_objects_surface(&self.ray, hits, lane);
        let (ray, t_left) = crate::scene::past_surface(&self.ray, self.t_left, point, normal);
        Crossing { shadow: self.shadow, ray, t_left, filter }
    }
}

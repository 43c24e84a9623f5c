//! Unidirectional path tracing: the rendering equation
//! `L_o(p, ω_o) = L_e(p, ω_o) + ∫ f(p, ω_o, ω_i) L_i(p, ω_i) |cos θ_i| dω_i`
//! estimated by random walks from the camera (Kajiya 1986).
//!
//! Each vertex takes one light sample (next-event estimation) and one BSDF sample; the
//! two estimate the same direct light and are combined by multiple importance sampling
//! with the power heuristic (Veach & Guibas 1995). Delta lights and delta lobes, which
//! only one strategy can find, get full weight. Depth and Russian roulette are counted
//! as Mitsuba 3's `path` integrator counts them, so `max_depth` means the same there.

use glam::{Vec2, Vec3};

use super::Counters;
use crate::bsdf::SurfaceBsdf;
use crate::desc::PathDesc;
use crate::emitter::{EmitterKind, LightSample};
use crate::film::Aov;
use crate::material::NO_TEXTURE;
use crate::math::{Ray, offset_ray_origin};
use crate::sampling::PathSampler;
use crate::scene::{Hit, RenderScene};

/// The shading frame: z along the unit normal.
#[derive(Clone, Copy, Debug)]
struct Frame {
    s: Vec3,
    t: Vec3,
    n: Vec3,
}

impl Frame {
    fn new(n: Vec3) -> Self {
        let (s, t) = n.any_orthonormal_pair();
        Self { s, t, n }
    }

    fn to_local(self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    fn to_world(self, v: Vec3) -> Vec3 {
        v.x * self.s + v.y * self.t + v.z * self.n
    }
}

/// `a²/(a² + b²)`: the power heuristic with β = 2.
#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

/// Where the last bounce came from, to weigh emission a BSDF-sampled ray finds.
#[derive(Clone, Copy)]
struct Bounce {
    point: Vec3,
    pdf: f32,
    delta: bool,
}

/// Radiance arriving along the camera ray `ray`, drawing every random number from
/// `sampler`; `aov`, when given, receives what the first hit looks like. Always inlined,
/// so the render's AVX2 tile loop compiles the path loop for AVX2 too.
#[inline(always)]
pub fn radiance(
    scene: &RenderScene,
    ray: &Ray,
    sampler: &mut PathSampler,
    counters: &mut Counters,
    mut aov: Option<&mut Aov>,
) -> Vec3 {
    let limits = match scene.settings.integrator {
        crate::desc::IntegratorDesc::Path(p) => p,
        crate::desc::IntegratorDesc::Whitted => PathDesc::default(),
    };
    if limits.max_depth == 0 {
        return Vec3::ZERO;
    }
    let mut radiance = Vec3::ZERO;
    let mut throughput = Vec3::ONE;
    let mut eta = 1.0f32;
    let mut ray = *ray;
    let mut previous: Option<Bounce> = None;
    let mut depth = 0u32;
    loop {
        counters.rays += 1;
        let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
            radiance += throughput * environment_light(scene, &ray, previous);
            break;
        };
        let wo_world = -ray.dir.normalize();
        let record = &scene.bsdfs[hit.material as usize];
        let mut bsdf = record.at(hit.uv, |i, uv| scene.texture(i, uv));
        bsdf.color *= hit.color;
        if let Some(aov) = aov.take() {
            *aov = Aov { albedo: bsdf.albedo(), normal: hit.normal, depth: hit.t * ray.dir.length() };
        }
        radiance += throughput * emitted(scene, &hit, &bsdf, wo_world, previous);
        if !radiance.is_finite() {
            counters.blame(&hit);
            break;
        }

        // Mitsuba's counting: a path of max_depth vertices past the camera at most.
        if depth.saturating_add(1) >= limits.max_depth {
            break;
        }
        let frame = Frame::new(hit.normal);
        let wo = frame.to_local(wo_world);
        // Dimensions are drawn in the same order at every vertex, light or not, so each
        // has a fixed place in the sequence.
        // One pair chooses the light and the BSDF lobe, one places the light sample,
        // one the BSDF direction.
        let choices = sampler.next_2d();
        let u_light = sampler.next_2d();
        let u_dir = sampler.next_2d();
        if bsdf.has_non_delta() {
            radiance +=
                throughput * direct_light(scene, &hit, &bsdf, &frame, wo, (choices.x, u_light), ray.time, counters);
        }
        if !radiance.is_finite() {
            counters.blame(&hit);
            break;
        }
        let u_lobe = choices.y;
        let Some(sample) = bsdf.sample(wo, u_lobe, u_dir) else { break };
        let wi = frame.to_world(sample.wi);
        if !same_side_story(&hit, (wo_world, wi), (wo, sample.wi)) {
            break;
        }
        throughput *= sample.weight;
        eta *= sample.eta;
        ray = Ray::new(offset_ray_origin(hit.point, side_normal(&hit, wi)), wi).at_time(ray.time);
        previous = Some(Bounce { point: hit.point, pdf: sample.pdf, delta: sample.delta });
        depth += 1;

        if !throughput.is_finite() {
            // A BSDF sample weighed NaN or infinity: the whole sample is void.
            counters.blame(&hit);
            return Vec3::NAN;
        }
        let most = throughput.max_element();
        if most <= 0.0 {
            break;
        }
        // Roulette draws its number only at depths where it plays (the same depths for
        // every path, so dimensions stay aligned).
        if depth >= limits.rr_depth {
            let survive = (most * eta * eta).min(0.95);
            if sampler.next_1d() >= survive {
                break;
            }
            throughput /= survive;
        }
    }
    radiance
}

/// Whether the shading frame and the true surface agree that `wi` is a reflection (same
/// side as `wo`) or a transmission. Interpolated mesh normals can make a direction above
/// the shading surface lie below the true one; following it would leak light through
/// the surface (Veach 1997, §5.3), so such directions carry nothing.
#[inline]
fn same_side_story(hit: &Hit, (wo_world, wi_world): (Vec3, Vec3), (wo, wi): (Vec3, Vec3)) -> bool {
    let ng = hit.geometric_normal;
    (wo.z * wi.z > 0.0) == (ng.dot(wo_world) * ng.dot(wi_world) > 0.0)
}

/// The geometric normal on the side `w` leaves from: secondary rays start off the
/// surface on that side.
#[inline]
fn side_normal(hit: &Hit, w: Vec3) -> Vec3 {
    if hit.geometric_normal.dot(w) >= 0.0 { hit.geometric_normal } else { -hit.geometric_normal }
}

/// Emission of the surface at `hit` toward `wo`, MIS-weighted against light sampling
/// when the surface was found by a BSDF sample.
fn emitted(scene: &RenderScene, hit: &Hit, bsdf: &SurfaceBsdf<'_>, wo: Vec3, previous: Option<Bounce>) -> Vec3 {
    let record = &bsdf.record;
    if !record.is_emissive() {
        return Vec3::ZERO;
    }
    // The true surface decides the side and the density, as light sampling sees it.
    let front = hit.geometric_normal.dot(wo) > 0.0;
    if !front && record.flags & crate::bsdf::EMITS_BOTH_SIDES == 0 {
        return Vec3::ZERO;
    }
    let weight = match previous {
        Some(b) if !b.delta => match (scene.emitter_of(hit), &scene.light_selection) {
            (Some(index), Some(selection)) => {
                let light_pdf = selection.probability(index as usize)
                    * scene.emitters[index as usize].pdf(b.point, hit.point, hit.geometric_normal);
                power_heuristic(b.pdf, light_pdf)
            }
            _ => 1.0,
        },
        _ => 1.0,
    };
    let texel = if record.emission_texture == NO_TEXTURE {
        Vec3::ONE
    } else {
        scene.texture(record.emission_texture, hit.uv * record.uv_repeat)
    };
    record.emission * texel * weight
}

/// Radiance from the environment along a ray that left the scene, MIS-weighted.
fn environment_light(scene: &RenderScene, ray: &Ray, previous: Option<Bounce>) -> Vec3 {
    let Some(env) = &scene.environment else { return scene.settings.background };
    let l = env.radiance(ray.dir);
    match (previous, &scene.light_selection) {
        (Some(b), Some(selection)) if !b.delta => {
            let light_pdf = selection.probability(scene.environment_emitter as usize) * env.pdf(ray.dir.normalize());
            l * power_heuristic(b.pdf, light_pdf)
        }
        _ => l,
    }
}

/// One light sample (next-event estimation): an emitter chosen by power, a point or
/// direction on it, a shadow ray, MIS-weighted against BSDF sampling.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn direct_light(
    scene: &RenderScene,
    hit: &Hit,
    bsdf: &SurfaceBsdf<'_>,
    frame: &Frame,
    wo: Vec3,
    (u_select, u): (f32, Vec2),
    time: f32,
    counters: &mut Counters,
) -> Vec3 {
    let Some(selection) = &scene.light_selection else { return Vec3::ZERO };
    let (index, _) = selection.sample_discrete(u_select);
    let p_select = selection.probability(index);
    let emitter = &scene.emitters[index];
    let sample = if emitter.kind == EmitterKind::Environment {
        let Some((wi, radiance, pdf)) = scene.environment.as_ref().and_then(|env| env.sample(u)) else {
            return Vec3::ZERO;
        };
        LightSample { wi, distance: f32::INFINITY, radiance, pdf, delta: false }
    } else {
        let Some(s) = emitter.sample(hit.point, u) else { return Vec3::ZERO };
        s
    };
    if (sample.pdf.is_nan() || sample.pdf <= 0.0) || sample.radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let wi = frame.to_local(sample.wi);
    if !same_side_story(hit, (frame.to_world(wo), sample.wi), (wo, wi)) {
        return Vec3::ZERO;
    }
    let f = bsdf.eval(wo, wi) * wi.z.abs();
    if f == Vec3::ZERO {
        return Vec3::ZERO;
    }
    counters.rays += 1;
    let origin = offset_ray_origin(hit.point, side_normal(hit, sample.wi));
    // Stop just short of the sampled point, which lies on the emitter itself.
    let t_max = if sample.distance.is_finite() { sample.distance * (1.0 - 1e-4) } else { f32::INFINITY };
    if scene.occluded(&Ray::new(origin, sample.wi).at_time(time), t_max) {
        return Vec3::ZERO;
    }
    let light_pdf = p_select * sample.pdf;
    let weight = if sample.delta { 1.0 } else { power_heuristic(light_pdf, bsdf.pdf(wo, wi)) };
    f * sample.radiance * (weight / light_pdf)
}

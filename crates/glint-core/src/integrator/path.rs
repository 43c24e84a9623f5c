//! Unidirectional path tracing: the rendering equation
//! `L_o(p, ω_o) = L_e(p, ω_o) + ∫ f(p, ω_o, ω_i) L_i(p, ω_i) |cos θ_i| dω_i`
//! estimated by random walks from the camera (Kajiya 1986).
//!
//! Each vertex takes one light sample (next-event estimation) and one BSDF sample; the
//! two estimate the same direct light and are combined by multiple importance sampling
//! with the power heuristic (Veach & Guibas 1995). Delta lights and delta lobes, which
//! only one strategy can find, get full weight. Depth and Russian roulette are counted
//! as Mitsuba 3's `path` integrator counts them, so `max_depth` means the same there.

mod wave;

pub use wave::{DiffuseWave, LanePath};

use glam::{Vec2, Vec3};

use super::{Counters, SurfaceId};
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
    let mut path = PathState::new(scene, ray, counters);
    while let Some(ray) = path.next_ray() {
        let hit = scene.intersect(&ray, f32::INFINITY);
        path.advance(scene, hit, sampler, counters, aov.take());
        if let Some(shadow) = path.shadow_ray() {
            let blocked = scene.occluded(&shadow.ray, shadow.t_max);
            path.resolve_shadow(blocked, counters);
        }
    }
    path.radiance()
}

/// A shadow ray a path waits on: the light it brings if nothing blocks it.
#[derive(Clone, Copy)]
pub struct ShadowRay {
    pub ray: Ray,
    /// The segment `0 < t < t_max` that must be clear.
    pub t_max: f32,
    /// Throughput times the MIS-weighted light sample: what the path gains.
    light: Vec3,
    /// The surface it leaves from, to blame should the light make the path non-finite.
    from: SurfaceId,
}

/// Where a path stands between two rays.
#[derive(Clone, Copy, PartialEq)]
enum Stage {
    /// Its next ray is `ray`, to be traced.
    Tracing,
    /// It has ended; `radiance` is its value.
    Done,
    /// A BSDF sample weighed NaN or infinity: the whole sample is void.
    Void,
}

/// A random walk from the camera between its rays: what it has gathered and what it
/// carries to the next vertex. The path asks for one closest-hit ray at a time
/// ([`PathState::next_ray`]) and, after each vertex, for at most one shadow ray
/// ([`PathState::shadow_ray`]); whoever traces them — one path alone, or a wave of
/// paths side by side — hands the answers back, and the path's value is the same
/// either way.
#[derive(Clone, Copy)]
pub struct PathState {
    radiance: Vec3,
    throughput: Vec3,
    eta: f32,
    ray: Ray,
    previous: Option<Bounce>,
    depth: u32,
    limits: PathDesc,
    shadow: Option<ShadowRay>,
    stage: Stage,
}

impl PathState {
    /// A path about to trace camera ray `ray` (already counted in `counters`).
    #[inline(always)]
    pub fn new(scene: &RenderScene, ray: &Ray, counters: &mut Counters) -> Self {
        let limits = match scene.settings.integrator {
            crate::desc::IntegratorDesc::Path(p) => p,
            crate::desc::IntegratorDesc::Whitted => PathDesc::default(),
        };
        let stage = if limits.max_depth == 0 { Stage::Done } else { Stage::Tracing };
        if stage == Stage::Tracing {
            counters.rays += 1;
        }
        PathState {
            radiance: Vec3::ZERO,
            throughput: Vec3::ONE,
            eta: 1.0,
            ray: *ray,
            previous: None,
            depth: 0,
            limits,
            shadow: None,
            stage,
        }
    }

    /// The closest-hit ray the path waits on, if it goes on (and no shadow ray is
    /// pending).
    #[inline(always)]
    pub fn next_ray(&self) -> Option<Ray> {
        (self.stage == Stage::Tracing && self.shadow.is_none()).then_some(self.ray)
    }

    /// The closest-hit ray the path traces once its pending shadow ray (if any) is
    /// resolved, if it goes on: the two may be traced together.
    #[inline(always)]
    pub fn ray_after_shadow(&self) -> Option<Ray> {
        (self.stage == Stage::Tracing).then_some(self.ray)
    }

    /// The shadow ray the path waits on, if the last vertex took a light sample.
    #[inline(always)]
    pub fn shadow_ray(&self) -> Option<&ShadowRay> {
        self.shadow.as_ref()
    }

    /// The path's radiance once it has ended (NaN for a void sample).
    #[inline(always)]
    pub fn radiance(&self) -> Vec3 {
        if self.stage == Stage::Void { Vec3::NAN } else { self.radiance }
    }

    /// Whether the path has ended and waits on nothing.
    #[inline(always)]
    pub fn is_done(&self) -> bool {
        self.stage != Stage::Tracing && self.shadow.is_none()
    }

    /// Adds the pending light sample unless its shadow ray was `blocked`.
    #[inline(always)]
    pub fn resolve_shadow(&mut self, blocked: bool, counters: &mut Counters) {
        let Some(shadow) = self.shadow.take() else { return };
        if !blocked {
            self.radiance += shadow.light;
        }
        if !self.radiance.is_finite() && self.stage != Stage::Void {
            counters.blame_surface(shadow.from);
            self.stage = Stage::Done;
        }
    }

    /// One vertex: `hit` is where [`PathState::next_ray`] ended (`None`: it left the
    /// scene). Adds the emission found there, takes a light sample (whose shadow ray
    /// the caller traces next) and a BSDF sample for the next ray.
    #[inline(always)]
    pub fn advance(
        &mut self,
        scene: &RenderScene,
        hit: Option<Hit>,
        sampler: &mut PathSampler,
        counters: &mut Counters,
        aov: Option<&mut Aov>,
    ) {
        let ray = self.ray;
        let Some(hit) = hit else {
            self.radiance += self.throughput * environment_light(scene, &ray, self.previous);
            self.stage = Stage::Done;
            return;
        };
        let wo_world = -ray.dir.normalize();
        let record = &scene.bsdfs[hit.material as usize];
        let mut bsdf = record.at(hit.uv, |i, uv| scene.texture(i, uv));
        bsdf.color *= hit.color;
        if let Some(aov) = aov {
            *aov = Aov { albedo: bsdf.albedo(), normal: hit.normal, depth: hit.t * ray.dir.length() };
        }
        // (Most surfaces emit nothing: the throughput, always finite here, would add zero.)
        if bsdf.record.is_emissive() {
            self.radiance += self.throughput * emitted(scene, &hit, &bsdf, wo_world, self.previous);
        }
        if !self.radiance.is_finite() {
            counters.blame(&hit);
            self.stage = Stage::Done;
            return;
        }

        // Mitsuba's counting: a path of max_depth vertices past the camera at most.
        if self.depth.saturating_add(1) >= self.limits.max_depth {
            self.stage = Stage::Done;
            return;
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
        if bsdf.has_non_delta()
            && let Some((shadow_ray, t_max, value)) =
                direct_light(scene, &hit, &bsdf, &frame, wo, (choices.x, u_light), ray.time, counters)
        {
            let light = self.throughput * value;
            self.shadow = Some(ShadowRay { ray: shadow_ray, t_max, light, from: SurfaceId::of(&hit) });
        }
        self.stage = Stage::Done;
        let u_lobe = choices.y;
        let Some(sample) = bsdf.sample(wo, u_lobe, u_dir) else { return };
        let wi = frame.to_world(sample.wi);
        if !same_side_story(&hit, (wo_world, wi), (wo, sample.wi)) {
            return;
        }
        self.throughput *= sample.weight;
        self.eta *= sample.eta;
        self.ray = Ray::new(offset_ray_origin(hit.point, side_normal(&hit, wi)), wi).at_time(ray.time);
        self.previous = Some(Bounce { point: hit.point, pdf: sample.pdf, delta: sample.delta });
        self.depth += 1;
        self.go_on_after_bounce(SurfaceId::of(&hit), sampler, counters);
    }

    /// After a bounce from `surface` has set the next ray and throughput: voids the sample
    /// on a non-finite throughput, ends a path that carries nothing, plays roulette,
    /// and otherwise sets the path tracing.
    #[inline(always)]
    fn go_on_after_bounce(&mut self, surface: SurfaceId, sampler: &mut PathSampler, counters: &mut Counters) {
        if !self.throughput.is_finite() {
            counters.blame_surface(surface);
            self.stage = Stage::Void;
            return;
        }
        let most = self.throughput.max_element();
        if most <= 0.0 {
            return;
        }
        // Roulette draws its number only at depths where it plays (the same depths for
        // every path, so dimensions stay aligned).
        if self.depth >= self.limits.rr_depth {
            let survive = (most * self.eta * self.eta).min(0.95);
            if sampler.next_1d() >= survive {
                return;
            }
            self.throughput /= survive;
        }
        self.stage = Stage::Tracing;
        counters.rays += 1;
    }
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
/// direction on it, MIS-weighted against BSDF sampling. Returns the shadow ray that
/// decides it (its origin, direction and segment) and the light it brings if clear.
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
) -> Option<(Ray, f32, Vec3)> {
    let (sample, p_select) = light_sample(scene, hit.point, (u_select, u))?;
    let wi = frame.to_local(sample.wi);
    if !same_side_story(hit, (frame.to_world(wo), sample.wi), (wo, wi)) {
        return None;
    }
    let f = bsdf.eval(wo, wi) * wi.z.abs();
    if f == Vec3::ZERO {
        return None;
    }
    counters.rays += 1;
    let origin = offset_ray_origin(hit.point, side_normal(hit, sample.wi));
    // Stop just short of the sampled point, which lies on the emitter itself.
    let t_max = if sample.distance.is_finite() { sample.distance * (1.0 - 1e-4) } else { f32::INFINITY };
    let light_pdf = p_select * sample.pdf;
    let weight = if sample.delta { 1.0 } else { power_heuristic(light_pdf, bsdf.pdf(wo, wi)) };
    Some((Ray::new(origin, sample.wi).at_time(time), t_max, f * sample.radiance * (weight / light_pdf)))
}

/// An emitter chosen by power with `u_select` and a sample of it from `point` placed by
/// `u`, with the probability of the choice; `None` when the sample carries nothing.
#[inline(always)]
fn light_sample(scene: &RenderScene, point: Vec3, (u_select, u): (f32, Vec2)) -> Option<(LightSample, f32)> {
    let selection = scene.light_selection.as_ref()?;
    let (index, _) = selection.sample_discrete(u_select);
    let p_select = selection.probability(index);
    let emitter = &scene.emitters[index];
    let sample = if emitter.kind == EmitterKind::Environment {
        let (wi, radiance, pdf) = scene.environment.as_ref().and_then(|env| env.sample(u))?;
        LightSample { wi, distance: f32::INFINITY, radiance, pdf, delta: false }
    } else {
        emitter.sample(point, u)?
    };
    if (sample.pdf.is_nan() || sample.pdf <= 0.0) || sample.radiance == Vec3::ZERO {
        return None;
    }
    Some((sample, p_select))
}

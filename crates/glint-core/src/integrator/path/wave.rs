//! Diffuse vertices of a wave of paths, shaded side by side.
//!
//! In a wave ([`crate::render`]'s waves of eight paths) most rays end on plain diffuse
//! surfaces. Shading such a vertex one path at a time is a chain of dependent square
//! roots and divisions (normalizing, the light's density, the MIS weight, the disk map
//! of the cosine lobe), each waiting on the last; eight of them side by side in vector
//! lanes cost about what one does. [`DiffuseWave`] does for those vertices what
//! [`PathState::advance`] does — the same operations in the same order on
//! [`crate::math::wide`]'s lanes, so each path takes the very values it would alone —
//! while what is per path by nature (its sampler, the choice of light, roulette, the
//! bookkeeping) stays per path.

// Lane loops index several arrays by the same lane: written so, they vectorize.
#![allow(clippy::needless_range_loop)]

use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

use super::{Bounce, PathState, ShadowRay, Stage, light_sample, power_heuristic};
use crate::bsdf::{BsdfKind, TWO_SIDED, lobes};
use crate::integrator::{Counters, SurfaceId};
use crate::material::NO_TEXTURE;
use crate::math::wide::{F8, M8, V8, WIDTH};
use crate::math::{Ray, offset_ray_origins};
use crate::sampling::PathSampler;
use crate::scene::RenderScene;

impl PathState {
    /// Whether a [`DiffuseWave`] can take the vertex where the path's ray met a surface
    /// of `material`: plain diffuse (untextured colour, no emission), and not the
    /// vertex the path ends on for its depth.
    #[inline(always)]
    pub fn shades_in_wave(&self, scene: &RenderScene, material: u32) -> bool {
        let record = &scene.bsdfs[material as usize];
        record.kind == BsdfKind::Diffuse
            && record.color_texture == NO_TEXTURE
            && !record.is_emissive()
            && self.radiance.is_finite()
            && self.depth.saturating_add(1) < self.limits.max_depth
    }
}

/// The diffuse vertices of a wave, gathered into lanes as their hits come in: lane
/// `k` holds the values of the path in the wave's lane `k`, or zeros where it has no
/// diffuse vertex (whose results are never read).
#[derive(Default)]
pub struct DiffuseWave {
    active: M8,
    /// The surface of each vertex, to blame for a non-finite value.
    surface: [SurfaceId; WIDTH],
    point: V8,
    /// The unit normal: the true surface's and the shading one (analytic surfaces).
    normal: V8,
    dir: V8,
    color: V8,
    two_sided: M8,
    throughput: V8,
    u_dir: [Vec2; WIDTH],
    /// The light sample: where it is valid, its direction, distance, radiance, density
    /// (times the probability of choosing its emitter) and whether it is a delta.
    has_light: M8,
    light_wi: V8,
    light_distance: F8,
    light_radiance: V8,
    light_pdf: F8,
    light_delta: M8,
}

impl DiffuseWave {
    /// Takes into lane `k` `path`'s vertex on `surface` (see
    /// [`PathState::shades_in_wave`]) at `point`, whose unit normal is `normal` (the
    /// true and the shading normal: analytic surfaces), drawing from `sampler` what the
    /// vertex draws before roulette: the choice of light, the light sample's place, the
    /// BSDF direction.
    #[inline(always)]
    pub fn add(
        &mut self,
        scene: &RenderScene,
        k: usize,
        path: &PathState,
        sampler: &mut PathSampler,
        (surface, point, normal): (SurfaceId, Vec3, Vec3),
    ) {
        let all = u32::MAX;
        let record = &scene.bsdfs[surface.material as usize];
        self.active.0[k] = all;
        self.surface[k] = surface;
        self.point.set(k, point);
        self.normal.set(k, normal);
        self.dir.set(k, path.ray.dir);
        // (The vertex colour of analytic surfaces is white: it would multiply by one.)
        self.color.set(k, record.color);
        self.two_sided.0[k] = if record.flags & TWO_SIDED != 0 { all } else { 0 };
        self.throughput.set(k, path.throughput);
        let choices = sampler.next_2d();
        let u_light = sampler.next_2d();
        self.u_dir[k] = sampler.next_2d();
        if let Some((sample, p_select)) = light_sample(scene, point, (choices.x, u_light)) {
            self.has_light.0[k] = all;
            self.light_wi.set(k, sample.wi);
            self.light_distance.0[k] = sample.distance;
            self.light_radiance.set(k, sample.radiance);
            self.light_pdf.0[k] = p_select * sample.pdf;
            self.light_delta.0[k] = if sample.delta { all } else { 0 };
        }
    }

    /// Whether no lane holds a vertex.
    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.active == M8::default()
    }

    /// Whether lane `k` holds a vertex.
    #[inline(always)]
    pub fn has(&self, k: usize) -> bool {
        self.active.get(k)
    }

    /// Shades every lane, then hands each path its results: what
    /// [`PathState::advance`] does for each alone. `lanes` yields the wave's lanes in
    /// order, each with its path or `None`.
    #[inline(always)]
    pub fn advance<'a>(&self, lanes: impl Iterator<Item = Option<LanePath<'a>>>) {
        let shaded = shade(self);
        for (k, lane) in lanes.enumerate().take(WIDTH) {
            if self.has(k)
                && let Some(lane) = lane
            {
                finish(lane, &shaded, self, k);
            }
        }
    }
}

/// What a lane's path hands the wave to take its results.
pub struct LanePath<'a> {
    pub path: &'a mut PathState,
    pub sampler: &'a mut PathSampler,
    pub counters: &'a mut Counters,
}

/// What the lanes computed: the shadow ray and its light, the next ray and its
/// weight, and which lanes have each.
struct Shaded {
    has_shadow: M8,
    shadow_origin: V8,
    shadow_dir: V8,
    shadow_t_max: F8,
    shadow_light: V8,
    goes_on: M8,
    next_origin: V8,
    next_dir: V8,
    next_pdf: F8,
    throughput: V8,
}

/// The shading frame: z along the unit normal `n` (glam's `any_orthonormal_pair`,
/// as [`super::Frame`] builds it).
#[derive(Clone, Copy)]
struct Frame8 {
    s: V8,
    t: V8,
    n: V8,
}

impl Frame8 {
    #[inline(always)]
    fn new(n: V8) -> Self {
        let one = F8::splat(1.0);
        let sign = n.z.map(f32::signum);
        let a = F8::splat(-1.0) / (sign + n.z);
        let b = n.x * n.y * a;
        let s = V8::new(one + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = V8::new(b, sign + n.y * n.y * a, -n.y);
        Frame8 { s, t, n }
    }

    #[inline(always)]
    fn to_local(self, v: V8) -> V8 {
        V8::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    #[inline(always)]
    fn to_world(self, v: V8) -> V8 {
        self.s.scale(v.x) + self.t.scale(v.y) + self.n.scale(v.z)
    }
}

/// `path.rs`'s `same_side_story` in lanes.
#[inline(always)]
fn same_side_story(ng: V8, (wo_world, wi_world): (V8, V8), (wo, wi): (V8, V8)) -> M8 {
    let zero = F8::splat(0.0);
    let local = (wo.z * wi.z).is_gt(zero);
    let true_surface = (ng.dot(wo_world) * ng.dot(wi_world)).is_gt(zero);
    // Equal masks: both set or both clear.
    M8(std::array::from_fn(|k| !(local.0[k] ^ true_surface.0[k])))
}

/// `path.rs`'s `side_normal` in lanes: the geometric normal on `w`'s side.
#[inline(always)]
fn side_normal(ng: V8, w: V8) -> V8 {
    ng.dot(w).test(F8::splat(0.0), |a, b| a >= b).select3(ng, -ng)
}

/// The lanes' part of [`PathState::advance`] for a diffuse vertex.
#[inline(always)]
fn shade(g: &DiffuseWave) -> Shaded {
    let (zero, one) = (F8::splat(0.0), F8::splat(1.0));
    let wo_world = -g.dir.normalize();
    let frame = Frame8::new(g.normal);
    let wo = frame.to_local(wo_world);
    // The true surface's normal, for the sides of rays (the shading normal here).
    let ng = g.normal;
    // The side the surface reflects on: the front, or the back of a two-sided one.
    let front = wo.z.is_gt(zero);
    let reflects = front.or(wo.z.is_lt(zero).and(g.two_sided));
    let side = front.select(one, -one);
    let lambert = g.color.scale(F8::splat(FRAC_1_PI));

    // The light sample: f·|cos θ|, MIS-weighted against the BSDF's density.
    let wi = frame.to_local(g.light_wi);
    let agrees = same_side_story(ng, (frame.to_world(wo), g.light_wi), (wo, wi));
    let lit = reflects.and_not((wi.z * side).is_le(zero));
    let f = lit.select3(lambert, V8::default()).scale(wi.z.abs());
    let black = f.x.is_eq(zero).and(f.y.is_eq(zero)).and(f.z.is_eq(zero));
    let has_shadow = g.active.and(g.has_light).and(agrees).and_not(black);
    let shadow_origin = offset_ray_origins(g.point, side_normal(ng, g.light_wi));
    let distance = g.light_distance;
    let finite = distance.is_finite();
    let shadow_t_max = finite.select(distance * F8::splat(1.0 - 1e-4), F8::splat(f32::INFINITY));
    let z = wi.z * side;
    let bsdf_pdf = lit.select(z.max(zero) * F8::splat(FRAC_1_PI), zero);
    let mis = g.light_pdf.zip(bsdf_pdf, power_heuristic);
    let weight = g.light_delta.select(one, mis);
    let value = (f * g.light_radiance).scale(weight / g.light_pdf);
    let shadow_light = g.throughput * value;

    // The BSDF sample: a cosine-weighted direction on the reflecting side.
    let d = cosine_hemisphere(&g.u_dir);
    let drawn = d.z.is_gt(zero);
    let next_pdf = d.z.max(zero) * F8::splat(FRAC_1_PI);
    let wi = V8::new(d.x, d.y, d.z * side);
    let next_dir = frame.to_world(wi);
    let agrees = same_side_story(ng, (wo_world, next_dir), (wo, wi));
    let goes_on = g.active.and(reflects).and(drawn).and(agrees);
    let next_origin = offset_ray_origins(g.point, side_normal(ng, next_dir));
    Shaded {
        has_shadow,
        shadow_origin,
        shadow_dir: g.light_wi,
        shadow_t_max,
        shadow_light,
        goes_on,
        next_origin,
        next_dir,
        next_pdf,
        throughput: g.throughput * g.color,
    }
}

/// `lobes::cosine_hemisphere` in lanes: Malley's method over the concentric disk.
#[inline(always)]
fn cosine_hemisphere(u: &[Vec2; WIDTH]) -> V8 {
    let (mut dx, mut dy) = (F8::default(), F8::default());
    for k in 0..WIDTH {
        dx.0[k] = 2.0 * u[k].x - 1.0;
        dy.0[k] = 2.0 * u[k].y - 1.0;
    }
    let zero = F8::splat(0.0);
    let centre = dx.is_eq(zero).and(dy.is_eq(zero));
    let near_x = dx.abs().is_gt(dy.abs());
    let q = near_x.select(dy / dx, dx / dy);
    let (mut sin, mut cos) = (F8::default(), F8::default());
    for k in 0..WIDTH {
        (sin.0[k], cos.0[k]) = lobes::sin_cos_quarter_pi(q.0[k]);
    }
    let radius = near_x.select(dx, dy);
    let x = centre.select(zero, near_x.select(radius * cos, radius * sin));
    let y = centre.select(zero, near_x.select(radius * sin, radius * cos));
    let z = (F8::splat(1.0) - (x * x + y * y)).max(zero).sqrt();
    V8::new(x, y, z)
}

/// Lane `k`'s results written back to its path, and what stays per path: counting
/// rays, blaming a non-finite throughput, roulette.
#[inline(always)]
fn finish(lane: LanePath, shaded: &Shaded, wave: &DiffuseWave, k: usize) {
    let path = lane.path;
    let time = path.ray.time;
    if shaded.has_shadow.get(k) {
        lane.counters.rays += 1;
        path.shadow = Some(ShadowRay {
            ray: Ray::new(shaded.shadow_origin.get(k), shaded.shadow_dir.get(k)).at_time(time),
            t_max: shaded.shadow_t_max.0[k],
            light: shaded.shadow_light.get(k),
            from: wave.surface[k],
        });
    }
    path.stage = Stage::Done;
    if !shaded.goes_on.get(k) {
        return;
    }
    path.throughput = shaded.throughput.get(k);
    path.ray = Ray::new(shaded.next_origin.get(k), shaded.next_dir.get(k)).at_time(time);
    path.previous = Some(Bounce { point: wave.point.get(k), pdf: shaded.next_pdf.0[k], delta: false });
    path.depth += 1;
    path.go_on_after_bounce(wave.surface[k], lane.sampler, lane.counters);
}

//! The lecture's recursive lighting equation (Whitted, 1980):
//!
//! `I = L_a·k_a·O_a + Σ_lights f_att·L·[k_d·O_d·(n·l) + k_s·O_s·(r·v)^n] + k_s·O_r·I_r + k_t·O_t·I_t`
//!
//! A light counts only if a shadow ray reaches it; transparent occluders filter it by
//! their `k_t·O_t`. Reflected and transmitted rays recurse until `max_depth` or until
//! their weight in the pixel falls below `min_contribution`.

use glam::Vec3;

use glam::Vec2;

use super::TraceContext;
use super::observe::{NoObserver, Observer, RayKind};
use crate::material::{Material, NO_TEXTURE};
use crate::math::{Ray, all_finite, offset_ray_origin};
use crate::scene::{Hit, RenderScene};

/// Radiance arriving along `ray`. `weight` is the product of the `k·O` factors that
/// lead from the pixel to this ray, used only to stop negligible recursion.
pub fn radiance(scene: &RenderScene, ray: &Ray, depth: u32, weight: Vec3, ctx: &mut TraceContext) -> Vec3 {
    shade(scene, ray, scene.intersect(ray, f32::INFINITY), depth, weight, ctx)
}

/// [`radiance`] for a camera ray, telling `observer` every ray of its tree and every
/// term of the lighting equation (to explain a pixel).
pub fn radiance_observed(scene: &RenderScene, ray: &Ray, ctx: &mut TraceContext, observer: &mut impl Observer) -> Vec3 {
    let hit = scene.intersect(ray, f32::INFINITY);
    shade_observed(scene, (ray, RayKind::Camera), hit, 0, Vec3::ONE, ctx, observer)
}

/// [`radiance`] along `ray` whose closest hit is already known: camera rays are
/// intersected in packets ([`RenderScene::intersect_packet`]) and shaded one by one.
pub fn shade(
    scene: &RenderScene,
    ray: &Ray,
    hit: Option<Hit>,
    depth: u32,
    weight: Vec3,
    ctx: &mut TraceContext,
) -> Vec3 {
    crate::accel::lanes::on_avx2_or!(
        |_avx| shade_avx2(scene, ray, hit, depth, weight, ctx),
        shade_observed(scene, (ray, RayKind::Camera), hit, depth, weight, ctx, &mut NoObserver)
    )
}

/// [`shade`] compiled for AVX2, its reflected and refracted rays shaded by itself again,
/// so the whole recursion runs as AVX2 code: VEX encoding and wider registers take
/// instructions off, and the results stay bit-identical (no multiply-add is fused).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn shade_avx2(
    scene: &RenderScene,
    ray: &Ray,
    hit: Option<Hit>,
    depth: u32,
    weight: Vec3,
    ctx: &mut TraceContext,
) -> Vec3 {
    // A closure inherits the AVX2 of the function it is written in.
    let again = |scene: &RenderScene,
                 (ray, _): (&Ray, RayKind),
                 hit,
                 depth,
                 weight,
                 ctx: &mut TraceContext,
                 _: &mut NoObserver| { shade_avx2(scene, ray, hit, depth, weight, ctx) };
    shade_with(scene, (ray, RayKind::Camera), hit, depth, weight, ctx, &mut NoObserver, &again)
}

/// [`shade`] telling `observer` what it does; with [`NoObserver`] the calls compile away.
fn shade_observed<O: Observer>(
    scene: &RenderScene,
    (ray, kind): (&Ray, RayKind),
    hit: Option<Hit>,
    depth: u32,
    weight: Vec3,
    ctx: &mut TraceContext,
    observer: &mut O,
) -> Vec3 {
    shade_with(scene, (ray, kind), hit, depth, weight, ctx, observer, &shade_observed::<O>)
}

/// The lighting equation at `ray`'s hit: the body of [`shade_observed`] and
/// [`shade_avx2`], inlined into each, whose secondary rays it shades with `again`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn shade_with<O: Observer>(
    scene: &RenderScene,
    (ray, kind): (&Ray, RayKind),
    hit: Option<Hit>,
    depth: u32,
    weight: Vec3,
    ctx: &mut TraceContext,
    observer: &mut O,
    again: &impl Fn(&RenderScene, (&Ray, RayKind), Option<Hit>, u32, Vec3, &mut TraceContext, &mut O) -> Vec3,
) -> Vec3 {
    ctx.counters.rays += 1;
    observer.ray(ray, kind, depth, hit.as_ref());
    let Some(hit) = hit else {
        let background = scene.background(ray.dir);
        observer.done(background);
        return background;
    };
    let facing = Facing::of(ray, &hit);
    let mut color = shade_vertex(scene, (ray, &hit, &facing), ctx, &mut TracedNow, observer);
    for_each_secondary(scene, (ray, &hit, &facing), depth, weight, |r, kind, k, weight| {
        let hit = scene.intersect(&r, f32::INFINITY);
        let term = k * again(scene, (&r, kind), hit, depth + 1, weight, ctx, observer);
        observer.term(kind.term_formula(), term);
        color += term;
    });
    observer.done(color);
    blamed_if_non_finite(color, &hit, ctx)
}

/// The local part of the lighting equation at `hit` (ambient and every light) for a
/// ray `ray` that found it, seen as `facing` says, its shadow rays handled by `shadows`.
#[inline(always)]
pub fn shade_vertex(
    scene: &RenderScene,
    (ray, hit, facing): (&Ray, &Hit, &Facing),
    ctx: &mut TraceContext,
    shadows: &mut impl ShadowRays,
    observer: &mut impl Observer,
) -> Vec3 {
    let material = &scene.materials[hit.material as usize];
    direct_lighting(scene, hit, material, (facing.n, -facing.d), ray.time, ctx, shadows, observer)
}

/// How a ray meets its hit: its unit direction, and the hit's shading and true normals
/// turned to face it (the side the ray arrived on is the side shaded). The true surface
/// decides the side and carries the ray offsets; an interpolated mesh normal may lean.
/// Found once per hit, for both its lighting and its secondary rays.
#[derive(Clone, Copy)]
pub struct Facing {
    d: Vec3,
    n: Vec3,
    ng: Vec3,
    entering: bool,
}

impl Facing {
    /// How `ray` meets `hit`.
    #[inline(always)]
    pub fn of(ray: &Ray, hit: &Hit) -> Facing {
        let d = ray.dir.normalize();
        let entering = hit.geometric_normal.dot(d) < 0.0;
        let (n, ng) = if entering { (hit.normal, hit.geometric_normal) } else { (-hit.normal, -hit.geometric_normal) };
        Facing { d, n, ng, entering }
    }
}

/// Calls `spawn(ray, kind, k, weight)` for the reflected and transmitted rays of the
/// ray `ray` that found `hit` (meeting it as `facing` says) at `depth` with `weight`, where they are worth tracing:
/// each adds `k` times what it brings back, and carries `weight · k` on.
#[inline(always)]
pub fn for_each_secondary(
    scene: &RenderScene,
    (ray, hit, facing): (&Ray, &Hit, &Facing),
    depth: u32,
    weight: Vec3,
    mut spawn: impl FnMut(Ray, RayKind, Vec3, Vec3),
) {
    if depth >= scene.settings.max_depth {
        return;
    }
    let material = &scene.materials[hit.material as usize];
    let Facing { d, n, ng, entering } = *facing;
    let worth_tracing = |w: Vec3| w.max_element() > scene.settings.min_contribution;
    let reflected_dir = reflect(d, n);
    let features = scene.settings.features;
    let reflect_weight = weight * material.reflective;
    if features.reflections && worth_tracing(reflect_weight) {
        let r = Ray::new(offset_ray_origin(hit.point, ng), reflected_dir).at_time(ray.time);
        spawn(r, RayKind::Reflected, material.reflective, reflect_weight);
    }
    let transmit_weight = weight * material.transmissive;
    if features.refractions && worth_tracing(transmit_weight) {
        let eta = if entering { 1.0 / material.ior } else { material.ior };
        let transmitted = if material.ior == 1.0 { Some(d) } else { refract(d, n, eta) };
        let (r, kind) = match transmitted {
            Some(t) => (Ray::new(offset_ray_origin(hit.point, -ng), t).at_time(ray.time), RayKind::Refracted),
            // Total internal reflection: the transmitted share is reflected instead.
            None => (
                Ray::new(offset_ray_origin(hit.point, ng), reflected_dir).at_time(ray.time),
                RayKind::TotalInternalReflection,
            ),
        };
        spawn(r, kind, material.transmissive, transmit_weight);
    }
}

/// How direct lighting learns what reaches a light: a shadow ray traced at once, or
/// put aside to be traced with others (a wave of rays) and its light added then.
pub trait ShadowRays {
    /// The filter (`k_t·O_t` of what the segment `0 < t < t_max` of `ray` crosses, zero
    /// if it is blocked), or `None` if the ray is put aside: [`ShadowRays::defer`]
    /// then takes the light it would add unshadowed. Adds to `rays` the rays traced
    /// past transparent surfaces after `ray` itself.
    fn filter(&mut self, scene: &RenderScene, ray: &Ray, t_max: f32, rays: &mut u64) -> Option<Vec3>;

    /// Keeps `light`, what the shadow ray last put aside adds times its filter.
    fn defer(&mut self, ray: &Ray, t_max: f32, light: Vec3);

    /// The scene's light `light_index` as seen from `p` ([`Light::sample`]), which a
    /// caller may have worked out beforehand.
    #[inline(always)]
    fn incidence(
        &mut self,
        _light_index: usize,
        light: &crate::light::Light,
        p: Vec3,
        index: u32,
        jitter: Vec2,
    ) -> crate::light::Incidence {
        light.sample(p, index, jitter)
    }
}

/// Shadow rays traced as they come, one by one.
pub struct TracedNow;

impl ShadowRays for TracedNow {
    #[inline(always)]
    fn filter(&mut self, scene: &RenderScene, ray: &Ray, t_max: f32, rays: &mut u64) -> Option<Vec3> {
        Some(if scene.settings.features.transparent_shadows {
            let (filter, crossed) = scene.transmittance_counted(ray, t_max);
            *rays += u64::from(crossed);
            filter
        } else if scene.occluded(ray, t_max) {
            Vec3::ZERO
        } else {
            Vec3::ONE
        })
    }

    fn defer(&mut self, _: &Ray, _: f32, _: Vec3) {
        unreachable!("shadow rays traced now are never put aside")
    }
}

/// `color`, after noting `hit` as the culprit if it is not finite. Rays return from the
/// deepest first, so the first surface noted is where the fault arose.
#[inline]
fn blamed_if_non_finite(color: Vec3, hit: &Hit, ctx: &mut TraceContext) -> Vec3 {
    if !all_finite(color) {
        ctx.counters.blame(hit);
    }
    color
}

/// The non-recursive part: ambient plus every unshadowed light's diffuse and specular.
/// `n` faces the viewer and `v` points to it; shadow rays travel at `time`. Inlined, so
/// the AVX2 shading compiles it for AVX2 too.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn direct_lighting(
    scene: &RenderScene,
    hit: &Hit,
    m: &Material,
    (n, v): (Vec3, Vec3),
    time: f32,
    ctx: &mut TraceContext,
    shadows: &mut impl ShadowRays,
    observer: &mut impl Observer,
) -> Vec3 {
    let features = scene.settings.features;
    let texel = (features.textures && m.texture != NO_TEXTURE)
        .then(|| scene.texture_at_hit(m.texture, hit, m.texture_repeat, time, ctx.footprint_scale));
    // Vertex colours tint the object's own colours (ambient and diffuse), not highlights.
    let diffuse = m.diffuse_with(texel) * hit.color;
    let mut color = scene.settings.ambient_light * m.ambient_with(texel) * hit.color;
    observer.term(m.ambient_formula(texel), color);
    // Seen from outside, a smooth mesh's shadow rays start on the surface its normals
    // describe (Hanika 2021), which removes the jagged self-shadow at the terminator.
    let outside = hit.geometric_normal.dot(n) >= 0.0;
    let ng = if outside { hit.geometric_normal } else { -hit.geometric_normal };
    let shadow_origin = offset_ray_origin(if outside { hit.shadow_point } else { hit.point }, ng);
    for (light_index, light) in scene.lights.iter().enumerate() {
        // An area light is the sum of its stratified samples; the others have one.
        for index in 0..light.sample_count() {
            // Point-like lights ignore the jitter: skipping it leaves an area light
            // listed after them the numbers it always drew.
            let jitter = if !light.is_point_like() {
                Vec2::new(ctx.rng.next_f32(), ctx.rng.next_f32())
            } else {
                ctx.rng.skip(2);
                Vec2::ZERO
            };
            let incidence = shadows.incidence(light_index, light, hit.point, index, jitter);
            let n_dot_l = n.dot(incidence.to_light);
            if n_dot_l <= 0.0 || incidence.radiance == Vec3::ZERO {
                continue;
            }
            let highlight = || if m.specular == Vec3::ZERO { 0.0 } else { m.highlight(n, incidence.to_light, v) };
            let filter = if features.shadows {
                ctx.counters.rays += 1;
                let shadow_ray = Ray::new(shadow_origin, incidence.to_light).at_time(time);
                let Some(filter) = shadows.filter(scene, &shadow_ray, incidence.distance, &mut ctx.counters.rays)
                else {
                    let light = incidence.radiance * (diffuse * n_dot_l + m.specular * highlight());
                    shadows.defer(&shadow_ray, incidence.distance, light);
                    continue;
                };
                observer.shadow_ray(&shadow_ray, incidence.distance, filter);
                filter
            } else {
                Vec3::ONE
            };
            if filter == Vec3::ZERO {
                continue;
            }
            let highlight = highlight();
            let lit = filter * incidence.radiance;
            observer.light(light_index, lit * diffuse * n_dot_l, lit * m.specular * highlight, m.specular_formula());
            color += lit * (diffuse * n_dot_l + m.specular * highlight);
        }
    }
    color
}

/// Mirror direction of `d` about the unit normal `n`: `d − 2(d·n)n`.
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Snell's law `η₁ sin θ₁ = η₂ sin θ₂` for unit `d` arriving against unit `n`
/// (`d·n < 0`), with `eta = η₁/η₂`. `None` past the critical angle: total internal
/// reflection.
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(eta * d + (eta * cos_i - cos_t) * n)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn incident(theta: f64) -> Vec3 {
        // In the xy plane, arriving downward onto the surface with normal +y.
        Vec3::new(theta.sin() as f32, -(theta.cos() as f32), 0.0)
    }

    #[test]
    fn refraction_obeys_snell() {
        for deg in [0.0f64, 10.0, 30.0, 60.0, 89.0] {
            let d = incident(deg.to_radians());
            let t = refract(d, Vec3::Y, 1.0 / 1.5).unwrap();
            assert!((t.length() - 1.0).abs() < 1e-5);
            let sin_t = t.x as f64;
            assert!((1.0 * deg.to_radians().sin() - 1.5 * sin_t).abs() < 1e-5, "{deg}°");
            assert!(t.y < 0.0, "transmitted ray continues through the surface");
        }
    }

    #[test]
    fn total_internal_reflection_begins_exactly_at_the_critical_angle() {
        // Leaving glass (η = 1.5) into air: θc = asin(1/1.5).
        let critical = (1.0f64 / 1.5).asin();
        let eta = 1.5;
        let below = refract(incident(critical - 1e-4), Vec3::Y, eta).expect("refracts below θc");
        assert!(below.x > 0.999, "grazing exit just below θc: {below:?}");
        assert!(refract(incident(critical + 1e-4), Vec3::Y, eta).is_none());
        // Approaching θc the refracted ray turns to run along the surface (cos θt → 0,
        // as √(2·η·cos θc·δ) for θ = θc − δ). At θc itself rounding decides whether
        // sin²θt lands above 1, so the test does not look there.
        let nearer = refract(incident(critical - 1e-6), Vec3::Y, eta).expect("refracts a hair below θc");
        assert!(nearer.y < 0.0 && nearer.y.abs() < 3e-3, "{nearer:?}");
        assert!(nearer.y.abs() < below.y.abs(), "{nearer:?} is no closer to the surface than {below:?}");
    }

    #[test]
    fn reflection_angle_equals_incidence() {
        let d = incident(0.7);
        let r = reflect(d, Vec3::Y);
        assert!((r - Vec3::new(d.x, -d.y, 0.0)).length() < 1e-6);
    }
}

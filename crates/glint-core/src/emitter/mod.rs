//! Emitters for the path tracer: every source of light as one flat record, sampled by
//! next-event estimation and looked up when a BSDF-sampled ray happens to hit it.
//!
//! Area emission lives on geometry (a material with `emission`): mesh triangles, the
//! faces of cubes and rectangles, disks (ellipses under any affine transform) and
//! spheres under similarity transforms are sampled directly; other emissive shapes
//! (and moving ones) are still found by BSDF sampling, which alone is unbiased for them.
//! Point, spot and directional lights are deltas; the environment is importance-sampled
//! by [`environment::Environment`]. Which emitter a sample uses is chosen in proportion
//! to its power.

pub mod environment;
mod geometry;
#[cfg(test)]
mod tests;

use bytemuck::NoUninit;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

use crate::bsdf::lobes::concentric_disk;
use crate::desc::LightDesc;
pub use environment::Environment;
pub use geometry::emitters_of_instances;

/// Marks an instance without sampled emitters.
pub const NO_EMITTER: u32 = u32::MAX;

/// What an [`Emitter`] record is.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum EmitterKind {
    /// `p + b1·e1 + b2·e2`, b1 + b2 ≤ 1.
    Triangle = 0,
    /// `p + u·e1 + v·e2`, u, v ∈ [0, 1].
    Parallelogram = 1,
    /// The ellipse `p + x·e1 + y·e2`, x² + y² ≤ 1.
    Disk = 2,
    /// Centre `p`, radius `size`.
    Sphere = 3,
    /// Position `p`, intensity `radiance`.
    Point = 4,
    /// A point light whose intensity falls off from axis `e1` between `cos_inner` and
    /// `cos_outer`.
    Spot = 5,
    /// Parallel light travelling along `e1`, irradiance `radiance`.
    Directional = 6,
    /// The scene's [`Environment`].
    Environment = 7,
}

/// A light source as flat data.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Emitter {
    pub kind: EmitterKind,
    pub p: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
    /// Unit normal of the emitting side of planar emitters.
    pub normal: Vec3,
    /// Emitted radiance (area), intensity (point, spot) or irradiance (directional).
    pub radiance: Vec3,
    /// Area of planar emitters; radius of spheres.
    pub size: f32,
    /// Point and spot: `(c1, c2, c3)` of the falloff `1/(c1 + c2·d + c3·d²)`; `(0, 0, 1)`
    /// is the physical inverse square.
    pub attenuation: Vec3,
    pub cos_inner: f32,
    pub cos_outer: f32,
    /// Area emitters: 1 when both sides emit (a two-sided material), else 0.
    pub two_sided: u32,
    /// Spot lights: 1 when the penumbra fades linearly in angle (Mitsuba's), else 0.
    pub linear_falloff: u32,
}

/// A direction toward an emitter, chosen from a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light.
    pub wi: Vec3,
    /// Distance to the sampled point (infinite for directional and environment light).
    pub distance: f32,
    /// Radiance arriving along `wi` before shadowing (for deltas: the irradiance-like
    /// quantity whose product with `f·cos` is the contribution).
    pub radiance: Vec3,
    /// Solid-angle density of `wi` given this emitter (1 for deltas).
    pub pdf: f32,
    pub delta: bool,
}

impl Emitter {
    fn empty(kind: EmitterKind) -> Self {
        Self {
            kind,
            p: Vec3::ZERO,
            e1: Vec3::ZERO,
            e2: Vec3::ZERO,
            normal: Vec3::ZERO,
            radiance: Vec3::ZERO,
            size: 0.0,
            attenuation: Vec3::new(0.0, 0.0, 1.0),
            cos_inner: 1.0,
            cos_outer: 1.0,
            two_sided: 0,
            linear_falloff: 0,
        }
    }

    /// The cosine at the emitter between its emitting side and the direction `-wi`
    /// back to the shading point (≤ 0: that side does not emit).
    #[inline]
    fn emitting_cos(&self, normal: Vec3, wi: Vec3) -> f32 {
        let c = -normal.dot(wi);
        if self.two_sided != 0 { c.abs() } else { c }
    }

    /// The record of a point, spot or directional light; `None` for area lights (the
    /// Whitted model's light shapes: the path tracer wants emissive geometry) and the
    /// environment (compiled on its own).
    pub fn from_light(desc: &LightDesc) -> Option<Self> {
        Some(match *desc {
            LightDesc::Point { position, color, attenuation } => {
                Self { p: position, radiance: color, attenuation, ..Self::empty(EmitterKind::Point) }
            }
            LightDesc::Spot { position, direction, color, attenuation, angle_degrees, penumbra_degrees, falloff } => {
                let outer = angle_degrees.to_radians();
                let inner = (outer - penumbra_degrees.to_radians()).max(0.0);
                Self {
                    p: position,
                    e1: direction.normalize(),
                    radiance: color,
                    attenuation,
                    cos_inner: inner.cos(),
                    cos_outer: outer.cos(),
                    linear_falloff: (falloff == crate::desc::SpotFalloff::Linear) as u32,
                    ..Self::empty(EmitterKind::Spot)
                }
            }
            LightDesc::Directional { direction, color } => {
                Self { e1: direction.normalize(), radiance: color, ..Self::empty(EmitterKind::Directional) }
            }
            LightDesc::Area { .. } | LightDesc::Environment(_) => return None,
        })
    }

    /// Whether light comes from a single point or direction (no MIS possible).
    pub fn is_delta(&self) -> bool {
        matches!(self.kind, EmitterKind::Point | EmitterKind::Spot | EmitterKind::Directional)
    }

    /// Emitted power (luminance), for choosing lights in proportion to it. Directional
    /// and environment light is counted over a disk of the scene's `radius`.
    pub fn power(&self, radius: f32, environment: Option<&Environment>) -> f32 {
        let lum = luminance(self.radiance);
        match self.kind {
            EmitterKind::Triangle | EmitterKind::Parallelogram | EmitterKind::Disk => PI * self.size * lum,
            EmitterKind::Sphere => PI * 4.0 * PI * self.size * self.size * lum,
            EmitterKind::Point => 4.0 * PI * lum,
            EmitterKind::Spot => 2.0 * PI * (1.0 - 0.5 * (self.cos_inner + self.cos_outer)) * lum,
            EmitterKind::Directional => PI * radius * radius * lum,
            EmitterKind::Environment => environment.map_or(0.0, |e| PI * radius * radius * e.power()),
        }
    }

    /// Area emitters: the point for `u`, and the density of choosing it per unit area.
    #[inline(always)]
    fn sample_area(&self, u: Vec2) -> (Vec3, f32) {
        match self.kind {
            EmitterKind::Triangle => {
                // Uniform barycentrics by the square-root warp.
                let s = u.x.sqrt();
                (self.p + (1.0 - s) * self.e1 + (s * u.y) * self.e2, 1.0 / self.size)
            }
            EmitterKind::Parallelogram => (self.p + u.x * self.e1 + u.y * self.e2, 1.0 / self.size),
            _ => {
                let d = concentric_disk(u);
                (self.p + d.x * self.e1 + d.y * self.e2, 1.0 / self.size)
            }
        }
    }

    /// A direction from `p` toward this emitter (not the environment: see
    /// [`Environment::sample`]).
    #[inline(always)]
    pub fn sample(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        match self.kind {
            EmitterKind::Point | EmitterKind::Spot => {
                let offset = self.p - p;
                let distance = offset.length();
                let wi = offset / distance;
                let falloff = if self.kind == EmitterKind::Spot { self.spot_falloff(-wi) } else { 1.0 };
                let radiance = self.radiance * (falloff * self.attenuate(distance));
                Some(LightSample { wi, distance, radiance, pdf: 1.0, delta: true })
            }
            EmitterKind::Directional => Some(LightSample {
                wi: -self.e1,
                distance: f32::INFINITY,
                radiance: self.radiance,
                pdf: 1.0,
                delta: true,
            }),
            EmitterKind::Sphere => self.sample_sphere(p, u),
            EmitterKind::Environment => None,
            _ => {
                let (q, pdf_area) = self.sample_area(u);
                let offset = q - p;
                let distance2 = offset.length_squared();
                let distance = distance2.sqrt();
                let wi = offset / distance;
                let cos_light = self.emitting_cos(self.normal, wi);
                if cos_light <= 0.0 || distance == 0.0 {
                    return None;
                }
                let pdf = pdf_area * distance2 / cos_light;
                Some(LightSample { wi, distance, radiance: self.radiance, pdf, delta: false })
            }
        }
    }

    /// Solid-angle density with which [`Emitter::sample`] from `p` picks the surface
    /// point `q` (whose unit normal is `n`), for weighing a BSDF-sampled hit.
    pub fn pdf(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        match self.kind {
            EmitterKind::Triangle | EmitterKind::Parallelogram | EmitterKind::Disk => {
                let offset = q - p;
                let distance2 = offset.length_squared();
                let cos_light = n.dot(offset).abs() / distance2.sqrt();
                if cos_light <= 0.0 { 0.0 } else { distance2 / (cos_light * self.size) }
            }
            EmitterKind::Sphere => self.sphere_pdf(p, q, n),
            _ => 0.0,
        }
    }

    /// `1/(c1 + c2·d + c3·d²)`: the inverse square law for `(0, 0, 1)`.
    fn attenuate(&self, d: f32) -> f32 {
        let [c1, c2, c3] = self.attenuation.to_array();
        1.0 / (c1 + c2 * d + c3 * d * d)
    }

    /// 1 inside the inner cone, 0 outside the outer one, the smooth cubic or the
    /// linear fade between (the same profiles as the Whitted spot light).
    fn spot_falloff(&self, from_light: Vec3) -> f32 {
        let cos = from_light.dot(self.e1);
        if cos >= self.cos_inner {
            return 1.0;
        }
        if cos <= self.cos_outer {
            return 0.0;
        }
        let (inner, outer) = (self.cos_inner.clamp(-1.0, 1.0).acos(), self.cos_outer.clamp(-1.0, 1.0).acos());
        let x = (cos.clamp(-1.0, 1.0).acos() - inner) / (outer - inner);
        if self.linear_falloff != 0 { 1.0 - x } else { 1.0 - x * x * (3.0 - 2.0 * x) }
    }

    /// Seen from outside, a uniform direction in the cone the sphere subtends (its
    /// solid angle, exactly); from inside, a uniform point of its surface.
    fn sample_sphere(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let (c, r) = (self.p, self.size);
        let to_centre = c - p;
        let d2 = to_centre.length_squared();
        if d2 <= r * r {
            let z = 1.0 - 2.0 * u.x;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            let n = Vec3::new(s * phi.cos(), s * phi.sin(), z);
            let q = c + r * n;
            let offset = q - p;
            let distance2 = offset.length_squared();
            let distance = distance2.sqrt();
            let wi = offset / distance;
            let cos_light = self.emitting_cos(n, wi);
            if cos_light <= 0.0 {
                return None;
            }
            let pdf = distance2 / (cos_light * 4.0 * PI * r * r);
            return Some(LightSample { wi, distance, radiance: self.radiance, pdf, delta: false });
        }
        let d = d2.sqrt();
        // 1 − cos θmax as sin²/(1 + cos): no cancellation for small, far spheres.
        let sin2_max = r * r / d2;
        let one_minus_cos_max = sin2_max / (1.0 + (1.0 - sin2_max).max(0.0).sqrt());
        let one_minus_cos = u.x * one_minus_cos_max;
        let cos = 1.0 - one_minus_cos;
        let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let axis = to_centre / d;
        let (t, b) = axis.any_orthonormal_pair();
        let wi = (sin * phi.cos()) * t + (sin * phi.sin()) * b + cos * axis;
        // Distance to the near side of the sphere along wi.
        let along = wi.dot(to_centre);
        let distance = along - (r * r - (d2 - along * along)).max(0.0).sqrt();
        let pdf = 1.0 / (2.0 * PI * one_minus_cos_max);
        Some(LightSample { wi, distance, radiance: self.radiance, pdf, delta: false })
    }

    fn sphere_pdf(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        let (c, r) = (self.p, self.size);
        let d2 = (c - p).length_squared();
        if d2 <= r * r {
            let offset = q - p;
            let distance2 = offset.length_squared();
            let cos_light = n.dot(offset).abs() / distance2.sqrt();
            return if cos_light <= 0.0 { 0.0 } else { distance2 / (cos_light * 4.0 * PI * r * r) };
        }
        let sin2_max = r * r / d2;
        let one_minus_cos_max = sin2_max / (1.0 + (1.0 - sin2_max).max(0.0).sqrt());
        1.0 / (2.0 * PI * one_minus_cos_max)
    }
}

/// Rec. 709 luminance.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

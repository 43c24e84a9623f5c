//! Physically based scattering (BSDFs) for the path tracer.
//!
//! A closed set of kinds in one flat record ([`Bsdf`]) per material, dispatched by
//! `match`, so the same data can be uploaded to a GPU. At a hit the record's textured
//! parameters are resolved once into a [`SurfaceBsdf`], which evaluates, samples and
//! gives densities in the local shading frame (z = the outward normal).
//!
//! Conventions (as PBRT's): `wo` points toward the viewer, `wi` toward the light;
//! `f(wo, wi)` excludes the cosine; sampled weights are `f·|cos θ_i| / pdf`.

mod coat;
pub mod fresnel;
pub mod lobes;
pub mod microfacet;
mod phong;
#[cfg(test)]
mod tests;

use bytemuck::NoUninit;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

use crate::desc::{BsdfDesc, ColorParam, MaterialDesc, ScalarParam};
use crate::material::NO_TEXTURE;
use lobes::{cosine_hemisphere, cosine_hemisphere_pdf, mirror};
use microfacet::{Ggx, Microfacet};

/// The largest f32 below 1: keeps a rescaled lobe choice inside [0, 1).
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// What a [`Bsdf`] record is.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum BsdfKind {
    Diffuse = 0,
    Conductor = 1,
    Dielectric = 2,
    ThinDielectric = 3,
    Plastic = 4,
    /// The lecture's Phong material read physically: see [`phong`].
    Phong = 5,
    /// glTF's metallic-roughness model: a metal and a plastic blended by `metallic`.
    MetallicRoughness = 6,
}

/// Record flag: the back side scatters like the front.
pub const TWO_SIDED: u32 = 1;
/// Record flag (plastic): internal scattering saturates colours (Mitsuba's `nonlinear`).
pub const NONLINEAR: u32 = 2;
/// Record flag: rough lobes use the Beckmann distribution instead of GGX.
pub const BECKMANN: u32 = 4;
/// Record flag: the surface emits from both sides (its material is two-sided), not
/// only from the side its normal points to. Kept apart from [`TWO_SIDED`], which
/// dielectrics and the Phong reading force on for scattering.
pub const EMITS_BOTH_SIDES: u32 = 8;
/// Record flag: objects of this material let shadow rays through
/// ([`crate::desc::MaterialDesc::casts_shadows`] is false).
pub const CASTS_NO_SHADOW: u32 = 16;

/// A compiled BSDF with the emission of its material, as flat data.
///
/// `color` is the main colour (diffuse reflectance, a conductor's specular tint, a
/// plastic's base); with a texture it is `lerp(color, texture_scale·T(uv), blend)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Bsdf {
    pub kind: BsdfKind,
    pub flags: u32,
    pub color: Vec3,
    pub color_texture: u32,
    pub texture_scale: Vec3,
    pub blend: f32,
    pub uv_repeat: Vec2,
    /// Dielectric/plastic reflectance tint; Phong: the mirror weight `k_s·O_r`.
    pub specular: Vec3,
    /// Dielectric transmittance tint; Phong: the transmitted weight `k_t·O_t`.
    pub transmittance: Vec3,
    /// Conductor: the real part of the index per channel. Dielectrics and plastic:
    /// `eta.x` = inside / outside index. Phong: `eta.x` = its ior.
    pub eta: Vec3,
    /// Conductor: the imaginary part (absorption) per channel.
    pub k: Vec3,
    /// GGX roughness (0 = smooth); times the texture's mean channel when textured.
    pub alpha: f32,
    pub alpha_texture: u32,
    /// Phong: the glossy weight `k_s·O_s` and its exponent `n`.
    pub glossy: Vec3,
    pub exponent: f32,
    /// Plastic: the internal diffuse Fresnel reflectance of the coat.
    pub internal_reflectance: f32,
    /// Rough plastic: the coat's transmittance at `cos θ = i/(N−1)` ([`coat`]).
    pub coat_transmittance: [f32; coat::COAT_TABLE],
    /// Radiance the surface emits from its front side (area light).
    pub emission: Vec3,
    /// Texture multiplying `emission`, or [`NO_TEXTURE`].
    pub emission_texture: u32,
    /// Metallic-roughness: the metal's share of the blend (0 plastic, 1 metal); times
    /// the mean channel of `metallic_texture` when there is one.
    pub metallic: f32,
    pub metallic_texture: u32,
}

impl Bsdf {
    /// The physically based reading of a material: its `bsdf` when given, else the
    /// Phong mapping of [`phong::from_phong`].
    pub fn compile(desc: &MaterialDesc) -> Self {
        let base = Self {
            kind: BsdfKind::Diffuse,
            flags: if desc.two_sided { TWO_SIDED | EMITS_BOTH_SIDES } else { 0 }
                | if desc.microfacet == crate::desc::MicrofacetKind::Beckmann { BECKMANN } else { 0 }
                | if desc.casts_shadows { 0 } else { CASTS_NO_SHADOW },
            color: Vec3::ZERO,
            color_texture: NO_TEXTURE,
            texture_scale: Vec3::ONE,
            blend: 0.0,
            uv_repeat: Vec2::ONE,
            specular: Vec3::ZERO,
            transmittance: Vec3::ZERO,
            eta: Vec3::ONE,
            k: Vec3::ZERO,
            alpha: 0.0,
            alpha_texture: NO_TEXTURE,
            glossy: Vec3::ZERO,
            exponent: 1.0,
            internal_reflectance: 0.0,
            coat_transmittance: [1.0; coat::COAT_TABLE],
            emission: desc.emission,
            emission_texture: tex(desc.emission_texture),
            metallic: 0.0,
            metallic_texture: NO_TEXTURE,
        };
        let Some(bsdf) = desc.bsdf else {
            return phong::from_phong(desc, base);
        };
        let with_color = |b: Self, c: ColorParam| Self {
            color: c.value,
            color_texture: tex(c.texture),
            texture_scale: c.value,
            blend: if c.texture.is_some() { 1.0 } else { 0.0 },
            ..b
        };
        let with_alpha = |b: Self, a: ScalarParam| Self { alpha: a.value, alpha_texture: tex(a.texture), ..b };
        match bsdf {
            BsdfDesc::Diffuse { reflectance } => with_color(base, reflectance),
            BsdfDesc::Conductor { eta, k, specular, alpha } => {
                with_alpha(with_color(Self { kind: BsdfKind::Conductor, eta, k, ..base }, specular), alpha)
            }
            // Matched indices make an interface light passes straight through: smooth.
            BsdfDesc::Dielectric { int_ior, ext_ior, reflectance, transmittance, alpha: _ } if int_ior == ext_ior => {
                Self {
                    kind: BsdfKind::Dielectric,
                    flags: base.flags | TWO_SIDED,
                    specular: reflectance,
                    transmittance,
                    ..base
                }
            }
            BsdfDesc::Dielectric { int_ior, ext_ior, reflectance, transmittance, alpha } => with_alpha(
                Self {
                    kind: BsdfKind::Dielectric,
                    flags: base.flags | TWO_SIDED,
                    eta: Vec3::splat(int_ior / ext_ior),
                    specular: reflectance,
                    transmittance,
                    ..base
                },
                alpha,
            ),
            BsdfDesc::ThinDielectric { int_ior, ext_ior, reflectance, transmittance } => Self {
                kind: BsdfKind::ThinDielectric,
                flags: base.flags | TWO_SIDED,
                eta: Vec3::splat(int_ior / ext_ior),
                specular: reflectance,
                transmittance,
                ..base
            },
            BsdfDesc::Plastic { diffuse, int_ior, ext_ior, specular, alpha, nonlinear } => {
                let plastic = Self {
                    kind: BsdfKind::Plastic,
                    flags: base.flags | if nonlinear { NONLINEAR } else { 0 },
                    specular,
                    ..base
                };
                with_alpha(with_color(plastic.with_coat(int_ior / ext_ior, alpha.value), diffuse), alpha)
            }
            BsdfDesc::MetallicRoughness { base: color, metallic, alpha, ior } => {
                let blend = Self {
                    kind: BsdfKind::MetallicRoughness,
                    specular: Vec3::ONE,
                    metallic: metallic.value,
                    metallic_texture: tex(metallic.texture),
                    ..base
                };
                with_alpha(with_color(blend.with_coat(ior, alpha.value), color), alpha)
            }
        }
    }

    /// A dielectric coat of relative index `eta` over the base: its Fresnel tables. A
    /// rough coat's are made at the base roughness `alpha` (a roughness texture varies
    /// the specular lobe only).
    fn with_coat(self, eta: f32, alpha: f32) -> Self {
        let (coat_transmittance, internal_reflectance) = if alpha >= Ggx::MIN_ALPHA {
            let beckmann = self.flags & BECKMANN != 0;
            coat::coat_tables(Microfacet { alpha, beckmann }, eta)
        } else {
            ([1.0; coat::COAT_TABLE], fresnel::diffuse_reflectance(1.0 / eta))
        };
        Self { eta: Vec3::splat(eta), coat_transmittance, internal_reflectance, ..self }
    }

    /// Whether the surface emits light.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// The parameters at texture coordinates `uv`; `texture(index, uv)` samples the
    /// scene's textures. Inlined into the path loop, where an untextured surface then
    /// costs three compares.
    #[inline(always)]
    pub fn at(&self, uv: Vec2, texture: impl Fn(u32, Vec2) -> Vec3) -> SurfaceBsdf<'_> {
        let mut color = self.color;
        if self.color_texture != NO_TEXTURE {
            let t = texture(self.color_texture, uv * self.uv_repeat);
            color = color.lerp(self.texture_scale * t, self.blend);
        }
        let mut alpha = self.alpha;
        if self.alpha_texture != NO_TEXTURE {
            alpha *= texture(self.alpha_texture, uv * self.uv_repeat).element_sum() / 3.0;
        }
        let mut metallic = self.metallic;
        if self.metallic_texture != NO_TEXTURE {
            metallic *= texture(self.metallic_texture, uv * self.uv_repeat).element_sum() / 3.0;
        }
        SurfaceBsdf {
            record: self,
            color,
            alpha: if alpha < Ggx::MIN_ALPHA { 0.0 } else { alpha },
            metallic: metallic.clamp(0.0, 1.0),
        }
    }
}

fn tex(index: Option<usize>) -> u32 {
    index.map_or(NO_TEXTURE, |i| i as u32)
}

/// A direction chosen by [`SurfaceBsdf::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Local direction toward the light.
    pub wi: Vec3,
    /// `f·|cos θ_i| / pdf`: the factor the path's throughput takes.
    pub weight: Vec3,
    /// Solid-angle density of `wi` (for a delta lobe, the probability of the lobe).
    pub pdf: f32,
    /// The lobe chosen is a delta (mirror or smooth refraction): no MIS with lights.
    pub delta: bool,
    /// Relative index across the interface when the ray was transmitted, else 1.
    pub eta: f32,
}

/// A BSDF with its textured parameters resolved at one point.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceBsdf<'a> {
    pub record: &'a Bsdf,
    pub color: Vec3,
    pub alpha: f32,
    /// Metallic-roughness: the metal's share at this point, in [0, 1].
    pub metallic: f32,
}

impl SurfaceBsdf<'_> {
    fn two_sided(&self) -> bool {
        self.record.flags & TWO_SIDED != 0
    }

    /// The distribution of the rough lobes at this point's roughness.
    fn microfacet(&self) -> Microfacet {
        Microfacet { alpha: self.alpha, beckmann: self.record.flags & BECKMANN != 0 }
    }

    /// Whether any lobe is smooth enough to take light samples (not only deltas).
    pub fn has_non_delta(&self) -> bool {
        match self.record.kind {
            BsdfKind::Diffuse | BsdfKind::Plastic => true,
            BsdfKind::Conductor | BsdfKind::Dielectric => self.alpha > 0.0,
            BsdfKind::MetallicRoughness => self.alpha > 0.0 || self.metallic < 1.0,
            BsdfKind::ThinDielectric => false,
            BsdfKind::Phong => phong::has_non_delta(self),
        }
    }

    /// The colour a denoiser would call albedo: the surface's main reflectance.
    pub fn albedo(&self) -> Vec3 {
        match self.record.kind {
            BsdfKind::Dielectric | BsdfKind::ThinDielectric => self.record.transmittance,
            BsdfKind::Conductor => self.color * fresnel::conductor(1.0, self.record.eta, self.record.k),
            _ => self.color,
        }
    }

    /// Reflection-only kinds see the world from their front; a two-sided one is mirrored
    /// to it, a one-sided one is black from behind. `None`: nothing scatters.
    #[inline(always)]
    fn reflection_side(&self, wo: Vec3) -> Option<f32> {
        if wo.z > 0.0 {
            Some(1.0)
        } else if wo.z < 0.0 && self.two_sided() {
            Some(-1.0)
        } else {
            None
        }
    }

    /// `f(wo, wi)` of the non-delta lobes.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        // Diffuse surfaces, the most common, are evaluated where they are asked for;
        // the other kinds in a call (the same arithmetic either way).
        if self.record.kind == BsdfKind::Diffuse {
            let Some(side) = self.reflection_side(wo) else { return Vec3::ZERO };
            return if wi.z * side <= 0.0 { Vec3::ZERO } else { self.diffuse_eval() };
        }
        self.eval_any(wo, wi)
    }

    /// [`SurfaceBsdf::eval`] for every kind, diffuse included.
    #[inline]
    fn eval_any(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self.record.kind {
            BsdfKind::Dielectric => self.rough_dielectric(wo, wi).0,
            BsdfKind::ThinDielectric => Vec3::ZERO,
            BsdfKind::Phong => phong::eval(self, wo, wi),
            _ => {
                let Some(side) = self.reflection_side(wo) else { return Vec3::ZERO };
                let (wo, wi) = (wo * Vec3::new(1.0, 1.0, side), wi * Vec3::new(1.0, 1.0, side));
                if wi.z <= 0.0 {
                    return Vec3::ZERO;
                }
                self.eval_front(wo, wi)
            }
        }
    }

    /// Density with which [`SurfaceBsdf::sample`] picks `wi` through a non-delta lobe.
    #[inline(always)]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.record.kind == BsdfKind::Diffuse {
            let Some(side) = self.reflection_side(wo) else { return 0.0 };
            let z = wi.z * side;
            return if z <= 0.0 { 0.0 } else { cosine_hemisphere_pdf(Vec3::new(wi.x, wi.y, z)) };
        }
        self.pdf_any(wo, wi)
    }

    /// [`SurfaceBsdf::pdf`] for every kind, diffuse included.
    #[inline]
    fn pdf_any(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self.record.kind {
            BsdfKind::Dielectric => self.rough_dielectric(wo, wi).1,
            BsdfKind::ThinDielectric => 0.0,
            BsdfKind::Phong => phong::pdf(self, wo, wi),
            _ => {
                let Some(side) = self.reflection_side(wo) else { return 0.0 };
                let (wo, wi) = (wo * Vec3::new(1.0, 1.0, side), wi * Vec3::new(1.0, 1.0, side));
                if wi.z <= 0.0 {
                    return 0.0;
                }
                self.pdf_front(wo, wi)
            }
        }
    }

    /// A direction `wi` for `wo`, from `u_lobe` (which lobe) and `u` (where in it).
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if self.record.kind == BsdfKind::Diffuse {
            let side = self.reflection_side(wo)?;
            let mut s = self.sample_diffuse(u)?;
            s.wi *= Vec3::new(1.0, 1.0, side);
            return Some(s);
        }
        self.sample_any(wo, u_lobe, u)
    }

    /// [`SurfaceBsdf::sample`] for every kind, diffuse included.
    #[inline]
    fn sample_any(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match self.record.kind {
            BsdfKind::Dielectric => self.sample_dielectric(wo, u_lobe, u),
            BsdfKind::ThinDielectric => self.sample_thin(wo, u_lobe),
            BsdfKind::Phong => phong::sample(self, wo, u_lobe, u),
            _ => {
                let side = self.reflection_side(wo)?;
                let flip = Vec3::new(1.0, 1.0, side);
                let mut s = self.sample_front(wo * flip, u_lobe, u)?;
                s.wi *= flip;
                Some(s)
            }
        }
    }

    // ---- reflection-only kinds, with wo and wi on the +z side ----

    fn eval_front(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self.record.kind {
            BsdfKind::Diffuse => self.diffuse_eval(),
            BsdfKind::Conductor => self.metal_eval(wo, wi),
            BsdfKind::Plastic => self.plastic_eval(wo, wi),
            BsdfKind::MetallicRoughness => {
                let m = self.metallic;
                let metal = if m > 0.0 { self.metal_eval(wo, wi) * m } else { Vec3::ZERO };
                let plastic = if m < 1.0 { self.plastic_eval(wo, wi) * (1.0 - m) } else { Vec3::ZERO };
                metal + plastic
            }
            _ => Vec3::ZERO,
        }
    }

    /// A metal's reflectance at `cos θ` to the microfacet normal: the complex-index
    /// Fresnel of a conductor, Schlick's with the base colour as F0 for
    /// metallic-roughness (as glTF defines it).
    fn metal_fresnel(&self, cos: f32) -> Vec3 {
        let r = self.record;
        if r.kind == BsdfKind::MetallicRoughness {
            fresnel::schlick(self.color, cos)
        } else {
            self.color * fresnel::conductor(cos, r.eta, r.k)
        }
    }

    /// The rough metal lobe (zero when smooth: a delta).
    fn metal_eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.alpha == 0.0 {
            return Vec3::ZERO;
        }
        let m = (wo + wi).normalize();
        let ggx = self.microfacet();
        self.metal_fresnel(wo.dot(m)) * (ggx.d(m) * ggx.g(wo, wi, m) / (4.0 * wo.z * wi.z))
    }

    fn metal_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.alpha == 0.0 {
            return 0.0;
        }
        let m = (wo + wi).normalize();
        self.microfacet().normal_pdf(wo, m) / (4.0 * wo.dot(m))
    }

    /// The diffuse base through the coat plus, when rough, the coat's specular lobe.
    fn plastic_eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let r = self.record;
        let mut f = self.plastic_diffuse(wo, wi);
        if self.alpha > 0.0 {
            let m = (wo + wi).normalize();
            let ggx = self.microfacet();
            let fr = fresnel::dielectric(wo.dot(m), r.eta.x).0;
            f += r.specular * (fr * ggx.d(m) * ggx.g(wo, wi, m) / (4.0 * wo.z * wi.z));
        }
        f
    }

    fn plastic_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p_specular = self.plastic_specular_probability(wo);
        let mut pdf = (1.0 - p_specular) * cosine_hemisphere_pdf(wi);
        if self.alpha > 0.0 {
            let m = (wo + wi).normalize();
            pdf += p_specular * self.microfacet().normal_pdf(wo, m) / (4.0 * wo.dot(m));
        }
        pdf
    }

    fn pdf_front(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self.record.kind {
            BsdfKind::Diffuse => cosine_hemisphere_pdf(wi),
            BsdfKind::Conductor => self.metal_pdf(wo, wi),
            BsdfKind::Plastic => self.plastic_pdf(wo, wi),
            BsdfKind::MetallicRoughness => {
                let m = self.metallic;
                let metal = if m > 0.0 { self.metal_pdf(wo, wi) * m } else { 0.0 };
                let plastic = if m < 1.0 { self.plastic_pdf(wo, wi) * (1.0 - m) } else { 0.0 };
                metal + plastic
            }
            _ => 0.0,
        }
    }

    fn sample_front(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let r = self.record;
        match r.kind {
            BsdfKind::Diffuse => self.sample_diffuse(u),
            BsdfKind::Conductor => self.sample_metal(wo, u),
            BsdfKind::Plastic => self.sample_plastic(wo, u_lobe, u),
            BsdfKind::MetallicRoughness => self.sample_metallic_roughness(wo, u_lobe, u),
            _ => None,
        }
    }

    /// Lambert's `f` (for `wo` and `wi` on the front).
    #[inline(always)]
    fn diffuse_eval(&self) -> Vec3 {
        self.color * FRAC_1_PI
    }

    /// A cosine-weighted direction on the front.
    #[inline(always)]
    fn sample_diffuse(&self, u: Vec2) -> Option<BsdfSample> {
        let wi = cosine_hemisphere(u);
        (wi.z > 0.0).then_some(BsdfSample {
            wi,
            weight: self.color,
            pdf: cosine_hemisphere_pdf(wi),
            delta: false,
            eta: 1.0,
        })
    }

    fn sample_metal(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if self.alpha == 0.0 {
            let weight = self.metal_fresnel(wo.z);
            return Some(BsdfSample { wi: mirror(wo), weight, pdf: 1.0, delta: true, eta: 1.0 });
        }
        let ggx = self.microfacet();
        let m = ggx.sample_normal(wo, u);
        let wi = lobes::reflect(wo, m);
        if wi.z <= 0.0 {
            return None;
        }
        let normal_pdf = ggx.normal_pdf(wo, m);
        if normal_pdf <= 0.0 {
            return None;
        }
        let pdf = normal_pdf / (4.0 * wo.dot(m));
        // f·cos/pdf = F·D·G·(wo·m)/(wo_z·pdf(m)): F·G1(wi) for GGX's visible normals.
        let weight = self.metal_fresnel(wo.dot(m)) * (ggx.d(m) * ggx.g(wo, wi, m) * wo.dot(m) / (wo.z * normal_pdf));
        Some(BsdfSample { wi, weight, pdf, delta: false, eta: 1.0 })
    }

    /// Picks the metal with probability `metallic`, else the plastic. A delta lobe's
    /// weight is its own (its share cancels against the probability of picking it);
    /// a rough direction is weighed by the whole blend, as any lobe could have made it.
    fn sample_metallic_roughness(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let m = self.metallic;
        if u_lobe < m {
            let s = self.sample_metal(wo, u)?;
            return if s.delta { Some(BsdfSample { pdf: m, ..s }) } else { self.weighed(wo, s.wi) };
        }
        let s = self.sample_plastic(wo, ((u_lobe - m) / (1.0 - m)).min(ONE_MINUS_EPSILON), u)?;
        Some(if self.alpha == 0.0 { BsdfSample { pdf: s.pdf * (1.0 - m), ..s } } else { s })
    }

    // ---- plastic: a diffuse base under a dielectric coat (Mitsuba's plastic) ----

    /// How often the coat's specular lobe is sampled: its Fresnel share weighted by the
    /// specular and diffuse colours' means.
    fn plastic_specular_probability(&self, wo: Vec3) -> f32 {
        let s = self.record.specular.element_sum() / 3.0;
        let d = self.color.element_sum() / 3.0;
        let weight = if s + d > 0.0 { s / (s + d) } else { 0.5 };
        let f = 1.0 - self.coat_transmittance(wo.z);
        let (ps, pd) = (f * weight, (1.0 - f) * (1.0 - weight));
        if ps + pd > 0.0 { ps / (ps + pd) } else { 0.0 }
    }

    /// The share of light at `cos θ = mu` that crosses the coat: `1 − F` for a smooth
    /// coat, the precomputed table for a rough one (as Mitsuba's plastics have it).
    fn coat_transmittance(&self, mu: f32) -> f32 {
        if self.alpha == 0.0 {
            1.0 - fresnel::dielectric(mu, self.record.eta.x).0
        } else {
            coat::lookup(&self.record.coat_transmittance, mu)
        }
    }

    /// Light refracted into the coat, scattered by the base (with the inter-reflections
    /// under the coat summed as a geometric series) and refracted out.
    fn plastic_diffuse(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let r = self.record;
        let eta = r.eta.x;
        let (fo, fi) = (1.0 - self.coat_transmittance(wo.z), 1.0 - self.coat_transmittance(wi.z));
        let denominator = if r.flags & NONLINEAR != 0 {
            Vec3::ONE - self.color * r.internal_reflectance
        } else {
            Vec3::splat(1.0 - r.internal_reflectance)
        };
        self.color / denominator * ((1.0 - fo) * (1.0 - fi) * FRAC_1_PI / (eta * eta))
    }

    fn sample_plastic(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let p_specular = self.plastic_specular_probability(wo);
        if self.alpha == 0.0 {
            if u_lobe < p_specular {
                let f = fresnel::dielectric(wo.z, self.record.eta.x).0;
                let weight = self.record.specular * (f / p_specular);
                return Some(BsdfSample { wi: mirror(wo), weight, pdf: p_specular, delta: true, eta: 1.0 });
            }
            let wi = cosine_hemisphere(u);
            let pdf = (1.0 - p_specular) * cosine_hemisphere_pdf(wi);
            if wi.z <= 0.0 || pdf <= 0.0 {
                return None;
            }
            let weight = self.plastic_diffuse(wo, wi) * (wi.z / pdf);
            return Some(BsdfSample { wi, weight, pdf, delta: false, eta: 1.0 });
        }
        let wi = if u_lobe < p_specular {
            lobes::reflect(wo, self.microfacet().sample_normal(wo, u))
        } else {
            cosine_hemisphere(u)
        };
        self.weighed(wo, wi)
    }

    /// A sample of `wi` weighed by the full `f` and `pdf` (for mixtures of non-delta
    /// lobes, where any lobe could have produced `wi`).
    fn weighed(&self, wo: Vec3, wi: Vec3) -> Option<BsdfSample> {
        if wi.z * wo.z <= 0.0 && self.record.kind != BsdfKind::Dielectric {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(wo, wi) * (wi.z.abs() / pdf);
        Some(BsdfSample { wi, weight, pdf, delta: false, eta: 1.0 })
    }

    // ---- dielectrics ----

    fn sample_thin(&self, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        let r = self.record;
        let mut reflect = fresnel::dielectric(wo.z.abs(), r.eta.x).0;
        if reflect < 1.0 {
            // Both faces' inter-reflections: R + T²R/(1 − R²).
            reflect += (1.0 - reflect) * (1.0 - reflect) * reflect / (1.0 - reflect * reflect);
        }
        if u_lobe < reflect {
            Some(BsdfSample { wi: mirror(wo), weight: r.specular, pdf: reflect, delta: true, eta: 1.0 })
        } else {
            Some(BsdfSample { wi: -wo, weight: r.transmittance, pdf: 1.0 - reflect, delta: true, eta: 1.0 })
        }
    }

    fn sample_dielectric(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let r = self.record;
        let eta = r.eta.x;
        if self.alpha == 0.0 {
            let (f, cos_t, eta_it, eta_ti) = fresnel::dielectric(wo.z, eta);
            if u_lobe < f {
                return Some(BsdfSample { wi: mirror(wo), weight: r.specular, pdf: f, delta: true, eta: 1.0 });
            }
            let wi = lobes::refract(wo, Vec3::Z, cos_t, eta_ti);
            // Radiance is compressed into a smaller solid angle inside: × (η_i/η_t)².
            let weight = r.transmittance * (eta_ti * eta_ti);
            return Some(BsdfSample { wi, weight, pdf: 1.0 - f, delta: true, eta: eta_it });
        }
        let ggx = self.microfacet();
        // A normal (z > 0) visible from wo's side: from inside, fresnel sees wo·m < 0.
        let m = ggx.sample_normal(wo * wo.z.signum(), u);
        let (f, cos_t, eta_it, eta_ti) = fresnel::dielectric(wo.dot(m), eta);
        let (wi, transmitted) =
            if u_lobe < f { (lobes::reflect(wo, m), false) } else { (lobes::refract(wo, m, cos_t, eta_ti), true) };
        if transmitted == (wi.z * wo.z > 0.0) || wi.z == 0.0 {
            return None;
        }
        let (value, pdf) = self.rough_dielectric(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = value * (wi.z.abs() / pdf);
        Some(BsdfSample { wi, weight, pdf, delta: false, eta: if transmitted { eta_it } else { 1.0 } })
    }

    /// `f` and pdf of the rough dielectric (Walter et al. 2007, with visible-normal
    /// sampling; the generalized half vector as in PBRT 4th ed. §9.7).
    fn rough_dielectric(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let r = self.record;
        if self.alpha == 0.0 || wo.z == 0.0 || wi.z == 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let eta = r.eta.x;
        let reflect = wo.z * wi.z > 0.0;
        let etap = if reflect {
            1.0
        } else if wo.z > 0.0 {
            eta
        } else {
            1.0 / eta
        };
        let mut m = wi * etap + wo;
        if m.length_squared() == 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        m = m.normalize();
        if m.z < 0.0 {
            m = -m;
        }
        // Microfacets seen from behind by either direction contribute nothing.
        if m.dot(wi) * wi.z < 0.0 || m.dot(wo) * wo.z < 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let ggx = self.microfacet();
        let f = fresnel::dielectric(wo.dot(m), eta).0;
        let visible = ggx.normal_pdf(wo, m);
        if reflect {
            let value = r.specular * (ggx.d(m) * ggx.g(wo, wi, m) * f / (4.0 * wi.z * wo.z).abs());
            (value, visible / (4.0 * wo.dot(m).abs()) * f)
        } else {
            let denom = wi.dot(m) + wo.dot(m) / etap;
            let denom2 = denom * denom;
            let value =
                ggx.d(m) * (1.0 - f) * ggx.g(wo, wi, m) * (wi.dot(m) * wo.dot(m) / (wi.z * wo.z * denom2)).abs();
            // Radiance scaling across the interface: ÷ η².
            let value = r.transmittance * (value / (etap * etap));
            let dm_dwi = wi.dot(m).abs() / denom2;
            (value, visible * dm_dwi * (1.0 - f))
        }
    }
}

//! The lecture's Phong material read as a physically plausible BSDF, so that every
//! Whitted scene also renders path-traced:
//!
//! | Whitted term | lobe |
//! |---|---|
//! | `k_d·O_d` (textured) | Lambertian diffuse |
//! | `k_s·O_s`, exponent `n` | normalized Phong glossy lobe `(n+2)/2π·cos^n α` around the mirror direction (Lafortune & Willems 1994) |
//! | `k_s·O_r` | perfect mirror (delta) |
//! | `k_t·O_t`, `ior` | refraction by Snell's law without Fresnel, or straight through when ior = 1 (delta) |
//!
//! When the weights add up to more than one in some channel they are scaled down
//! together, so the surface never reflects more light than it receives. The ambient
//! term has no counterpart: global illumination computes what it stood for.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

use super::lobes::{cosine_hemisphere, cosine_hemisphere_pdf, mirror, phong_lobe, phong_lobe_pdf};
use super::{Bsdf, BsdfKind, BsdfSample, SurfaceBsdf, TWO_SIDED};
use crate::desc::MaterialDesc;
use crate::material::{BLINN_HIGHLIGHT, Material};

/// The Phong record of a material without an explicit BSDF.
pub(super) fn from_phong(desc: &MaterialDesc, base: Bsdf) -> Bsdf {
    let m = Material::compile(desc, desc.texture.map(|t| t as u32));
    Bsdf {
        kind: BsdfKind::Phong,
        flags: base.flags | TWO_SIDED,
        color: m.diffuse,
        color_texture: m.texture,
        texture_scale: Vec3::splat(m.kd),
        blend: m.blend,
        uv_repeat: m.texture_repeat,
        specular: m.reflective,
        transmittance: m.transmissive,
        eta: Vec3::splat(m.ior),
        glossy: m.specular,
        exponent: lobe_exponent(&m),
        ..base
    }
}

/// The glossy lobe's exponent around the mirror direction. A Blinn highlight `(n·h)^n`
/// is about as wide as Phong's `(r·v)^(n/4)` (the half-vector angle is half the
/// mirror-direction angle), so Blinn materials keep their highlight's size.
fn lobe_exponent(m: &Material) -> f32 {
    let n = m.shininess.max(0.0);
    if m.highlight == BLINN_HIGHLIGHT { n / 4.0 } else { n }
}

/// The four lobe weights (diffuse, glossy, mirror, transmitted), scaled to conserve
/// energy, and the probabilities of sampling each.
fn lobes(s: &SurfaceBsdf<'_>) -> ([Vec3; 4], [f32; 4]) {
    let r = &s.record;
    let mut w = [s.color, r.glossy, r.specular, r.transmittance].map(|c| c.max(Vec3::ZERO));
    let total = (w[0] + w[1] + w[2] + w[3]).max_element();
    if total > 1.0 {
        w = w.map(|c| c / total);
    }
    let means = w.map(|c| c.element_sum());
    let sum: f32 = means.iter().sum();
    let p = if sum > 0.0 { means.map(|m| m / sum) } else { [0.0; 4] };
    (w, p)
}

pub(super) fn has_non_delta(s: &SurfaceBsdf<'_>) -> bool {
    let (_, p) = lobes(s);
    p[0] + p[1] > 0.0
}

/// `wo` and `wi` seen from `wo`'s side (the material is two-sided).
fn front(wo: Vec3, wi: Vec3) -> (Vec3, Vec3) {
    if wo.z < 0.0 { (wo * Vec3::new(1.0, 1.0, -1.0), wi * Vec3::new(1.0, 1.0, -1.0)) } else { (wo, wi) }
}

pub(super) fn eval(s: &SurfaceBsdf<'_>, wo: Vec3, wi: Vec3) -> Vec3 {
    let (wo, wi) = front(wo, wi);
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return Vec3::ZERO;
    }
    let (w, _) = lobes(s);
    let n = s.record.exponent;
    let cos_a = mirror(wo).dot(wi).max(0.0);
    w[0] * FRAC_1_PI + w[1] * ((n + 2.0) / (2.0 * PI) * cos_a.powf(n))
}

pub(super) fn pdf(s: &SurfaceBsdf<'_>, wo: Vec3, wi: Vec3) -> f32 {
    let (wo, wi) = front(wo, wi);
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let (_, p) = lobes(s);
    p[0] * cosine_hemisphere_pdf(wi) + p[1] * phong_lobe_pdf(mirror(wo), s.record.exponent, wi)
}

pub(super) fn sample(s: &SurfaceBsdf<'_>, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
    let (w, p) = lobes(s);
    let flip = if wo.z < 0.0 { Vec3::new(1.0, 1.0, -1.0) } else { Vec3::ONE };
    let wo_front = wo * flip;
    let (c0, c1, c2) = (p[0], p[0] + p[1], p[0] + p[1] + p[2]);
    if u_lobe < c1 {
        let wi_front =
            if u_lobe < c0 { cosine_hemisphere(u) } else { phong_lobe(mirror(wo_front), s.record.exponent, u) };
        let wi = wi_front * flip;
        let pdf = pdf(s, wo, wi);
        if wi_front.z <= 0.0 || (pdf.is_nan() || pdf <= 0.0) {
            return None;
        }
        return Some(BsdfSample { wi, weight: eval(s, wo, wi) * (wi_front.z / pdf), pdf, delta: false, eta: 1.0 });
    }
    if u_lobe < c2 {
        return Some(BsdfSample { wi: mirror(wo), weight: w[2] / p[2], pdf: p[2], delta: true, eta: 1.0 });
    }
    if p[3] <= 0.0 {
        return None;
    }
    let ior = s.record.eta.x;
    if ior == 1.0 {
        return Some(BsdfSample { wi: -wo, weight: w[3] / p[3], pdf: p[3], delta: true, eta: 1.0 });
    }
    // Snell's law alone (no Fresnel), as the Whitted model refracts.
    let eta_it = if wo.z > 0.0 { ior } else { 1.0 / ior };
    let eta_ti = 1.0 / eta_it;
    let sin2_t = eta_ti * eta_ti * (1.0 - wo.z * wo.z).max(0.0);
    if sin2_t >= 1.0 {
        // Total internal reflection: the transmitted share is reflected.
        return Some(BsdfSample { wi: mirror(wo), weight: w[3] / p[3], pdf: p[3], delta: true, eta: 1.0 });
    }
    let cos_t = (1.0 - sin2_t).sqrt() * -wo.z.signum();
    let wi = Vec3::new(-eta_ti * wo.x, -eta_ti * wo.y, cos_t);
    let weight = w[3] / p[3] * (eta_ti * eta_ti);
    Some(BsdfSample { wi, weight, pdf: p[3], delta: true, eta: eta_it })
}

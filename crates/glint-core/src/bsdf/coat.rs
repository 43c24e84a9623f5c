//! What a rough dielectric coat lets through: the tables Mitsuba's `roughplastic`
//! precomputes, so that a rough plastic's diffuse base is as bright here as there.
//!
//! `t(μ) = 1 − ρ(μ)`, where `ρ(μ)` is the directional albedo of the coat's microfacet
//! reflection for light arriving at `cos θ = μ`; the internal reflectance is the
//! cosine-weighted mean of `ρ` seen from inside the coat (relative index `1/η`).

use glam::{Vec2, Vec3};

use super::fresnel;
use super::lobes::reflect;
use super::microfacet::Microfacet;

/// Entries of the transmittance table, at `μ = i/(N−1)`.
pub const COAT_TABLE: usize = 32;

/// Stratified samples per axis for each albedo integral.
const STRATA: usize = 24;

/// `ρ(μ)`: the albedo of the microfacet reflection lobe with Fresnel at relative index
/// `eta`, by stratified sampling of microfacet normals (deterministic).
fn reflected_albedo(distribution: Microfacet, eta: f32, mu: f32) -> f32 {
    let wi = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let mut sum = 0.0f64;
    for a in 0..STRATA {
        for b in 0..STRATA {
            let u = Vec2::new((a as f32 + 0.5) / STRATA as f32, (b as f32 + 0.5) / STRATA as f32);
            let m = distribution.sample_normal(wi, u);
            let wo = reflect(wi, m);
            let pdf_m = distribution.normal_pdf(wi, m);
            if wo.z <= 0.0 || pdf_m <= 0.0 {
                continue;
            }
            // f·cos/pdf = F·D·G·(wi·m)/(wi_z·pdf(m)).
            let f = fresnel::dielectric(wi.dot(m), eta).0;
            let weight = f * distribution.d(m) * distribution.g(wi, wo, m) * wi.dot(m) / (wi.z * pdf_m);
            sum += weight as f64;
        }
    }
    (sum / (STRATA * STRATA) as f64).min(1.0) as f32
}

/// The coat's transmittance table and internal diffuse reflectance.
pub fn coat_tables(distribution: Microfacet, eta: f32) -> ([f32; COAT_TABLE], f32) {
    let mut table = [0.0; COAT_TABLE];
    let mut internal = 0.0f64;
    for (i, t) in table.iter_mut().enumerate() {
        let mu = (i as f32 / (COAT_TABLE - 1) as f32).max(1e-6);
        *t = 1.0 - reflected_albedo(distribution, eta, mu);
        internal += (reflected_albedo(distribution, 1.0 / eta, mu) * mu) as f64;
    }
    (table, (2.0 * internal / COAT_TABLE as f64) as f32)
}

/// The table at `mu` in [0, 1], linearly interpolated.
#[inline]
pub fn lookup(table: &[f32; COAT_TABLE], mu: f32) -> f32 {
    let x = mu.clamp(0.0, 1.0) * (COAT_TABLE - 1) as f32;
    let i = (x as usize).min(COAT_TABLE - 2);
    let w = x - i as f32;
    table[i] * (1.0 - w) + table[i + 1] * w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nearly_smooth_coat_transmits_one_minus_fresnel() {
        let (table, internal) = coat_tables(Microfacet { alpha: 0.01, beckmann: false }, 1.5);
        for mu in [0.2f32, 0.5, 0.9, 1.0] {
            let smooth = 1.0 - fresnel::dielectric(mu, 1.5).0;
            assert!((lookup(&table, mu) - smooth).abs() < 0.01, "μ {mu}: {} vs {smooth}", lookup(&table, mu));
        }
        // Inside, the cosine-weighted reflectance is the diffuse Fresnel reflectance.
        assert!((internal - fresnel::diffuse_reflectance(1.0 / 1.5)).abs() < 0.02, "{internal}");
    }

    #[test]
    fn rougher_coats_reflect_less_at_grazing_angles() {
        let smooth = coat_tables(Microfacet { alpha: 0.05, beckmann: false }, 1.5).0;
        let rough = coat_tables(Microfacet { alpha: 0.5, beckmann: true }, 1.5).0;
        assert!(lookup(&rough, 0.1) > lookup(&smooth, 0.1));
        assert!(rough.iter().chain(&smooth).all(|t| (0.0..=1.0).contains(t)));
    }
}

//! Fresnel reflectance at smooth interfaces, unpolarized light.

use glam::Vec3;

/// Reflectance of a dielectric interface for a ray whose cosine with the normal is
/// `cos_i` (negative: arriving from inside), relative index `eta` = inside / outside.
/// Returns (R, cos θ_t, η_it, η_ti) as Mitsuba's `fresnel` does: `cos_t` is negative
/// when `cos_i` is positive (the transmitted ray goes inside) and 0 under total
/// internal reflection, where R = 1.
#[inline]
pub fn dielectric(cos_i: f32, eta: f32) -> (f32, f32, f32, f32) {
    let outside = cos_i >= 0.0;
    let eta_it = if outside { eta } else { 1.0 / eta };
    let eta_ti = 1.0 / eta_it;
    let cos_i_abs = cos_i.abs();
    // Snell: sin²θ_t = η_ti²·sin²θ_i.
    let cos2_t = 1.0 - eta_ti * eta_ti * (1.0 - cos_i_abs * cos_i_abs).max(0.0);
    if cos2_t <= 0.0 || eta == 1.0 {
        return if eta == 1.0 { (0.0, -cos_i, 1.0, 1.0) } else { (1.0, 0.0, eta_it, eta_ti) };
    }
    let cos_t_abs = cos2_t.sqrt();
    let a_s = (eta_it * cos_t_abs - cos_i_abs) / (eta_it * cos_t_abs + cos_i_abs);
    let a_p = (eta_it * cos_i_abs - cos_t_abs) / (eta_it * cos_i_abs + cos_t_abs);
    let r = 0.5 * (a_s * a_s + a_p * a_p);
    let cos_t = if outside { -cos_t_abs } else { cos_t_abs };
    (r, cos_t, eta_it, eta_ti)
}

/// Reflectance of a conductor with complex index `eta + i·k` (relative to the outside),
/// per channel, for `cos_i` in [0, 1] (exact formula for unpolarized light; PBRT 4th
/// ed. §9.5, written in real arithmetic as Mitsuba's `fresnel_conductor`).
#[inline]
pub fn conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let c = cos_i.clamp(0.0, 1.0);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let eta2 = eta * eta;
    let k2 = k * k;
    let t0 = eta2 - k2 - Vec3::splat(s2);
    let a2b2 = (t0 * t0 + 4.0 * eta2 * k2).max(Vec3::ZERO);
    let a2b2 = Vec3::new(a2b2.x.sqrt(), a2b2.y.sqrt(), a2b2.z.sqrt());
    let a = (0.5 * (a2b2 + t0)).max(Vec3::ZERO);
    let a = Vec3::new(a.x.sqrt(), a.y.sqrt(), a.z.sqrt());
    let t1 = a2b2 + Vec3::splat(c2);
    let t2 = 2.0 * c * a;
    let r_s = (t1 - t2) / (t1 + t2);
    let t3 = c2 * a2b2 + Vec3::splat(s2 * s2);
    let t4 = t2 * s2;
    // η = k = 0 (a perfect mirror) makes t3 = t4 = 0 at normal incidence: R_p = R_s.
    let ratio = (t3 - t4) / (t3 + t4);
    let ratio = Vec3::select((t3 + t4).cmpgt(Vec3::ZERO), ratio, Vec3::ONE);
    let r_p = r_s * ratio;
    (0.5 * (r_s + r_p)).clamp(Vec3::ZERO, Vec3::ONE)
}

/// Schlick's approximation with reflectance `f0` at normal incidence, per channel: the
/// metal Fresnel of glTF's metallic-roughness model.
#[inline]
pub fn schlick(f0: Vec3, cos_i: f32) -> Vec3 {
    let c = 1.0 - cos_i.clamp(0.0, 1.0);
    let c2 = c * c;
    f0 + (Vec3::ONE - f0) * (c2 * c2 * c)
}

/// Hemispherical average of the dielectric reflectance for light arriving from a
/// cosine-weighted hemisphere (the diffuse Fresnel reflectance), by numerical
/// integration: `2∫R(μ)μ dμ`. `eta` is the index on the far side over the near side.
pub fn diffuse_reflectance(eta: f32) -> f32 {
    let steps = 2048;
    let mut sum = 0.0f64;
    for i in 0..steps {
        let mu = (i as f32 + 0.5) / steps as f32;
        sum += (dielectric(mu, eta).0 * mu) as f64;
    }
    (2.0 * sum / steps as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_matches_known_values() {
        // Normal incidence: ((η−1)/(η+1))².
        let (r, cos_t, ..) = dielectric(1.0, 1.5);
        assert!((r - 0.04).abs() < 1e-6);
        assert!((cos_t + 1.0).abs() < 1e-6);
        // Brewster's angle: p-polarized reflectance vanishes, R = R_s/2.
        let brewster = 1.5f32.atan();
        let (r, ..) = dielectric(brewster.cos(), 1.5);
        assert!((r - 0.0740).abs() < 2e-3, "{r}");
        // Total internal reflection from inside past the critical angle.
        assert_eq!(dielectric(-0.5, 1.5).0, 1.0);
        // Grazing: R → 1.
        assert!(dielectric(1e-4, 1.5).0 > 0.99);
        // Reciprocity of the interface: the same R from both sides at matched angles.
        let (r_out, cos_t, ..) = dielectric(0.8, 1.33);
        let (r_in, ..) = dielectric(cos_t, 1.33);
        assert!((r_out - r_in).abs() < 1e-5);
    }

    #[test]
    fn conductor_reduces_to_dielectric_for_zero_k_and_matches_gold() {
        for c in [0.1f32, 0.5, 0.9, 1.0] {
            let r = conductor(c, Vec3::splat(1.5), Vec3::ZERO);
            assert!((r.x - dielectric(c, 1.5).0).abs() < 1e-5, "{c}: {r}");
        }
        // Gold at normal incidence: ((n−1)² + k²)/((n+1)² + k²).
        let (eta, k) = (Vec3::new(0.143, 0.374, 1.442), Vec3::new(3.983, 2.385, 1.603));
        let r = conductor(1.0, eta, k);
        let expected = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
        assert!((r - expected).abs().max_element() < 1e-4, "{r} {expected}");
    }

    #[test]
    fn diffuse_fresnel_reflectance_matches_the_fitted_formula() {
        // Egan & Hilgeman's fit for η > 1 (external reflectance of 1.5 glass ≈ 0.092).
        let r = diffuse_reflectance(1.5);
        assert!((r - 0.0918).abs() < 3e-3, "{r}");
        // Internal reflectance (from the denser side) is much larger: 1 − (1 − R_ext)/η².
        let internal = diffuse_reflectance(1.0 / 1.5);
        assert!((internal - (1.0 - (1.0 - r) / 2.25)).abs() < 3e-3, "{internal}");
    }
}

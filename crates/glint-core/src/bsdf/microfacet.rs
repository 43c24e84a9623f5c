//! Microfacet distributions — GGX (Trowbridge–Reitz) and Beckmann — with the separable
//! Smith shadowing term, in the local frame (z = normal). GGX samples visible normals;
//! Beckmann samples its normal distribution (both unbiased; visible normals are less
//! noisy).

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// An isotropic GGX distribution of roughness `alpha`.
#[derive(Clone, Copy, Debug)]
pub struct Ggx {
    pub alpha: f32,
}

/// An isotropic microfacet distribution: GGX, or Beckmann when `beckmann` is set.
#[derive(Clone, Copy, Debug)]
pub struct Microfacet {
    pub alpha: f32,
    pub beckmann: bool,
}

impl Microfacet {
    /// `D(m)`, normalized so that ∫D(m)·m_z dm = 1.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if !self.beckmann {
            return Ggx { alpha: self.alpha }.d(m);
        }
        if m.z <= 0.0 {
            return 0.0;
        }
        let cos2 = m.z * m.z;
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        let a2 = self.alpha * self.alpha;
        (-tan2 / a2).exp() / (PI * a2 * cos2 * cos2)
    }

    /// `G1(w, m)`; for Beckmann, Walter et al.'s rational fit as Mitsuba evaluates it.
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if !self.beckmann {
            return Ggx { alpha: self.alpha }.g1(w, m);
        }
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        let cos2 = w.z * w.z;
        let tan = ((1.0 - cos2).max(0.0) / cos2).sqrt();
        if tan == 0.0 {
            return 1.0;
        }
        let a = 1.0 / (self.alpha * tan);
        if a >= 1.6 { 1.0 } else { (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a) }
    }

    /// `G1(wo)·G1(wi)`.
    #[inline]
    pub fn g(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        self.g1(wo, m) * self.g1(wi, m)
    }

    /// A normal `m` (z > 0) for a viewer at `w` (`w.z > 0`).
    #[inline]
    pub fn sample_normal(&self, w: Vec3, u: Vec2) -> Vec3 {
        if !self.beckmann {
            return Ggx { alpha: self.alpha }.sample_visible(w, u);
        }
        let tan2 = -self.alpha * self.alpha * (1.0 - u.x).max(1e-12).ln();
        let cos = 1.0 / (1.0 + tan2).sqrt();
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
    }

    /// The density of [`Microfacet::sample_normal`] choosing `m` for a viewer at `w`
    /// (either side: `|w_z|`, `|w·m|`).
    #[inline]
    pub fn normal_pdf(&self, w: Vec3, m: Vec3) -> f32 {
        if self.beckmann {
            return self.d(m) * m.z.max(0.0);
        }
        if w.z == 0.0 {
            return 0.0;
        }
        let ggx = Ggx { alpha: self.alpha };
        ggx.g1(w, m) * w.dot(m).abs() * ggx.d(m) / w.z.abs()
    }
}

impl Ggx {
    /// Smallest roughness treated as rough; below it surfaces are perfectly smooth
    /// (delta lobes), where a microfacet lobe would be numerically unstable.
    pub const MIN_ALPHA: f32 = 1e-4;

    /// `D(m)`: density of microfacet normals `m` (projected area, ∫D(m)·m_z dm = 1).
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
        1.0 / (PI * a2 * t * t)
    }

    /// Smith's Λ for direction `w`.
    #[inline]
    fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::INFINITY;
        }
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        0.5 * ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0)
    }

    /// `G1(w, m)`: the fraction of microfacets with normal `m` visible from `w`.
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w))
    }

    /// `G(wo, wi, m) = G1(wo)·G1(wi)`, the separable form Mitsuba uses.
    #[inline]
    pub fn g(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        self.g1(wo, m) * self.g1(wi, m)
    }

    /// Density of sampling `m` as a visible normal from `w` (`w.z > 0`):
    /// `G1(w)·max(0, w·m)·D(m) / w_z`.
    #[inline]
    pub fn visible_pdf(&self, w: Vec3, m: Vec3) -> f32 {
        if w.z <= 0.0 {
            return 0.0;
        }
        self.g1(w, m) * w.dot(m).max(0.0) * self.d(m) / w.z
    }

    /// A microfacet normal visible from `w` (`w.z > 0`), by Heitz 2018 ("Sampling the
    /// GGX Distribution of Visible Normals").
    pub fn sample_visible(&self, w: Vec3, u: Vec2) -> Vec3 {
        // Stretch to the hemisphere configuration.
        let wh = Vec3::new(self.alpha * w.x, self.alpha * w.y, w.z).normalize();
        let len2 = wh.x * wh.x + wh.y * wh.y;
        let t1 = if len2 > 0.0 { Vec3::new(-wh.y, wh.x, 0.0) / len2.sqrt() } else { Vec3::X };
        let t2 = wh.cross(t1);
        // A uniform point on the disk, squeezed onto the visible half.
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + wh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * wh;
        Vec3::new(self.alpha * nh.x, self.alpha * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn projected_normal_density_integrates_to_one() {
        for alpha in [0.05f32, 0.3, 0.8] {
            let ggx = Ggx { alpha };
            // ∫ D(m) cos θ dω over the hemisphere, in (cos θ, φ) with a fine grid on
            // cos θ near 1 where D peaks for small alpha.
            let n = 4000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let t = (i as f32 + 0.5) / n as f32;
                let cos = 1.0 - t * t; // denser near the pole
                let dcos = 2.0 * t / n as f32;
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let m = Vec3::new(sin, 0.0, cos);
                sum += (ggx.d(m) * cos * dcos * 2.0 * PI) as f64;
            }
            assert!((sum - 1.0).abs() < 5e-3, "alpha {alpha}: {sum}");
        }
    }

    #[test]
    fn beckmann_normals_integrate_to_one_and_follow_their_density() {
        for alpha in [0.1f32, 0.4] {
            let b = Microfacet { alpha, beckmann: true };
            let n = 4000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let t = (i as f32 + 0.5) / n as f32;
                let cos = 1.0 - t * t;
                let m = Vec3::new((1.0 - cos * cos).max(0.0).sqrt(), 0.0, cos);
                sum += (b.d(m) * cos * 2.0 * t / n as f32 * 2.0 * PI) as f64;
            }
            assert!((sum - 1.0).abs() < 5e-3, "alpha {alpha}: {sum}");
            // Sampled normals: the mean of cos θ_m matches ∫ cos θ · pdf.
            let mut rng = Rng::new(2);
            let w = Vec3::new(0.3, 0.0, 0.95).normalize();
            let samples = 100_000;
            let mean: f32 =
                (0..samples).map(|_| b.sample_normal(w, Vec2::new(rng.next_f32(), rng.next_f32())).z).sum::<f32>()
                    / samples as f32;
            let mut expected = 0.0f64;
            for i in 0..n {
                let t = (i as f32 + 0.5) / n as f32;
                let cos = 1.0 - t * t;
                let m = Vec3::new((1.0 - cos * cos).max(0.0).sqrt(), 0.0, cos);
                expected += (b.normal_pdf(w, m) * cos * 2.0 * t / n as f32 * 2.0 * PI) as f64;
            }
            assert!((mean as f64 - expected).abs() < 2e-3, "alpha {alpha}: {mean} vs {expected}");
        }
    }

    #[test]
    fn visible_normals_face_the_viewer_and_follow_their_density() {
        let ggx = Ggx { alpha: 0.4 };
        let w = Vec3::new(0.6, 0.2, 0.5).normalize();
        let mut rng = Rng::new(3);
        // Histogram over cos θ_m against the density integrated per bin numerically.
        let bins = 10;
        let mut hist = vec![0u32; bins];
        let n = 200_000;
        for _ in 0..n {
            let m = ggx.sample_visible(w, Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!(m.dot(w) >= -1e-4 && m.z > 0.0);
            hist[((m.z * bins as f32) as usize).min(bins - 1)] += 1;
        }
        for (b, &count) in hist.iter().enumerate() {
            let (lo, hi) = (b as f32 / bins as f32, (b + 1) as f32 / bins as f32);
            let mut expected = 0.0f64;
            let (nc, np) = (200, 400);
            for i in 0..nc {
                let cos = lo + (hi - lo) * (i as f32 + 0.5) / nc as f32;
                let sin = (1.0 - cos * cos).sqrt();
                for j in 0..np {
                    let phi = 2.0 * PI * (j as f32 + 0.5) / np as f32;
                    let m = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                    expected += (ggx.visible_pdf(w, m) * (hi - lo) / nc as f32 * 2.0 * PI / np as f32) as f64;
                }
            }
            let observed = count as f64 / n as f64;
            assert!((observed - expected).abs() < 0.004, "bin {b}: {observed} vs {expected}");
        }
    }
}

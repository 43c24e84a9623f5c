//! Elementary lobes shared by the BSDFs: cosine-weighted diffuse, mirror reflection and
//! refraction in the local frame (z = normal), and Phong's cosine-power lobe.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// A direction of the upper hemisphere with density `cos θ / π` (Malley's method over
/// the concentric disk map).
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// The density of [`cosine_hemisphere`] for `w`.
#[inline]
pub fn cosine_hemisphere_pdf(w: Vec3) -> f32 {
    w.z.max(0.0) * FRAC_1_PI
}

/// Shirley & Chiu's concentric map from [0, 1)² onto the unit disk.
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let d = 2.0 * u - Vec2::ONE;
    if d == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if d.x.abs() > d.y.abs() {
        (d.x, std::f32::consts::FRAC_PI_4 * (d.y / d.x))
    } else {
        (d.y, std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (d.x / d.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Mirror of `w` about the local normal.
#[inline]
pub fn mirror(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Reflection of `w` about the unit vector `m`.
#[inline]
pub fn reflect(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// Refraction of `w` through the microfacet `m`, given the transmitted cosine `cos_t`
/// (signed as [`super::fresnel::dielectric`] returns it) and `eta_ti`.
#[inline]
pub fn refract(w: Vec3, m: Vec3, cos_t: f32, eta_ti: f32) -> Vec3 {
    m * (w.dot(m) * eta_ti + cos_t) - w * eta_ti
}

/// A direction around `axis` with density `(n+1)/2π · cos^n α` (the sampling density
/// of the normalized Phong lobe).
pub fn phong_lobe(axis: Vec3, exponent: f32, u: Vec2) -> Vec3 {
    let cos_a = u.x.powf(1.0 / (exponent + 1.0));
    let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let (t, b) = axis.any_orthonormal_pair();
    (sin_a * phi.cos()) * t + (sin_a * phi.sin()) * b + cos_a * axis
}

/// The density of [`phong_lobe`].
#[inline]
pub fn phong_lobe_pdf(axis: Vec3, exponent: f32, w: Vec3) -> f32 {
    let c = axis.dot(w);
    if c <= 0.0 { 0.0 } else { (exponent + 1.0) / (2.0 * PI) * c.powf(exponent) }
}

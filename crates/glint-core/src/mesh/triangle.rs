//! Watertight ray–triangle intersection (Woop, Benthin & Wald, "Watertight
//! Ray/Triangle Intersection", JCGT 2(1), 2013), with a tie-breaking rule for hits
//! exactly on an edge or a vertex so that they are found by exactly one triangle.
//!
//! The ray is sheared and scaled so it becomes the +z axis of a ray space; every vertex
//! is moved into that space once, by the same arithmetic whichever triangle it belongs
//! to. The 2D edge functions `U, V, W` of a shared edge are then exact negations of
//! each other in the two triangles that share it, so no ray can slip between them.

use glam::{DVec2, Vec3};

use crate::math::Ray;

/// A ray prepared for [`intersect`]: the axis permutation and shear of the paper's §3.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    pub(super) origin: Vec3,
    /// The axis of largest |d| is `kz`; `kx`, `ky` follow it, swapped when `d_kz < 0`
    /// so the winding of triangles is kept.
    pub(super) k: [usize; 3],
    /// `S_x = d_kx/d_kz`, `S_y = d_ky/d_kz`, `S_z = 1/d_kz`.
    pub(super) shear: Vec3,
}

impl WatertightRay {
    /// `None` for a zero or non-finite direction.
    #[inline]
    pub fn new(ray: &Ray) -> Option<Self> {
        // Arrays, not `Vec3`: indexing a `Vec3` by a run-time axis compiles to a chain of
        // branches, which random directions mispredict; an array index is one load.
        let d = ray.dir.to_array();
        let a = d.map(f32::abs);
        let kz = if a[0] > a[1] {
            if a[0] > a[2] { 0 } else { 2 }
        } else if a[1] > a[2] {
            1
        } else {
            2
        };
        if !(a[kz] > 0.0 && a[kz].is_finite()) {
            return None;
        }
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Some(Self { origin: ray.origin, k: [kx, ky, kz], shear: Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]) })
    }

    /// A vertex in ray space: `(x, y)` relative to the ray, `z` along it (unscaled).
    #[inline]
    fn ray_space(&self, p: Vec3) -> Vec3 {
        let a = (p - self.origin).to_array();
        let [kx, ky, kz] = self.k;
        Vec3::new(a[kx] - self.shear.x * a[kz], a[ky] - self.shear.y * a[kz], a[kz])
    }
}

/// A hit: `t` and the barycentric weights `(b0, b1, b2)` of the three vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub barycentric: Vec3,
}

/// Whether an edge whose edge function is exactly zero owns the points on it.
///
/// The rasterizer's "top-left" rule, applied to the edge's ray-space direction `to − from`:
/// of two triangles sharing an edge with consistent winding, one walks it one way and
/// the other the opposite way, so exactly one owns it. Around a shared vertex the same
/// half-plane test gives the vertex to exactly one triangle of the fan. The signs of the
/// differences are exact in floating point, so both triangles agree.
#[inline]
fn owns_edge(from: Vec3, to: Vec3) -> bool {
    let (dx, dy) = (to.x - from.x, to.y - from.y);
    dy > 0.0 || (dy == 0.0 && dx < 0.0)
}

/// Edge function `a × b` (2D) in double precision; exact in sign because the products
/// of two f32 fit in an f64 (the paper's fallback for `U, V, W = 0`).
#[inline]
fn edge_f64(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (DVec2::new(a.x as f64, a.y as f64), DVec2::new(b.x as f64, b.y as f64));
    (a.x * b.y - a.y * b.x) as f32
}

/// The hit of `ray` with triangle `(p0, p1, p2)` at `0 < t < t_max`, double-sided.
#[inline]
pub fn intersect(ray: &WatertightRay, p0: Vec3, p1: Vec3, p2: Vec3, t_max: f32) -> Option<TriangleHit> {
    let a = ray.ray_space(p0);
    let b = ray.ray_space(p1);
    let c = ray.ray_space(p2);
    // Scaled barycentrics: U is the edge b→c (opposite p0), V is c→a, W is a→b.
    let mut u = c.x * b.y - c.y * b.x;
    let mut v = a.x * c.y - a.y * c.x;
    let mut w = b.x * a.y - b.y * a.x;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        u = edge_f64(c, b);
        v = edge_f64(a, c);
        w = edge_f64(b, a);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    // On an edge or a vertex: only the owning triangle reports the hit.
    if (u == 0.0 && !owns_edge(b, c)) || (v == 0.0 && !owns_edge(c, a)) || (w == 0.0 && !owns_edge(a, b)) {
        return None;
    }
    let sz = ray.shear.z;
    let t_scaled = u * (sz * a.z) + v * (sz * b.z) + w * (sz * c.z);
    // t = T/det must lie in (0, t_max); compare without dividing, sign by sign.
    if det > 0.0 {
        if t_scaled <= 0.0 || t_scaled >= t_max * det {
            return None;
        }
    } else if t_scaled >= 0.0 || t_scaled <= t_max * det {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    (t > 0.0 && t < t_max).then(|| TriangleHit { t, barycentric: Vec3::new(u, v, w) * inv_det })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(origin: Vec3, dir: Vec3, tri: [Vec3; 3]) -> Option<TriangleHit> {
        intersect(&WatertightRay::new(&Ray::new(origin, dir))?, tri[0], tri[1], tri[2], f32::INFINITY)
    }

    #[test]
    fn centre_hit_has_equal_weights_and_right_t() {
        let tri = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0)];
        let h = hit(Vec3::new(1.0, 1.0, 2.0), Vec3::new(0.0, 0.0, -0.5), tri).unwrap();
        assert!((h.t - 4.0).abs() < 1e-6);
        assert!((h.barycentric - Vec3::splat(1.0 / 3.0)).abs().max_element() < 1e-6);
        // Double-sided: from below too.
        assert!(hit(Vec3::new(1.0, 1.0, -2.0), Vec3::Z, tri).is_some());
        // Behind the origin and beyond t_max are misses.
        assert!(hit(Vec3::new(1.0, 1.0, 2.0), Vec3::Z, tri).is_none());
        let r = WatertightRay::new(&Ray::new(Vec3::new(1.0, 1.0, 2.0), Vec3::NEG_Z)).unwrap();
        assert!(intersect(&r, tri[0], tri[1], tri[2], 1.5).is_none());
    }

    #[test]
    fn misses_outside_and_degenerate() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert!(hit(Vec3::new(0.6, 0.6, 1.0), Vec3::NEG_Z, tri).is_none());
        let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        assert!(hit(Vec3::new(0.5, 0.0, 1.0), Vec3::NEG_Z, flat).is_none());
        assert!(WatertightRay::new(&Ray::new(Vec3::ZERO, Vec3::ZERO)).is_none());
    }
}

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
    // In front (t = T/det > 0) where T and det have one sign; t_max bounds the divided
    // t alone. Comparing `T < t_max·det` instead, to save the division, refused hits a
    // larger t_max accepted once the products were subnormal (corners about 1e-19 from
    // the ray), so which of two triangles won depended on the order they were tested in.
    if !(if det > 0.0 { t_scaled > 0.0 } else { t_scaled < 0.0 }) {
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

    /// Whether a triangle is hit depends on t_max only through t < t_max: with corners
    /// about 1e-19 from a ray whose direction is 1e-10 long, `T` and `t_max·det` are
    /// subnormal, and `T < t_max·det` (compared to save the division) refused hits a
    /// larger t_max accepted, so the closest of two depended on the order tested.
    #[test]
    fn t_max_only_bounds_t_even_where_t_and_det_are_subnormal() {
        let ray = Ray::new(
            Vec3::new(-1.4234867e-18, -1.929634e-19, 1.2044693e-18),
            Vec3::new(8.330293e-11, 0.0, -5.5322885e-11),
        );
        let w = WatertightRay::new(&ray).unwrap();
        let triangles = [
            [
                Vec3::ZERO,
                Vec3::new(3.171191e-19, -4.5011943e-19, 7.907504e-19),
                Vec3::new(-5.0937643e-20, 5.2608706e-20, -6.8172333e-19),
            ],
            [
                Vec3::new(-5.0937643e-20, 5.2608706e-20, -6.8172333e-19),
                Vec3::new(3.171191e-19, -4.5011943e-19, 7.907504e-19),
                Vec3::new(-5.674402e-19, 0.0, 0.0),
            ],
            [Vec3::new(0.0, -9.429014e-19, 0.0), Vec3::ZERO, Vec3::new(9.381497e-19, 0.0, -8.3752466e-19)],
            [
                Vec3::new(4.0957515e-19, -9.220986e-19, 0.0),
                Vec3::new(-3.544334e-19, -5.4512055e-19, 0.0),
                Vec3::new(9.365551e-19, 5.0078734e-19, 0.0),
            ],
        ];
        let mut hits = 0;
        for [a, b, c] in triangles {
            let Some(h) = intersect(&w, a, b, c, f32::INFINITY) else { continue };
            hits += 1;
            for t_max in [h.t * (1.0 + 1e-6), h.t * 1.03, h.t * 2.0] {
                assert_eq!(intersect(&w, a, b, c, t_max).map(|g| g.t), Some(h.t), "t_max {t_max}");
            }
            assert!(intersect(&w, a, b, c, h.t).is_none(), "t = t_max is outside (0, t_max)");
        }
        assert!(hits >= 2, "the ray passes through the fan: {hits} hits");
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

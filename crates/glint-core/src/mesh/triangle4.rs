//! Four triangles tested against one ray at once: the watertight test of
//! [`super::triangle`] (Woop, Benthin & Wald, JCGT 2(1), 2013) on 4-lane vectors, over
//! leaves stored as structure of arrays, as Embree's `Triangle4` leaves are (Wald et al.,
//! "Embree: A Kernel Framework for Efficient CPU Ray Tracing", 2014).
//!
//! `glam::Vec4` is one SSE register on x86-64 (and plain arrays elsewhere), so this is
//! portable code that compiles to SSE. Every lane does exactly the scalar test's
//! arithmetic (same operations, same order, no fused multiply-add), so a lane's `U, V, W`
//! and `t` are bit for bit the scalar ones. Lanes with an edge function exactly 0 (a ray
//! through an edge or a vertex) go to the scalar test, whose f64 fallback and ownership
//! rule make such hits found exactly once.

use bytemuck::{Pod, Zeroable};
use glam::{BVec4A, Vec3, Vec4};

use super::triangle::{self, WatertightRay};

/// Up to four triangles, coordinates by corner and axis, lane = triangle; 160 bytes.
/// A leaf with fewer than four repeats its last triangle in the spare lanes, which then
/// report the same hit twice, harmlessly.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Triangle4 {
    /// `p[corner][axis][lane]`.
    pub p: [[[f32; 4]; 3]; 3],
    /// The mesh's triangle index of each lane.
    pub triangle: [u32; 4],
}

impl Triangle4 {
    /// Packs `corners` (one to four triangles) with their triangle indices.
    pub fn new(corners: &[[Vec3; 3]], first: u32) -> Triangle4 {
        assert!((1..=4).contains(&corners.len()), "a packet holds one to four triangles");
        let mut packet = Triangle4::zeroed();
        for lane in 0..4 {
            let k = lane.min(corners.len() - 1);
            for (corner, v) in corners[k].iter().enumerate() {
                for axis in 0..3 {
                    packet.p[corner][axis][lane] = v[axis];
                }
            }
            packet.triangle[lane] = first + k as u32;
        }
        packet
    }

    /// The corners of `lane`.
    #[inline]
    fn corners(&self, lane: usize) -> [Vec3; 3] {
        self.p.map(|c| Vec3::new(c[0][lane], c[1][lane], c[2][lane]))
    }
}

/// A [`WatertightRay`] splatted to four lanes, made once per ray.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay4 {
    scalar: WatertightRay,
    /// The origin's coordinates on axes `kx, ky, kz`.
    origin: [Vec4; 3],
    shear: [Vec4; 3],
}

impl WatertightRay4 {
    pub fn new(scalar: WatertightRay) -> Self {
        let [kx, ky, kz] = scalar.k;
        let o = scalar.origin.to_array();
        let s = scalar.shear;
        Self { scalar, origin: [o[kx], o[ky], o[kz]].map(Vec4::splat), shear: [s.x, s.y, s.z].map(Vec4::splat) }
    }
}

/// Lanes hit in `(0, t_max)` by the vector test, with their `t`, and (as a bitmask) the
/// lanes left to the scalar test because an edge function is exactly 0.
#[derive(Clone, Copy, Debug)]
struct Lanes {
    hit: BVec4A,
    t: Vec4,
    on_edge: u32,
}

/// The vector part of the test: the scalar [`triangle::intersect`] lane by lane, for
/// lanes whose edge functions are all nonzero.
#[inline(always)]
fn test(ray: &WatertightRay4, packet: &Triangle4, t_max: f32) -> Lanes {
    let [kx, ky, kz] = ray.scalar.k;
    let [ox, oy, oz] = ray.origin;
    let [sx, sy, sz] = ray.shear;
    // Each corner in ray space: `(a_kx − S_x·a_kz, a_ky − S_y·a_kz, a_kz)`, a = p − o.
    let ray_space = |c: &[[f32; 4]; 3]| {
        let z = Vec4::from(c[kz]) - oz;
        (Vec4::from(c[kx]) - ox - sx * z, Vec4::from(c[ky]) - oy - sy * z, z)
    };
    let (ax, ay, az) = ray_space(&packet.p[0]);
    let (bx, by, bz) = ray_space(&packet.p[1]);
    let (cx, cy, cz) = ray_space(&packet.p[2]);
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    let zero = Vec4::ZERO;
    let on_edge = u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero);
    let negative = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
    let positive = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
    let inside = !(negative & positive | on_edge);
    // Most packets a ray reaches miss it on all four lanes: stop before the distance
    // and its division.
    if !inside.any() {
        return Lanes { hit: inside, t: zero, on_edge: on_edge.bitmask() };
    }
    let det = u + v + w;
    let t_scaled = u * (sz * az) + v * (sz * bz) + w * (sz * cz);
    // In front where T and det have one sign; t_max bounds the divided t alone, as in
    // the scalar test (`T < t_max·det` is unreliable once the products are subnormal).
    let in_front = (det.cmpgt(zero) & t_scaled.cmpgt(zero)) | (det.cmplt(zero) & t_scaled.cmplt(zero));
    let candidate = inside & in_front;
    if !candidate.any() {
        return Lanes { hit: candidate, t: zero, on_edge: on_edge.bitmask() };
    }
    let t = t_scaled * (Vec4::ONE / det);
    let hit = candidate & t.cmpgt(zero) & t.cmplt(Vec4::splat(t_max));
    Lanes { hit, t, on_edge: on_edge.bitmask() }
}

/// The closest hit among the packet's triangles in `(0, t_max)`: `(t, triangle)`.
#[inline(always)]
pub fn intersect(ray: &WatertightRay4, packet: &Triangle4, t_max: f32) -> Option<(f32, u32)> {
    let lanes = test(ray, packet, t_max);
    let mut best = None;
    let mut t_max = t_max;
    let mut hit = lanes.hit.bitmask();
    if hit != 0 {
        let t = Vec4::select(lanes.hit, lanes.t, Vec4::INFINITY);
        let t_min = t.min_element();
        hit &= t.cmpeq(Vec4::splat(t_min)).bitmask();
        t_max = t_min;
        best = Some((t_min, packet.triangle[hit.trailing_zeros() as usize]));
    }
    let mut edge = lanes.on_edge;
    while edge != 0 {
        let lane = edge.trailing_zeros() as usize;
        edge &= edge - 1;
        let [a, b, c] = packet.corners(lane);
        if let Some(h) = triangle::intersect(&ray.scalar, a, b, c, t_max) {
            t_max = h.t;
            best = Some((h.t, packet.triangle[lane]));
        }
    }
    best
}

/// Whether any of the packet's triangles is hit in `(0, t_max)`.
#[inline(always)]
pub fn occluded(ray: &WatertightRay4, packet: &Triangle4, t_max: f32) -> bool {
    let lanes = test(ray, packet, t_max);
    if lanes.hit.any() {
        return true;
    }
    let mut edge = lanes.on_edge;
    while edge != 0 {
        let lane = edge.trailing_zeros() as usize;
        edge &= edge - 1;
        let [a, b, c] = packet.corners(lane);
        if triangle::intersect(&ray.scalar, a, b, c, t_max).is_some() {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::math::Ray;

    proptest! {
        /// The packet finds what the scalar test finds on each of its triangles.
        #[test]
        fn packet_equals_scalar_test(
            seeds in prop::collection::vec(prop::array::uniform9(-2i8..=2), 1..=4),
            origin in prop::array::uniform3(-3.0f32..3.0),
            dir in prop::array::uniform3(-1.0f32..1.0),
            grid in any::<bool>(),
            t_max in prop_oneof![Just(f32::INFINITY), 0.5f32..8.0],
        ) {
            // Small integer corners and origins make rays through edges and vertices common.
            let origin = if grid { Vec3::from(origin).round() } else { Vec3::from(origin) };
            let Some(w) = WatertightRay::new(&Ray::new(origin, Vec3::from(dir))) else { return Ok(()) };
            let corners: Vec<[Vec3; 3]> = seeds
                .iter()
                .map(|s| [0, 3, 6].map(|k| Vec3::new(s[k] as f32, s[k + 1] as f32, s[k + 2] as f32)))
                .collect();
            let scalar = corners
                .iter()
                .enumerate()
                .filter_map(|(i, [a, b, c])| triangle::intersect(&w, *a, *b, *c, t_max).map(|h| (h.t, i as u32)))
                .min_by(|x, y| x.0.total_cmp(&y.0));
            let packet = Triangle4::new(&corners, 0);
            let w4 = WatertightRay4::new(w);
            prop_assert_eq!(scalar.map(|s| s.0), intersect(&w4, &packet, t_max).map(|h| h.0));
            prop_assert_eq!(scalar.is_some(), occluded(&w4, &packet, t_max));
        }
    }
}

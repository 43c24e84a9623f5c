use glam::Vec3;

use super::wide::{F8, V8};

/// Moves a surface point off the surface along `n`, far enough that a ray leaving
/// from it cannot re-hit the same surface through rounding error, and no farther.
///
/// This is Wächter & Binder, "A Fast and Robust Method for Avoiding Self-Intersection"
/// (Ray Tracing Gems, ch. 6): the offset is a fixed number of ULPs of each coordinate,
/// so it scales with the magnitude of the point and works the same for a scene
/// measured in millimetres or in kilometres. Near the origin, where ULPs vanish, a
/// small absolute offset takes over. `n` need not be normalized but must point to the
/// side the new ray leaves on.
#[inline(always)]
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    let n = super::unit_or_zero(n);
    #[cfg(target_arch = "x86_64")]
    return offset_lanes(p, n);
    #[cfg(not(target_arch = "x86_64"))]
    Vec3::new(offset_axis(p.x, n.x), offset_axis(p.y, n.y), offset_axis(p.z, n.z))
}

/// [`offset_ray_origin`] for eight points side by side: lane `k` is the one point
/// `p[k]` moved along `n[k]`, bit for bit.
#[inline(always)]
pub fn offset_ray_origins(p: V8, n: V8) -> V8 {
    let n = n.normalize_or_zero();
    V8::new(offset_axes(p.x, n.x), offset_axes(p.y, n.y), offset_axes(p.z, n.z))
}

/// [`offset_axis`] in eight lanes, without branches (as [`offset_lanes`] does it), so
/// the loop compiles to vector instructions. `n` is a unit vector's component, or 0.
#[inline(always)]
fn offset_axes(p: F8, n: F8) -> F8 {
    let mut out = [0.0; 8];
    for (out, (&p, &n)) in out.iter_mut().zip(p.0.iter().zip(&n.0)) {
        // SAFETY: `n` is a unit vector's component or 0, never NaN, so |256·n| ≤ 257
        // fits an i32 (where the conversion equals the saturating `as` of the scalar
        // step); unchecked, it is one vector instruction.
        let ulps: i32 = unsafe { (INT_SCALE * n).to_int_unchecked() };
        // −ulps where p < 0: (ulps ^ m) − m with m all ones there.
        let negative = 0i32.wrapping_sub(i32::from(p < 0.0));
        let ulps = (ulps ^ negative).wrapping_sub(negative);
        let stepped = (p.to_bits() as i32).wrapping_add(ulps) as u32;
        let nudged = (p + FLOAT_SCALE * n).to_bits();
        let near_origin = 0u32.wrapping_sub(u32::from(p.abs() < ORIGIN));
        *out = f32::from_bits((nudged & near_origin) | (stepped & !near_origin));
    }
    F8(out)
}

/// Coordinates nearer the origin than this move by `FLOAT_SCALE·n`, the others by
/// `INT_SCALE·n` ULPs.
const ORIGIN: f32 = 1.0 / 32.0;
const FLOAT_SCALE: f32 = 1.0 / 65536.0;
const INT_SCALE: f32 = 256.0;

/// One coordinate `p` moved along its normal component `n` (`|n| ≤ 1`).
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline(always)]
fn offset_axis(p: f32, n: f32) -> f32 {
    if p.abs() < ORIGIN {
        return p + FLOAT_SCALE * n;
    }
    let ulps = (INT_SCALE * n) as i32;
    let ulps = if p < 0.0 { -ulps } else { ulps };
    f32::from_bits((p.to_bits() as i32).wrapping_add(ulps) as u32)
}

/// [`offset_axis`] for the three coordinates at once in SSE2 lanes, without branches:
/// the same operations, so the same bits (`|256·n| ≤ 257` truncates alike both ways).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn offset_lanes(p: Vec3, n: Vec3) -> Vec3 {
    use glam::Vec4;
    use std::arch::x86_64::*;
    let (p, n) = (__m128::from(p.extend(0.0)), __m128::from(n.extend(0.0)));
    // SAFETY: SSE2 is part of every x86-64 CPU.
    let moved = unsafe {
        let ulps = _mm_cvttps_epi32(_mm_mul_ps(_mm_set1_ps(INT_SCALE), n));
        // -ulps where p < 0: (ulps ^ m) - m with m all ones there.
        let negative = _mm_castps_si128(_mm_cmplt_ps(p, _mm_setzero_ps()));
        let ulps = _mm_sub_epi32(_mm_xor_si128(ulps, negative), negative);
        let stepped = _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(p), ulps));
        let nudged = _mm_add_ps(p, _mm_mul_ps(_mm_set1_ps(FLOAT_SCALE), n));
        let magnitude = _mm_andnot_ps(_mm_set1_ps(-0.0), p);
        let near_origin = _mm_cmplt_ps(magnitude, _mm_set1_ps(ORIGIN));
        _mm_or_ps(_mm_and_ps(near_origin, nudged), _mm_andnot_ps(near_origin, stepped))
    };
    Vec4::from(moved).truncate()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_normal_side_at_every_scale() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        for scale in [1e-6_f32, 1e-3, 1.0, 1e3, 1e6] {
            let p = Vec3::new(1.0, -2.0, 3.0) * scale;
            let q = offset_ray_origin(p, n);
            let moved = q - p;
            assert!(moved.dot(n) > 0.0, "scale {scale}: {moved:?}");
            // Never more than a tiny relative distance.
            assert!(moved.length() <= 1e-3 * p.length().max(1.0 / 32.0), "scale {scale}");
        }
    }

    #[test]
    fn lanes_move_every_coordinate_as_the_scalar_step_does() {
        // Near and far from the origin, both signs, signed zeros, the normal's extremes
        // and a NaN coordinate.
        let coordinates = [0.0, -0.0, 1e-3, -0.02, 0.03125, -0.03125, 0.5, -7.0, 3e5, -1e30, f32::NAN];
        let components = [0.0, -0.0, 1.0, -1.0, 0.999, -0.3, 1e-7, 0.5];
        #[cfg(target_arch = "x86_64")]
        for &p in &coordinates {
            for &n in &components {
                let lanes = offset_lanes(Vec3::new(p, -p, 2.0 * p), Vec3::new(n, -n, 0.5 * n));
                let scalar = [offset_axis(p, n), offset_axis(-p, -n), offset_axis(2.0 * p, 0.5 * n)];
                assert_eq!(lanes.to_array().map(f32::to_bits), scalar.map(f32::to_bits), "p {p} n {n}");
            }
        }
    }

    #[test]
    fn eight_points_move_as_each_alone() {
        let points = [0.0, -0.02, 0.5, -7.0, 3e5, -1e30, 1e-3, 2.0];
        let normals = [Vec3::Y, -Vec3::X, Vec3::new(0.3, -0.5, 0.8), Vec3::ZERO, Vec3::new(1e-7, 2.0, -3.0)];
        for (j, normal) in normals.iter().enumerate() {
            let (mut p, mut n) = (V8::default(), V8::default());
            let point = |k: usize| Vec3::new(points[k], -points[(k + j) % 8], 0.5 * points[(k + 3) % 8]);
            for k in 0..8 {
                p.set(k, point(k));
                n.set(k, *normal * (k as f32 - 3.5));
            }
            let moved = offset_ray_origins(p, n);
            for k in 0..8 {
                let alone = offset_ray_origin(point(k), *normal * (k as f32 - 3.5));
                assert_eq!(moved.get(k).to_array().map(f32::to_bits), alone.to_array().map(f32::to_bits));
            }
        }
    }
}

use glam::Vec3;

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
    let n = n.normalize_or_zero();
    #[cfg(target_arch = "x86_64")]
    return offset_lanes(p, n);
    #[cfg(not(target_arch = "x86_64"))]
    Vec3::new(offset_axis(p.x, n.x), offset_axis(p.y, n.y), offset_axis(p.z, n.z))
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
}

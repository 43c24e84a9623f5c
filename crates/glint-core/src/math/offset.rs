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
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let n = n.normalize_or_zero();
    let step = |p: f32, n: f32| -> f32 {
        if p.abs() < ORIGIN {
            return p + FLOAT_SCALE * n;
        }
        let ulps = (INT_SCALE * n) as i32;
        let ulps = if p < 0.0 { -ulps } else { ulps };
        f32::from_bits((p.to_bits() as i32).wrapping_add(ulps) as u32)
    };
    Vec3::new(step(p.x, n.x), step(p.y, n.y), step(p.z, n.z))
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
}

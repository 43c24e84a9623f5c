//! Tangent-space normal maps: the shading normal bent by a texture, as glTF, OBJ's
//! `norm` and pbrt's `normalmap` mean it.
//!
//! The tangent frame of a triangle comes from its uvs: `∂p/∂u` and `∂p/∂v`
//! ([`crate::mesh::Mesh::uv_frame`]), made orthonormal against the interpolated shading
//! normal. That is MikkTSpace's frame before it averages tangents per vertex, so maps
//! baked by MikkTSpace tools match except for a faint facet where neighbouring
//! triangles' uv frames differ.

use glam::Vec3;

/// The normal that `texel` (RGB in [0, 1], OpenGL convention: green along +v) encodes
/// in the frame `[∂p/∂u, ∂p/∂v, n]` (world space, any lengths; `n` the unit shading
/// normal), its tangential part times `scale`. Falls back to `n` where the frame is
/// degenerate or the result is not finite.
pub fn bent_normal([dpdu, dpdv, n]: [Vec3; 3], texel: Vec3, scale: f32) -> Vec3 {
    let Some(t) = (dpdu - n * n.dot(dpdu)).try_normalize() else { return n };
    // The bitangent keeps the side of ∂p/∂v: uv frames may be mirrored.
    let b = n.cross(t);
    let b = if b.dot(dpdv) < 0.0 { -b } else { b };
    let local = (2.0 * texel - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
    (t * local.x + b * local.y + n * local.z.max(0.0)).try_normalize().unwrap_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLAT: Vec3 = Vec3::new(0.5, 0.5, 1.0);

    #[test]
    fn a_flat_texel_keeps_the_normal() {
        let frame = [Vec3::new(2.0, 0.0, 0.3), Vec3::new(0.0, 0.5, 0.0), Vec3::Z];
        assert!((bent_normal(frame, FLAT, 1.0) - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn red_tilts_toward_u_and_green_toward_v_on_either_handedness() {
        let texel = Vec3::new(1.0, 0.5, 0.5); // (1, 0, 0) in tangent space, at 45° with z
        let toward_u = bent_normal([Vec3::X, Vec3::Y, Vec3::Z], texel, 1.0);
        assert!((toward_u - Vec3::X).length() < 1e-6, "{toward_u}");
        let green = Vec3::new(0.5, 0.75, 0.75);
        let up = bent_normal([Vec3::X, Vec3::Y, Vec3::Z], green, 1.0);
        assert!(up.y > 0.3 && up.z > 0.3 && up.x.abs() < 1e-6, "{up}");
        // A mirrored uv layout (v running along −y) tilts the other way in space.
        let mirrored = bent_normal([Vec3::X, Vec3::NEG_Y, Vec3::Z], green, 1.0);
        assert!((mirrored - Vec3::new(up.x, -up.y, up.z)).length() < 1e-6, "{mirrored}");
    }

    #[test]
    fn scale_bends_more_or_less_and_the_result_is_unit() {
        let texel = Vec3::new(0.75, 0.5, 0.9);
        let frame = [Vec3::X, Vec3::Y, Vec3::Z];
        let [weak, unit, strong] = [0.5, 1.0, 2.0].map(|s| bent_normal(frame, texel, s));
        assert!(weak.x < unit.x && unit.x < strong.x);
        for n in [weak, unit, strong] {
            assert!((n.length() - 1.0).abs() < 1e-6);
        }
        // A degenerate frame (∂p/∂u along the normal) keeps the normal.
        assert_eq!(bent_normal([Vec3::Z, Vec3::Y, Vec3::Z], texel, 1.0), Vec3::Z);
    }
}

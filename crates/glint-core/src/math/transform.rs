use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Mat4, Vec3};

use super::Ray;

/// An affine transform kept together with its inverse.
///
/// Named by the spaces it maps between: `world_from_object` is the lecture's `M`,
/// `object_from_world` is `M⁻¹`. Composing elementary transforms composes their exact
/// inverses too ("accumulate the composite of inverses, which are easy to take"), so
/// only a user-supplied general matrix is ever inverted numerically.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Transform {
    pub world_from_object: Mat4,
    pub object_from_world: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform { world_from_object: Mat4::IDENTITY, object_from_world: Mat4::IDENTITY };

    pub fn translate(v: Vec3) -> Self {
        Self { world_from_object: Mat4::from_translation(v), object_from_world: Mat4::from_translation(-v) }
    }

    /// Non-uniform scale; `None` when a factor is zero (the transform has no inverse).
    pub fn scale(s: Vec3) -> Option<Self> {
        (s.cmpne(Vec3::ZERO).all() && s.is_finite())
            .then(|| Self { world_from_object: Mat4::from_scale(s), object_from_world: Mat4::from_scale(s.recip()) })
    }

    /// Right-handed rotation about `axis`; `None` for a zero-length axis.
    pub fn rotate(axis: Vec3, degrees: f32) -> Option<Self> {
        let axis = axis.try_normalize()?;
        let r = Mat4::from_axis_angle(axis, degrees.to_radians());
        // A rotation's inverse is its transpose: exact, no numeric inversion.
        Some(Self { world_from_object: r, object_from_world: r.transpose() })
    }

    /// A rotation given as a unit quaternion.
    pub fn from_quat(rotation: glam::Quat) -> Self {
        let r = Mat4::from_quat(rotation);
        Self { world_from_object: r, object_from_world: r.transpose() }
    }

    /// A general affine matrix; `None` unless it is affine and invertible.
    pub fn from_matrix(m: Mat4) -> Option<Self> {
        let affine = m.row(3) == glam::Vec4::W;
        let det = m.determinant();
        (affine && det.is_finite() && det.abs() > f32::MIN_POSITIVE && m.is_finite())
            .then(|| Self { world_from_object: m, object_from_world: m.inverse() })
    }

    /// `self` applied first, then `outer`: the matrix `outer · self`.
    pub fn then(&self, outer: &Transform) -> Transform {
        Transform {
            world_from_object: outer.world_from_object * self.world_from_object,
            object_from_world: self.object_from_world * outer.object_from_world,
        }
    }

    /// The ray in object space: `P̃ = M⁻¹P`, `d̃ = M⁻¹d`, with `d̃` NOT normalized so
    /// that `t` means the same point in both spaces.
    #[inline]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray {
            origin: self.object_from_world.transform_point3(ray.origin),
            dir: self.object_from_world.transform_vector3(ray.dir),
            time: ray.time,
        }
    }

    #[inline]
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.world_from_object.transform_point3(p)
    }

    #[inline]
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.world_from_object.transform_vector3(v)
    }

    /// An object-space normal in world space: `n_world = (M₃⁻¹)ᵀ n_obj` (not normalized).
    #[inline]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        Mat3::from_mat4(self.object_from_world).transpose() * n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn composed_inverse_is_the_inverse() {
        let t = Transform::scale(Vec3::new(2.0, 0.5, 3.0))
            .unwrap()
            .then(&Transform::rotate(Vec3::new(1.0, 2.0, 3.0), 37.0).unwrap())
            .then(&Transform::translate(Vec3::new(4.0, -1.0, 2.0)));
        let product = t.world_from_object * t.object_from_world;
        assert!(product.abs_diff_eq(Mat4::IDENTITY, 1e-5), "{product:?}");
    }

    #[test]
    fn first_op_acts_on_the_object_first() {
        // Scale by 2 then move by (1,0,0): the object point (1,0,0) lands at (3,0,0).
        let t = Transform::scale(Vec3::splat(2.0)).unwrap().then(&Transform::translate(Vec3::X));
        assert_eq!(t.point_to_world(Vec3::X), Vec3::new(3.0, 0.0, 0.0));
    }

    #[test]
    fn normals_scale_opposite_to_the_surface() {
        // The lecture's example: scaling y by 2 scales the normal's y by 1/2.
        let t = Transform::scale(Vec3::new(0.5, 2.0, 1.0)).unwrap();
        let n = t.normal_to_world(Vec3::new(1.0, 1.0, 0.0));
        assert!((n - Vec3::new(2.0, 0.5, 0.0)).length() < 1e-6);
        // It stays perpendicular to transformed tangents.
        let tangent = t.vector_to_world(Vec3::new(1.0, -1.0, 0.0));
        assert!(n.dot(tangent).abs() < 1e-6);
    }

    #[test]
    fn singular_transforms_are_rejected() {
        assert!(Transform::scale(Vec3::new(1.0, 0.0, 1.0)).is_none());
        assert!(Transform::rotate(Vec3::ZERO, 10.0).is_none());
        assert!(Transform::from_matrix(Mat4::ZERO).is_none());
        let projective = Mat4::from_cols_array(&[1.0, 0., 0., 0.5, 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.]);
        assert!(Transform::from_matrix(projective).is_none());
    }
}

//! Moving instances for motion blur: a pose at shutter open and one at shutter close,
//! interpolated at each ray's time.

use bytemuck::NoUninit;
use glam::{Mat4, Quat, Vec3};

use crate::math::{Aabb, Transform};

/// Marks an instance that does not move.
pub const NO_MOTION: u32 = u32::MAX;

/// A pose decomposed into scale, rotation and translation, so that it interpolates
/// without shearing (rotation by slerp, the rest linearly).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Pose {
    pub rotation: Quat,
    pub translation: Vec3,
    pub _pad0: f32,
    pub scale: Vec3,
    pub _pad1: f32,
}

impl Pose {
    /// Decomposes `m`; `None` when it shears (a shear has no meaningful in-between).
    pub fn from_transform(t: &Transform) -> Option<Self> {
        let (scale, rotation, translation) = t.world_from_object.to_scale_rotation_translation();
        let rebuilt = Mat4::from_scale_rotation_translation(scale, rotation, translation);
        let tolerance = 1e-4 * t.world_from_object.to_cols_array().iter().fold(1.0f32, |m, v| m.max(v.abs()));
        (rebuilt.abs_diff_eq(t.world_from_object, tolerance) && scale.cmpne(Vec3::ZERO).all()).then_some(Self {
            rotation,
            translation,
            _pad0: 0.0,
            scale,
            _pad1: 0.0,
        })
    }
}

/// How one instance moves: `M(τ) = outer · pose(τ) · inner`, where `inner` places the
/// shape inside the moving node and `outer` places the moving node in the world.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Motion {
    pub inner: Transform,
    pub outer: Transform,
    pub open: Pose,
    pub close: Pose,
}

impl Motion {
    /// The instance's transform at `time` in [0, 1]; inverses stay exact by composing
    /// the inverses of the interpolated parts.
    pub fn at(&self, time: f32) -> Transform {
        let scale = self.open.scale.lerp(self.close.scale, time);
        let rotation = self.open.rotation.slerp(self.close.rotation, time);
        let translation = self.open.translation.lerp(self.close.translation, time);
        // Compile refuses scales that change sign, so the lerped scale is never zero.
        let scale = Transform::scale(scale).unwrap_or_default();
        let pose = scale.then(&Transform::from_quat(rotation)).then(&Transform::translate(translation));
        self.inner.then(&pose).then(&self.outer)
    }

    /// World bounds of `object_bounds` over the whole shutter interval: the union of
    /// the boxes at 17 times, grown by the most a rotating point can bulge out of the
    /// chord between two of them, `R·(1 − cos(Δθ/2))`.
    pub fn bounds(&self, object_bounds: &Aabb) -> Aabb {
        const STEPS: usize = 16;
        let union = (0..=STEPS)
            .map(|i| object_bounds.transformed(&self.at(i as f32 / STEPS as f32).world_from_object))
            .fold(Aabb::EMPTY, Aabb::union);
        let step_angle = self.open.rotation.angle_between(self.close.rotation) / STEPS as f32;
        let bulge = union.extent().length() * (1.0 - (0.5 * step_angle).cos());
        Aabb::new(union.min - Vec3::splat(bulge), union.max + Vec3::splat(bulge))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(open: Transform, close: Transform) -> Motion {
        Motion {
            inner: Transform::IDENTITY,
            outer: Transform::IDENTITY,
            open: Pose::from_transform(&open).unwrap(),
            close: Pose::from_transform(&close).unwrap(),
        }
    }

    #[test]
    fn ends_reproduce_the_poses_and_the_middle_interpolates() {
        let open = Transform::translate(Vec3::X);
        let close = Transform::rotate(Vec3::Y, 90.0).unwrap().then(&Transform::translate(Vec3::new(3.0, 0.0, 0.0)));
        let m = motion(open, close);
        assert!(m.at(0.0).world_from_object.abs_diff_eq(open.world_from_object, 1e-5));
        assert!(m.at(1.0).world_from_object.abs_diff_eq(close.world_from_object, 1e-5));
        let mid = m.at(0.5);
        assert!((mid.point_to_world(Vec3::ZERO) - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-5);
        assert!(mid.world_from_object.mul_mat4(&mid.object_from_world).abs_diff_eq(Mat4::IDENTITY, 1e-5));
    }

    #[test]
    fn bounds_contain_the_object_at_every_time() {
        let m = motion(
            Transform::IDENTITY,
            Transform::rotate(Vec3::Z, 170.0).unwrap().then(&Transform::translate(Vec3::X)),
        );
        let unit = Aabb::new(Vec3::new(1.0, -0.1, -0.1), Vec3::new(2.0, 0.1, 0.1));
        let swept = m.bounds(&unit);
        for i in 0..=1000 {
            let b = unit.transformed(&m.at(i as f32 / 1000.0).world_from_object);
            assert!(b.min.cmpge(swept.min).all() && b.max.cmple(swept.max).all(), "t = {}", i as f32 / 1000.0);
        }
    }

    #[test]
    fn shear_cannot_be_animated() {
        let shear = Transform::from_matrix(Mat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]))
        .unwrap();
        assert!(Pose::from_transform(&shear).is_none());
    }
}

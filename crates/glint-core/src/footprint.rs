//! How much of a surface one pixel covers where a ray lands: the steps in position (and,
//! through the shape, in uv) to the neighbouring pixels, which a texture averages over so
//! that a pattern finer than the pixels (a checkered floor at the horizon) shows its mean
//! instead of moiré, at one sample per pixel.
//!
//! The footprint is pbrt-v4's camera approximation (Pharr, Jakob & Humphreys, 4th ed.,
//! §10.1.1): however a path reached a point, the point is measured as if the camera saw
//! it directly. The rays through the next pixel across and the next pixel down meet the
//! point's tangent plane; the offsets to those meeting points are `∂p/∂x` and `∂p/∂y`.
//! That is exact for camera rays, an estimate after mirrors and glass, and needs no state
//! carried along the ray, so the GPU computes the same from the same two vectors.

use glam::Vec3;

use crate::camera::Camera;

/// One pixel's step across and down the film, as world vectors for a direction whose
/// component along the look axis is 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelSpacing {
    pub eye: Vec3,
    pub forward: Vec3,
    pub dx: Vec3,
    pub dy: Vec3,
}

/// The footprint, as a fraction of a pixel, for `spp` samples per pixel: with more
/// samples each covers less of the pixel, so, as pbrt-v4 does, it shrinks by `1/√spp`,
/// never below an eighth.
pub fn footprint_scale(spp: u32) -> f32 {
    (1.0 / (spp.max(1) as f32).sqrt()).max(0.125)
}

impl PixelSpacing {
    /// For `camera` on a `width`×`height` film, a footprint `scale` pixels across (see
    /// [`footprint_scale`]).
    #[inline]
    pub fn new(camera: &Camera, width: u32, height: u32, scale: f32) -> Self {
        let m = camera.world_from_canonical;
        Self {
            eye: camera.eye,
            forward: camera.forward,
            // The film spans [−1, 1] along each axis: a pixel is 2/width of it across.
            dx: m.x_axis.truncate() * (2.0 * scale / width.max(1) as f32),
            dy: m.y_axis.truncate() * (2.0 * scale / height.max(1) as f32),
        }
    }

    /// `[∂p/∂x, ∂p/∂y]` at `p` on a surface of normal `n`: where the rays through the
    /// neighbouring pixels meet the plane through `p`, less `p`. `None` where the
    /// footprint is unbounded: `p` behind the eye, or a neighbouring ray parallel to the
    /// plane or leaving it (a floor at the horizon).
    #[inline]
    pub fn surface_steps(&self, p: Vec3, n: Vec3) -> Option<[Vec3; 2]> {
        let d = p - self.eye;
        let along = d.dot(self.forward);
        if along.is_nan() || along <= 0.0 {
            return None;
        }
        let d_n = d.dot(n);
        let step = |offset: Vec3| {
            let dir = d + along * offset;
            let t = d_n / dir.dot(n);
            let step = t * dir - d;
            (t > 0.0 && step.is_finite()).then_some(step)
        };
        Some([step(self.dx)?, step(self.dy)?])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::desc::CameraDesc;

    fn looking_down(height: f32) -> Camera {
        let desc = CameraDesc {
            eye: Vec3::new(0.0, height, 0.0),
            look: Vec3::NEG_Y,
            up: Vec3::NEG_Z,
            fov_y_degrees: 90.0,
            ..Default::default()
        };
        Camera::new(&desc, 1.0).unwrap()
    }

    #[test]
    fn a_floor_seen_straight_down_steps_one_pixel_width_of_the_view() {
        // 90° over 100 pixels at height 3: the view is 6 units wide, a pixel 0.06.
        let spacing = PixelSpacing::new(&looking_down(3.0), 100, 100, 1.0);
        let [dx, dy] = spacing.surface_steps(Vec3::ZERO, Vec3::Y).unwrap();
        assert!((dx - Vec3::new(0.06, 0.0, 0.0)).length() < 1e-6, "{dx}");
        assert!((dy.length() - 0.06).abs() < 1e-6 && dy.y.abs() < 1e-7, "{dy}");
        // Four samples a pixel halve it; sixty-four stop at an eighth.
        let [dx4, _] = PixelSpacing::new(&looking_down(3.0), 100, 100, footprint_scale(4))
            .surface_steps(Vec3::ZERO, Vec3::Y)
            .unwrap();
        assert!((dx4.length() - 0.03).abs() < 1e-6);
        let [dx_many, _] = PixelSpacing::new(&looking_down(3.0), 100, 100, footprint_scale(1000))
            .surface_steps(Vec3::ZERO, Vec3::Y)
            .unwrap();
        assert!((dx_many.length() - 0.06 / 8.0).abs() < 1e-6);
    }

    #[test]
    fn a_tilted_plane_stretches_the_step_by_one_over_the_cosine() {
        // The point on the axis, the plane turned 60° about x: the step down the film
        // (along z on the plane) grows by 1/cos 60° = 2, the step across does not.
        let spacing = PixelSpacing::new(&looking_down(3.0), 1000, 1000, 1.0);
        let n = Vec3::new(0.0, 60f32.to_radians().cos(), 60f32.to_radians().sin());
        let [dx, dy] = spacing.surface_steps(Vec3::ZERO, n).unwrap();
        assert!((dx.length() - 0.006).abs() < 1e-5, "{dx}");
        assert!((dy.length() - 0.012).abs() < 1e-4, "{dy}");
        assert!(dx.dot(n).abs() < 1e-6 && dy.dot(n).abs() < 1e-6, "the steps lie in the plane");
    }

    #[test]
    fn the_footprint_is_unbounded_at_the_horizon_and_behind_the_eye() {
        let spacing = PixelSpacing::new(&looking_down(3.0), 100, 100, 1.0);
        // A plane containing the view ray: the neighbours never meet it.
        assert_eq!(spacing.surface_steps(Vec3::ZERO, Vec3::X), None);
        assert_eq!(spacing.surface_steps(Vec3::new(0.0, 5.0, 0.0), Vec3::Y), None);
    }
}

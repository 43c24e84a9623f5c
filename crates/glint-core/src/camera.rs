//! The lecture's camera: primary rays through points on the film plane.

use glam::{Mat4, Vec2, Vec3};

use crate::bsdf::lobes::concentric_disk;
use crate::desc::CameraDesc;
use crate::math::Ray;

/// A pinhole camera holding the inverse of the normalizing transformation.
///
/// The normalizing transformation maps world space to the canonical frustum (eye at the
/// origin, looking down −z, view angles scaled to 45°, far plane z = −1). A film point
/// `(x, y, −1)` with x, y ∈ [−1, 1] is taken back to world space by its inverse,
/// `world_from_canonical`, and the ray runs from the eye through it. The far distance
/// is irrelevant to directions, so the frustum is built with far = 1.
///
/// With an open aperture it is a thin lens (Cook, Porter & Carpenter 1984): rays leave
/// from a point on a lens disk around the eye and pass through the point of the pinhole
/// ray that lies on the plane of focus, so only that plane is sharp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub world_from_canonical: Mat4,
    /// Unit camera axes: right (u), up (v), and the look direction (−w).
    pub right: Vec3,
    pub up: Vec3,
    pub forward: Vec3,
    pub aperture_radius: f32,
    pub focal_distance: f32,
}

impl Camera {
    /// `None` when look or up is zero or the two are parallel.
    pub fn new(desc: &CameraDesc, aspect: f32) -> Option<Self> {
        let w = (-desc.look).try_normalize()?;
        let u = desc.up.cross(w).try_normalize()?;
        let v = w.cross(u);
        let tan_y = desc.fov_axis.tan_half_vertical(desc.fov_y_degrees, aspect);
        let tan_x = tan_y * aspect;
        let rotate = Mat4::from_cols(u.extend(0.0), v.extend(0.0), w.extend(0.0), glam::Vec4::W);
        let unscale = Mat4::from_scale(Vec3::new(tan_x, tan_y, 1.0));
        let world_from_canonical = Mat4::from_translation(desc.eye) * rotate * unscale;
        Some(Self {
            eye: desc.eye,
            world_from_canonical,
            right: u,
            up: v,
            forward: -w,
            aperture_radius: desc.aperture_radius,
            focal_distance: desc.focal_distance,
        })
    }

    /// The primary ray through film point `(x, y)` in [−1, 1]² (+y up), unit direction;
    /// `lens` in [0, 1)² picks the point on the lens (ignored by a pinhole). The
    /// pinhole's ray is always inlined (into the AVX2 tiles, with the camera samples'
    /// loop); a lens's is a call.
    #[inline(always)]
    pub fn ray(&self, x: f32, y: f32, lens: Vec2) -> Ray {
        let film_point = self.world_from_canonical.transform_point3(Vec3::new(x, y, -1.0));
        let pinhole = Ray::new(self.eye, (film_point - self.eye).normalize());
        if self.aperture_radius <= 0.0 {
            return pinhole;
        }
        self.through_lens(&pinhole, lens)
    }

    /// The pinhole's unit directions through the film points `(x[k], y[k])` (as
    /// [`Camera::ray`] takes them), worked out side by side: bit for bit the directions
    /// `ray` gives one at a time without a lens, for a wave of camera rays that then
    /// waits on one vector square root and division rather than `N` in a row.
    #[inline(always)]
    pub fn pinhole_directions<const N: usize>(&self, x: &[f32; N], y: &[f32; N]) -> [[f32; N]; 3] {
        let m = &self.world_from_canonical;
        let mut dir = [[0.0; N]; 3];
        for (axis, dir) in dir.iter_mut().enumerate() {
            // The film point's coordinate, summed in the order `transform_point3` sums
            // it (z = −1: its column times −1 is its negation, exactly), less the eye's.
            let (cx, cy, cz, cw) = (m.x_axis[axis], m.y_axis[axis], m.z_axis[axis], m.w_axis[axis]);
            for ((d, &x), &y) in dir.iter_mut().zip(x).zip(y) {
                *d = (cx * x + cy * y - cz + cw) - self.eye[axis];
            }
        }
        for k in 0..N {
            let [dx, dy, dz] = [dir[0][k], dir[1][k], dir[2][k]];
            let reciprocal = 1.0 / (dx * dx + dy * dy + dz * dz).sqrt();
            for axis in &mut dir {
                axis[k] *= reciprocal;
            }
        }
        dir
    }

    /// The ray from lens point `lens` to where `pinhole` meets the plane of focus.
    #[inline(never)]
    fn through_lens(&self, pinhole: &Ray, lens: Vec2) -> Ray {
        // The pinhole ray meets the plane of focus at distance f along the look axis.
        let focus = pinhole.at(self.focal_distance / pinhole.dir.dot(self.forward));
        let on_lens = self.aperture_radius * concentric_disk(lens);
        let origin = self.eye + on_lens.x * self.right + on_lens.y * self.up;
        Ray::new(origin, (focus - origin).normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pinhole_directions_in_lanes_are_the_rays_directions_bit_for_bit() {
        let desc = CameraDesc {
            eye: Vec3::new(0.3, 1.7, -4.2),
            look: Vec3::new(0.2, -0.4, 1.0),
            up: Vec3::new(0.1, 1.0, 0.0),
            fov_y_degrees: 37.0,
            ..Default::default()
        };
        let cam = Camera::new(&desc, 4.0 / 3.0).unwrap();
        let mut rng = crate::sampling::Rng::new(11);
        for _ in 0..2_000 {
            let x: [f32; 8] = std::array::from_fn(|_| 2.0 * rng.next_f32() - 1.0);
            let y: [f32; 8] = std::array::from_fn(|_| 2.0 * rng.next_f32() - 1.0);
            let lanes = cam.pinhole_directions(&x, &y);
            for k in 0..8 {
                let one = cam.ray(x[k], y[k], Vec2::ZERO).dir;
                let lane = Vec3::new(lanes[0][k], lanes[1][k], lanes[2][k]);
                assert_eq!(
                    one.to_array().map(f32::to_bits),
                    lane.to_array().map(f32::to_bits),
                    "at ({}, {})",
                    x[k],
                    y[k]
                );
            }
        }
    }

    #[test]
    fn centre_ray_looks_along_look_and_corners_span_the_view_angle() {
        let desc = CameraDesc {
            eye: Vec3::new(1.0, 2.0, 3.0),
            look: Vec3::new(0.0, 0.0, -2.0),
            up: Vec3::Y,
            fov_y_degrees: 90.0,
            ..Default::default()
        };
        let cam = Camera::new(&desc, 2.0).unwrap();
        let centre = cam.ray(0.0, 0.0, Vec2::ZERO);
        assert_eq!(centre.origin, desc.eye);
        assert!((centre.dir - Vec3::NEG_Z).length() < 1e-6);
        // Top edge: 45° up from the axis for a 90° vertical angle.
        let top = cam.ray(0.0, 1.0, Vec2::ZERO).dir;
        assert!((top.angle_between(Vec3::NEG_Z).to_degrees() - 45.0).abs() < 1e-3);
        assert!(top.y > 0.0);
        // Right edge: atan(2·tan 45°) for aspect 2.
        let right = cam.ray(1.0, 0.0, Vec2::ZERO).dir;
        assert!((right.angle_between(Vec3::NEG_Z) - 2.0f32.atan()).abs() < 1e-5);
        assert!(right.x > 0.0);
    }

    #[test]
    fn thin_lens_rays_converge_on_the_focal_plane() {
        let desc = CameraDesc { aperture_radius: 0.5, focal_distance: 7.0, ..Default::default() };
        let cam = Camera::new(&desc, 1.5).unwrap();
        for (x, y) in [(0.0, 0.0), (0.6, -0.3), (-1.0, 1.0)] {
            let pinhole = Camera { aperture_radius: 0.0, ..cam }.ray(x, y, Vec2::ZERO);
            let sharp = pinhole.at(7.0 / pinhole.dir.dot(cam.forward));
            for lens in [Vec2::new(0.1, 0.9), Vec2::new(0.8, 0.2), Vec2::splat(0.5)] {
                let r = cam.ray(x, y, lens);
                assert!((r.origin - cam.eye).length() <= 0.5 + 1e-5);
                // Every lens ray passes through the same in-focus point.
                let t = (sharp - r.origin).dot(r.dir);
                assert!((r.at(t) - sharp).length() < 1e-4, "{x},{y} {lens}");
            }
        }
    }

    #[test]
    fn view_angles_along_every_axis_span_that_extent() {
        use crate::desc::FovAxis;
        let angle = |axis, aspect: f32| {
            let desc = CameraDesc { fov_y_degrees: 60.0, fov_axis: axis, ..Default::default() };
            let cam = Camera::new(&desc, aspect).unwrap();
            let (right, top) = (cam.ray(1.0, 0.0, Vec2::ZERO).dir, cam.ray(0.0, 1.0, Vec2::ZERO).dir);
            let corner = cam.ray(1.0, 1.0, Vec2::ZERO).dir;
            let deg = |d: Vec3| 2.0 * d.angle_between(cam.forward).to_degrees();
            (deg(right), deg(top), deg(corner))
        };
        let close = |a: f32, b: f32| (a - b).abs() < 1e-3;
        assert!(close(angle(FovAxis::Y, 2.0).1, 60.0));
        assert!(close(angle(FovAxis::X, 2.0).0, 60.0));
        assert!(close(angle(FovAxis::Diagonal, 2.0).2, 60.0));
        assert!(close(angle(FovAxis::Smaller, 2.0).1, 60.0) && close(angle(FovAxis::Smaller, 0.5).0, 60.0));
        assert!(close(angle(FovAxis::Larger, 2.0).0, 60.0) && close(angle(FovAxis::Larger, 0.5).1, 60.0));
    }

    #[test]
    fn degenerate_cameras_are_rejected() {
        let parallel = CameraDesc { up: Vec3::new(0.0, 0.0, 1.0), look: Vec3::Z, ..Default::default() };
        assert!(Camera::new(&parallel, 1.0).is_none());
        let zero = CameraDesc { look: Vec3::ZERO, ..Default::default() };
        assert!(Camera::new(&zero, 1.0).is_none());
    }
}

//! The viewer's camera as an eye circling a target: orbit, pan, zoom and fly move it,
//! and the scene file's camera stays behind as the place to return to.

use glam::{Quat, Vec3};
use glint_core::desc::CameraDesc;
use glint_core::math::Aabb;

/// Nearest the eye may come to the target, and to the poles of `up` when orbiting
/// (radians), so the basis never degenerates.
const MIN_DISTANCE: f32 = 1e-3;
const POLE_MARGIN: f32 = 0.01;

/// A look-at camera: the eye looks at `target`, `up` fixes the roll.
#[derive(Clone, Debug, PartialEq)]
pub struct OrbitCamera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Full view angle in degrees along the scene's `fov_axis`.
    pub fov_degrees: f32,
}

impl OrbitCamera {
    /// The scene's camera, orbiting the centre of what it holds (projected onto the
    /// line of sight, so the view does not jump) or a point 1 unit ahead when the
    /// scene is empty or behind the eye.
    pub fn from_desc(desc: &CameraDesc, bounds: &Aabb) -> Self {
        let forward = desc.look.try_normalize().unwrap_or(Vec3::NEG_Z);
        let depth = if bounds.min.cmple(bounds.max).all() { (centre(bounds) - desc.eye).dot(forward) } else { 0.0 };
        let distance = if depth > MIN_DISTANCE { depth } else { desc.look.length().max(1.0) };
        Self {
            eye: desc.eye,
            target: desc.eye + forward * distance,
            up: desc.up.try_normalize().unwrap_or(Vec3::Y),
            fov_degrees: desc.fov_y_degrees,
        }
    }

    /// `base` (lens, fov axis) looking as this camera looks.
    pub fn to_desc(&self, base: &CameraDesc) -> CameraDesc {
        CameraDesc {
            eye: self.eye,
            look: self.target - self.eye,
            up: self.up,
            fov_y_degrees: self.fov_degrees,
            ..*base
        }
    }

    /// How far the eye is from the target.
    pub fn distance(&self) -> f32 {
        self.eye.distance(self.target)
    }

    /// Unit direction of sight.
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye).normalize_or(Vec3::NEG_Z)
    }

    /// Unit film axis to the right, `forward × up`.
    pub fn right(&self) -> Vec3 {
        self.forward().cross(self.up).normalize_or(Vec3::X)
    }

    /// Unit film axis upward (`right × forward`).
    pub fn film_up(&self) -> Vec3 {
        self.right().cross(self.forward())
    }

    /// Turns the eye about the target: `yaw` radians about `up`, then `pitch` radians
    /// toward `up` (positive raises the eye), stopping short of the poles.
    pub fn orbit(&mut self, yaw: f32, pitch: f32) {
        let offset = Quat::from_axis_angle(self.up, yaw) * (self.eye - self.target);
        let polar = offset.angle_between(self.up);
        let turned = (polar - pitch).clamp(POLE_MARGIN, std::f32::consts::PI - POLE_MARGIN);
        let axis = offset.cross(self.up).normalize_or(self.right());
        // Rotating about `offset × up` by a positive angle swings the offset toward up.
        self.eye = self.target + Quat::from_axis_angle(axis, polar - turned) * offset;
    }

    /// Slides eye and target together along the film axes (world units).
    pub fn pan(&mut self, right: f32, up: f32) {
        let shift = self.right() * right + self.film_up() * up;
        self.eye += shift;
        self.target += shift;
    }

    /// Moves the eye toward the target: the distance is multiplied by `factor`.
    pub fn zoom(&mut self, factor: f32) {
        let distance = (self.distance() * factor).max(MIN_DISTANCE);
        self.eye = self.target - self.forward() * distance;
    }

    /// Moves eye and target together: `step` in world units along right, film up and
    /// forward (x, y, z).
    pub fn fly(&mut self, step: Vec3) {
        let shift = self.right() * step.x + self.film_up() * step.y + self.forward() * step.z;
        self.eye += shift;
        self.target += shift;
    }

    /// Looks at the centre of `bounds` from the current direction, just far enough that
    /// its bounding sphere fits the narrower view angle (`tan_half` of it).
    pub fn frame(&mut self, bounds: &Aabb, tan_half: f32) {
        if !bounds.min.cmple(bounds.max).all() {
            return;
        }
        let radius = (0.5 * (bounds.max - bounds.min).length()).max(MIN_DISTANCE);
        let forward = self.forward();
        self.target = centre(bounds);
        // A sphere of radius r fits a half-angle θ from distance r / sin θ.
        let sin_half = tan_half / (1.0 + tan_half * tan_half).sqrt();
        self.eye = self.target - forward * (1.05 * radius / sin_half.max(1e-3));
    }

    /// Height of the film at the target's distance: how many world units a drag across
    /// the whole window moves the scene when panning.
    pub fn film_height_at_target(&self, tan_half_vertical: f32) -> f32 {
        2.0 * self.distance() * tan_half_vertical
    }
}

/// The centre of a box.
pub fn centre(bounds: &Aabb) -> Vec3 {
    0.5 * (bounds.min + bounds.max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn looking_down_z() -> OrbitCamera {
        OrbitCamera { eye: Vec3::new(0.0, 0.0, 5.0), target: Vec3::ZERO, up: Vec3::Y, fov_degrees: 40.0 }
    }

    #[test]
    fn yaw_of_a_quarter_turn_moves_the_eye_round_the_target_keeping_its_distance() {
        let mut camera = looking_down_z();
        camera.orbit(std::f32::consts::FRAC_PI_2, 0.0);
        assert!(camera.eye.distance(Vec3::new(5.0, 0.0, 0.0)) < 1e-4, "{}", camera.eye);
        assert_eq!(camera.target, Vec3::ZERO);
    }

    #[test]
    fn positive_pitch_raises_the_eye_and_stops_before_the_pole() {
        let mut camera = looking_down_z();
        camera.orbit(0.0, 0.5);
        assert!(camera.eye.y > 0.0 && (camera.distance() - 5.0).abs() < 1e-4, "{}", camera.eye);
        camera.orbit(0.0, 10.0);
        assert!(camera.eye.angle_between(Vec3::Y) >= POLE_MARGIN * 0.99);
        assert!(camera.right().is_finite());
    }

    #[test]
    fn pan_moves_eye_and_target_together_and_zoom_keeps_the_target() {
        let mut camera = looking_down_z();
        camera.pan(1.0, 2.0);
        assert!(camera.eye.distance(Vec3::new(1.0, 2.0, 5.0)) < 1e-5);
        assert!(camera.target.distance(Vec3::new(1.0, 2.0, 0.0)) < 1e-5);
        camera.zoom(0.5);
        assert!((camera.distance() - 2.5).abs() < 1e-5);
    }

    #[test]
    fn framing_a_box_puts_its_centre_ahead_and_its_sphere_inside_the_view() {
        let mut camera = looking_down_z();
        let bounds = Aabb::new(Vec3::new(9.0, -1.0, -1.0), Vec3::new(11.0, 1.0, 1.0));
        camera.frame(&bounds, 0.5);
        assert_eq!(camera.target, Vec3::new(10.0, 0.0, 0.0));
        let radius = 3f32.sqrt();
        assert!(radius / camera.distance() <= 0.5 / (1.25f32).sqrt() + 1e-4);
    }
}

//! What a glTF node carries besides meshes: cameras, and the lights of
//! `KHR_lights_punctual`. Both look down the node's −z axis with +y up.
//!
//! Light intensities are taken as glint's intensities, unscaled (candela for point and
//! spot lights, lux for directional ones, as three.js and Filament take them without an
//! exposure), falling off with the inverse square of the distance; `range` is ignored.

use glam::{Mat4, Vec3};
use glint_core::desc::{CameraDesc, LightDesc, SpotFalloff};

use super::State;

impl State<'_> {
    /// Adds the node's camera to the file's cameras (perspective ones; the first is used).
    pub(super) fn camera(&mut self, camera: &gltf::Camera, world: Mat4) {
        let gltf::camera::Projection::Perspective(perspective) = camera.projection() else {
            self.warn(format!("camera {} is orthographic; glint frames the model with its own camera", camera.index()));
            return;
        };
        let fov_y_degrees = perspective.yfov().to_degrees();
        if !(fov_y_degrees.is_finite() && fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
            self.warn(format!("camera {} has a view angle of {fov_y_degrees}°; it is left out", camera.index()));
            return;
        }
        let eye = world.transform_point3(Vec3::ZERO);
        let look = world.transform_vector3(Vec3::NEG_Z);
        let up = world.transform_vector3(Vec3::Y);
        self.import.cameras.push(CameraDesc { eye, look, up, fov_y_degrees, ..Default::default() });
        if self.import.cameras.len() == 1 {
            self.import.aspect_ratio = perspective.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0);
        }
    }

    /// Adds the node's light, placed and aimed by its transform.
    pub(super) fn light(&mut self, light: &gltf::khr_lights_punctual::Light, world: Mat4) {
        use gltf::khr_lights_punctual::Kind;
        let color = Vec3::from(light.color()) * light.intensity();
        if !color.is_finite() || color.min_element() < 0.0 {
            self.warn(format!(
                "light {} has an intensity that is not a finite positive number; it is left out",
                light.index()
            ));
            return;
        }
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z);
        let inverse_square = Vec3::new(0.0, 0.0, 1.0);
        let desc = match light.kind() {
            Kind::Point => LightDesc::Point { position, color, attenuation: inverse_square },
            Kind::Directional => LightDesc::Directional { direction, color },
            Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                let outer = outer_cone_angle.to_degrees();
                LightDesc::Spot {
                    position,
                    direction,
                    color,
                    attenuation: inverse_square,
                    angle_degrees: outer,
                    // max/min, not clamp: a negative or NaN angle must not panic.
                    penumbra_degrees: (outer - inner_cone_angle.to_degrees()).max(0.0).min(outer),
                    falloff: SpotFalloff::default(),
                }
            }
        };
        self.import.lights.push(desc);
    }
}

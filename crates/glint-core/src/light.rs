//! Light sources: point (with the lecture's distance attenuation), directional and spot.

use bytemuck::NoUninit;
use glam::Vec3;

use crate::desc::LightDesc;

/// What a [`Light`] record is.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum LightKind {
    Point = 0,
    Directional = 1,
    Spot = 2,
}

/// A light as flat data.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Light {
    pub kind: LightKind,
    /// `L_p`, the intensity per colour channel.
    pub color: Vec3,
    pub position: Vec3,
    /// Unit direction the light travels (directional) or its axis (spot).
    pub direction: Vec3,
    /// `(c1, c2, c3)` of `f_att = min(1, 1/(c1 + c2·d + c3·d²))`.
    pub attenuation: Vec3,
    /// Spot: angle from the axis where the falloff begins, radians.
    pub inner_angle: f32,
    /// Spot: angle from the axis where the light ends, radians.
    pub outer_angle: f32,
}

/// What a surface point receives from one light before shadowing.
#[derive(Clone, Copy, Debug)]
pub struct Incidence {
    /// Unit vector from the surface toward the light (the lecture's `l`).
    pub to_light: Vec3,
    /// Distance to the light (infinite for directional lights).
    pub distance: f32,
    /// `f_att · L`, including a spot light's cone falloff.
    pub radiance: Vec3,
}

impl Light {
    pub fn compile(desc: &LightDesc) -> Self {
        let base = Self {
            kind: LightKind::Point,
            color: Vec3::ZERO,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            attenuation: Vec3::X,
            inner_angle: 0.0,
            outer_angle: 0.0,
        };
        match *desc {
            LightDesc::Point { position, color, attenuation } => Self { position, color, attenuation, ..base },
            LightDesc::Directional { direction, color } => {
                Self { kind: LightKind::Directional, direction: direction.normalize(), color, ..base }
            }
            LightDesc::Spot { position, direction, color, attenuation, angle_degrees, penumbra_degrees } => {
                let outer = angle_degrees.to_radians();
                Self {
                    kind: LightKind::Spot,
                    position,
                    direction: direction.normalize(),
                    color,
                    attenuation,
                    outer_angle: outer,
                    inner_angle: (outer - penumbra_degrees.to_radians()).max(0.0),
                }
            }
        }
    }

    /// Direction, distance and unshadowed intensity of this light at `p`.
    pub fn incidence(&self, p: Vec3) -> Incidence {
        if self.kind == LightKind::Directional {
            return Incidence { to_light: -self.direction, distance: f32::INFINITY, radiance: self.color };
        }
        let offset = self.position - p;
        let distance = offset.length();
        let to_light = offset / distance;
        let [c1, c2, c3] = self.attenuation.to_array();
        let f_att = (1.0 / (c1 + c2 * distance + c3 * distance * distance)).min(1.0);
        let cone = if self.kind == LightKind::Spot { self.spot_falloff(-to_light) } else { 1.0 };
        Incidence { to_light, distance, radiance: f_att * cone * self.color }
    }

    /// 1 inside the inner cone, 0 outside the outer one, and the smooth cubic
    /// `1 − (3x² − 2x³)` in between, where x runs 0→1 across the penumbra.
    fn spot_falloff(&self, from_light: Vec3) -> f32 {
        let angle = from_light.dot(self.direction).clamp(-1.0, 1.0).acos();
        if angle <= self.inner_angle {
            return 1.0;
        }
        if angle >= self.outer_angle {
            return 0.0;
        }
        let x = (angle - self.inner_angle) / (self.outer_angle - self.inner_angle);
        1.0 - x * x * (3.0 - 2.0 * x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attenuation_follows_the_lecture_formula_and_is_capped_at_one() {
        let light = Light::compile(&LightDesc::Point {
            position: Vec3::ZERO,
            color: Vec3::ONE,
            attenuation: Vec3::new(0.5, 0.25, 0.125),
        });
        let at = |d: f32| light.incidence(Vec3::new(d, 0.0, 0.0)).radiance.x;
        assert_eq!(at(0.1), 1.0); // 1/(0.5+0.025+0.00125) > 1 → capped
        assert!((at(4.0) - 1.0 / (0.5 + 1.0 + 2.0)).abs() < 1e-6);
        assert!((light.incidence(Vec3::new(0.0, 3.0, 4.0)).distance - 5.0).abs() < 1e-6);
    }

    #[test]
    fn spot_is_full_inside_zero_outside_and_smooth_between() {
        let light = Light::compile(&LightDesc::Spot {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            attenuation: Vec3::X,
            angle_degrees: 30.0,
            penumbra_degrees: 10.0,
        });
        let at_angle = |deg: f32| {
            let a = deg.to_radians();
            light.incidence(Vec3::new(a.sin(), -a.cos(), 0.0)).radiance.x
        };
        assert_eq!(at_angle(0.0), 1.0);
        assert_eq!(at_angle(19.0), 1.0);
        assert!((at_angle(25.0) - 0.5).abs() < 1e-3);
        assert_eq!(at_angle(31.0), 0.0);
        assert!(at_angle(22.0) > at_angle(24.0) && at_angle(24.0) > at_angle(28.0));
    }
}

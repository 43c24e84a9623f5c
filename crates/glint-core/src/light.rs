//! Light sources: point (with the lecture's distance attenuation), directional and spot.

use bytemuck::NoUninit;
use glam::{Vec2, Vec3};

use crate::desc::{AreaShape, LightDesc};

/// What a [`Light`] record is.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum LightKind {
    Point = 0,
    Directional = 1,
    Spot = 2,
    /// Area lights: a parallelogram, a disk, a sphere.
    Rectangle = 3,
    Disk = 4,
    Sphere = 5,
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
    /// Rectangle: the two edges from `position` (its corner).
    pub edge_u: Vec3,
    pub edge_v: Vec3,
    /// Disk and sphere: the radius (`position` is the centre, `direction` the disk's normal).
    pub radius: f32,
    /// Area lights: samples along each axis of the stratified pattern.
    pub samples_per_axis: u32,
    /// Spot: 1 when the penumbra fades linearly in angle, 0 for the smooth cubic.
    pub linear_falloff: u32,
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
    /// The record of a light the Whitted integrator samples; `None` for an environment,
    /// which it sees only where rays leave the scene.
    pub fn compile(desc: &LightDesc) -> Option<Self> {
        let base = Self {
            kind: LightKind::Point,
            color: Vec3::ZERO,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            attenuation: Vec3::X,
            inner_angle: 0.0,
            outer_angle: 0.0,
            edge_u: Vec3::ZERO,
            edge_v: Vec3::ZERO,
            radius: 0.0,
            samples_per_axis: 1,
            linear_falloff: 0,
        };
        Some(match *desc {
            LightDesc::Environment(_) => return None,
            LightDesc::Point { position, color, attenuation } => Self { position, color, attenuation, ..base },
            LightDesc::Directional { direction, color } => {
                Self { kind: LightKind::Directional, direction: direction.normalize(), color, ..base }
            }
            LightDesc::Spot { position, direction, color, attenuation, angle_degrees, penumbra_degrees, falloff } => {
                let outer = angle_degrees.to_radians();
                Self {
                    kind: LightKind::Spot,
                    position,
                    direction: direction.normalize(),
                    color,
                    attenuation,
                    outer_angle: outer,
                    inner_angle: (outer - penumbra_degrees.to_radians()).max(0.0),
                    linear_falloff: (falloff == crate::desc::SpotFalloff::Linear) as u32,
                    ..base
                }
            }
            LightDesc::Area { shape, color, attenuation, samples } => {
                let area = Self { color, attenuation, samples_per_axis: samples.max(1), ..base };
                match shape {
                    AreaShape::Rectangle { corner, edge_u, edge_v } => {
                        Self { kind: LightKind::Rectangle, position: corner, edge_u, edge_v, ..area }
                    }
                    AreaShape::Disk { center, normal, radius } => {
                        Self { kind: LightKind::Disk, position: center, direction: normal.normalize(), radius, ..area }
                    }
                    AreaShape::Sphere { center, radius } => {
                        Self { kind: LightKind::Sphere, position: center, radius, ..area }
                    }
                }
            }
        })
    }

    /// Whether light comes from one point (or one direction): no jitter moves it.
    #[inline]
    pub fn is_point_like(&self) -> bool {
        matches!(self.kind, LightKind::Point | LightKind::Directional | LightKind::Spot)
    }

    /// How many samples one shading point takes of this light.
    pub fn sample_count(&self) -> u32 {
        if self.is_point_like() { 1 } else { self.samples_per_axis * self.samples_per_axis }
    }

    /// Incidence from sample `index` of [`Light::sample_count`], jittered by `jitter` in
    /// [0, 1)² inside its stratum. An area light's intensity is shared equally by its
    /// samples, so summing all samples gives the whole light.
    /// Inlined into the shading loops, the point light's case with it; an area light's
    /// sample is a call.
    #[inline]
    pub fn sample(&self, p: Vec3, index: u32, jitter: Vec2) -> Incidence {
        if self.is_point_like() { self.incidence(p) } else { self.sample_area(p, index, jitter) }
    }

    /// [`Light::sample`] of an area light.
    fn sample_area(&self, p: Vec3, index: u32, jitter: Vec2) -> Incidence {
        // (After the test: the integer divisions would otherwise run for every light.)
        let n = self.samples_per_axis;
        let u = (Vec2::new((index % n) as f32, (index / n) as f32) + jitter) / n as f32;
        let point = match self.kind {
            LightKind::Point | LightKind::Directional | LightKind::Spot => unreachable!("returned above"),
            LightKind::Rectangle => self.position + u.x * self.edge_u + u.y * self.edge_v,
            LightKind::Disk => self.position + disk_point(self.direction, self.radius, u),
            // The disk the sphere presents to p: the visible part of a sphere light.
            LightKind::Sphere => self.position + disk_point(p - self.position, self.radius, u),
        };
        let offset = point - p;
        let distance = offset.length();
        let share = 1.0 / self.sample_count() as f32;
        Incidence { to_light: offset / distance, distance, radiance: share * self.f_att(distance) * self.color }
    }

    #[inline]
    fn f_att(&self, d: f32) -> f32 {
        let [c1, c2, c3] = self.attenuation.to_array();
        (1.0 / (c1 + c2 * d + c3 * d * d)).min(1.0)
    }

    /// Direction, distance and unshadowed intensity of this light at `p`.
    #[inline]
    pub fn incidence(&self, p: Vec3) -> Incidence {
        if self.kind == LightKind::Directional {
            return Incidence { to_light: -self.direction, distance: f32::INFINITY, radiance: self.color };
        }
        let offset = self.position - p;
        let distance = offset.length();
        // One division, not three: each waits a dozen cycles, and a hit meets every light.
        let to_light = offset * distance.recip();
        let f_att = self.f_att(distance);
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
        if self.linear_falloff != 0 { 1.0 - x } else { 1.0 - x * x * (3.0 - 2.0 * x) }
    }
}

/// A point of the disk of `radius` facing `normal`, from `u` in [0, 1)² by Shirley and
/// Chiu's concentric mapping (keeps strata compact and equal in area).
fn disk_point(normal: Vec3, radius: f32, u: Vec2) -> Vec3 {
    let (tangent, bitangent) = normal.normalize_or(Vec3::Y).any_orthonormal_pair();
    let d = 2.0 * u - Vec2::ONE;
    if d == Vec2::ZERO {
        return Vec3::ZERO;
    }
    let (r, theta) = if d.x.abs() > d.y.abs() {
        (d.x, std::f32::consts::FRAC_PI_4 * (d.y / d.x))
    } else {
        (d.y, std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (d.x / d.y))
    };
    radius * r * (theta.cos() * tangent + theta.sin() * bitangent)
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
        })
        .unwrap();
        let at = |d: f32| light.incidence(Vec3::new(d, 0.0, 0.0)).radiance.x;
        assert_eq!(at(0.1), 1.0); // 1/(0.5+0.025+0.00125) > 1 → capped
        assert!((at(4.0) - 1.0 / (0.5 + 1.0 + 2.0)).abs() < 1e-6);
        assert!((light.incidence(Vec3::new(0.0, 3.0, 4.0)).distance - 5.0).abs() < 1e-6);
    }

    #[test]
    fn area_light_samples_share_the_intensity_and_cover_the_shape() {
        let light = Light::compile(&LightDesc::Area {
            shape: AreaShape::Rectangle {
                corner: Vec3::new(-1.0, 5.0, -1.0),
                edge_u: 2.0 * Vec3::X,
                edge_v: 2.0 * Vec3::Z,
            },
            color: Vec3::ONE,
            attenuation: Vec3::X,
            samples: 4,
        })
        .unwrap();
        assert_eq!(light.sample_count(), 16);
        let samples: Vec<Incidence> = (0..16).map(|i| light.sample(Vec3::ZERO, i, Vec2::splat(0.5))).collect();
        let total: Vec3 = samples.iter().map(|s| s.radiance).sum();
        assert!((total - Vec3::ONE).length() < 1e-5);
        // Stratum centres of a 2×2 square seen from below: x and z spread over (−1, 1).
        let xs: Vec<f32> = samples.iter().map(|s| s.to_light.x * s.distance).collect();
        assert!((xs.iter().cloned().fold(f32::MAX, f32::min) + 0.75).abs() < 1e-5);
        assert!((xs.iter().cloned().fold(f32::MIN, f32::max) - 0.75).abs() < 1e-5);
    }

    #[test]
    fn disk_samples_stay_on_the_disk() {
        for i in 0..100 {
            let u = Vec2::new((i % 10) as f32 / 10.0 + 0.03, (i / 10) as f32 / 10.0 + 0.07);
            let q = disk_point(Vec3::new(1.0, 1.0, 0.0), 2.0, u);
            assert!(q.length() <= 2.0 + 1e-5);
            assert!(q.dot(Vec3::new(1.0, 1.0, 0.0)).abs() < 1e-5);
        }
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
            falloff: crate::desc::SpotFalloff::Smooth,
        })
        .unwrap();
        let at_angle = |deg: f32| {
            let a = deg.to_radians();
            light.incidence(Vec3::new(a.sin(), -a.cos(), 0.0)).radiance.x
        };
        assert_eq!(at_angle(0.0), 1.0);
        assert_eq!(at_angle(19.0), 1.0);
        assert!((at_angle(25.0) - 0.5).abs() < 1e-3);
        assert_eq!(at_angle(31.0), 0.0);
        assert!(at_angle(22.0) > at_angle(24.0) && at_angle(24.0) > at_angle(28.0));
        // A quarter into the penumbra: the cubic keeps 27/32, the linear fade 3/4.
        assert!((at_angle(22.5) - 27.0 / 32.0).abs() < 1e-3);
        let linear = Light { linear_falloff: 1, ..light };
        let at = |deg: f32| {
            let a = deg.to_radians();
            linear.incidence(Vec3::new(a.sin(), -a.cos(), 0.0)).radiance.x
        };
        assert!((at(22.5) - 0.75).abs() < 1e-3 && (at(27.5) - 0.25).abs() < 1e-3);
    }
}

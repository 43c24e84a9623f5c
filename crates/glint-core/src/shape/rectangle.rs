use glam::{Vec2, Vec3};

use super::{Primitive, ShapeHit, SurfacePoint};
use crate::math::{Aabb, Ray};

/// The square `|x| ≤ 1, |z| ≤ 1` in the plane `y = 0`, facing +y: Mitsuba's
/// `rectangle` (its z axis is glint's y), the usual shape of an area light.
#[derive(Clone, Copy, Debug, Default)]
pub struct Rectangle;

impl Primitive for Rectangle {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let t = -ray.origin.y / ray.dir.y;
        let p = ray.at(t);
        (t > 0.0 && t < t_max && p.x.abs() <= 1.0 && p.z.abs() <= 1.0).then_some(ShapeHit { t, part: 0 })
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let p = ray.at(hit.t) * Vec3::new(1.0, 0.0, 1.0);
        SurfacePoint { point: p, normal: Vec3::Y, uv: Vec2::new(0.5 + 0.5 * p.x, 0.5 - 0.5 * p.z) }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_hit_inside_the_square_and_miss_outside() {
        let down = Vec3::new(0.0, -2.0, 0.0);
        let hit = Rectangle.intersect(&Ray::new(Vec3::new(0.9, 4.0, -0.9), down), f32::INFINITY).unwrap();
        assert_eq!(hit.t, 2.0);
        let s = Rectangle.surface(&Ray::new(Vec3::new(0.9, 4.0, -0.9), down), hit);
        assert_eq!(s.normal, Vec3::Y);
        assert!((s.uv - Vec2::new(0.95, 0.95)).length() < 1e-6);
        assert!(Rectangle.intersect(&Ray::new(Vec3::new(1.1, 4.0, 0.0), down), f32::INFINITY).is_none());
        assert!(Rectangle.intersect(&Ray::new(Vec3::new(0.0, 4.0, 0.0), -down), f32::INFINITY).is_none());
    }
}

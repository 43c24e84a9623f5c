use glam::{Vec2, Vec3};

use super::{Primitive, ShapeHit, SurfacePoint};
use crate::math::{Aabb, Ray};

/// The infinite plane `f = y`, facing +y; uv are the plane coordinates `(x, −z)`
/// (textures repeat once per unit).
#[derive(Clone, Copy, Debug, Default)]
pub struct Plane;

impl Primitive for Plane {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let t = -ray.origin.y / ray.dir.y;
        (t > 0.0 && t < t_max).then_some(ShapeHit { t, part: 0 })
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let p = ray.at(hit.t);
        let point = Vec3::new(p.x, 0.0, p.z);
        SurfacePoint { point, normal: Vec3::Y, uv: Vec2::new(p.x, -p.z) }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::new(f32::NEG_INFINITY, 0.0, f32::NEG_INFINITY), Vec3::new(f32::INFINITY, 0.0, f32::INFINITY))
    }
}

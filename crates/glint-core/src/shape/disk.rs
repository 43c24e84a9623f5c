use glam::Vec3;

use super::cylinder::cap_surface;
use super::{Primitive, ShapeHit, SurfacePoint};
use crate::math::{Aabb, Ray};

/// The disk `x² + z² ≤ 1` in the plane `y = 0`, facing +y.
#[derive(Clone, Copy, Debug, Default)]
pub struct Disk;

impl Primitive for Disk {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let t = -ray.origin.y / ray.dir.y;
        let p = ray.at(t);
        (t > 0.0 && t < t_max && p.x * p.x + p.z * p.z <= 1.0).then_some(ShapeHit { t, part: 0 })
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let cap = cap_surface(ray.at(hit.t), true);
        SurfacePoint { point: cap.point * Vec3::new(1.0, 0.0, 1.0), ..cap }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0))
    }
}

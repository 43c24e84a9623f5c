use glam::{Vec2, Vec3};

use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint};
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

/// Inside CSG a plane is the half-space `y ≤ 0` below it (as in POV-Ray), so it can cut
/// solids open.
impl Solid for Plane {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let (o, d) = (ray.origin.y, ray.dir.y);
        if d == 0.0 {
            if o <= 0.0 {
                out.push(Span::ALL);
            }
            return;
        }
        let t = -o / d;
        out.push(if d > 0.0 { Span::new(f32::NEG_INFINITY, 0, t, 0) } else { Span::new(t, 0, f32::INFINITY, 0) });
    }
}

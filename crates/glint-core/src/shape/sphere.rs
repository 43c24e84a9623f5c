use glam::{Vec2, Vec3};

use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint, azimuth_u, nearest_root, rebase};
use crate::math::{Aabb, Ray};

/// The unit sphere `f(x, y, z) = x² + y² + z² − 1`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sphere;

impl Primitive for Sphere {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        // From the closest point P' of the line, |P' + s·d|² = 1 gives
        // s = ±√((1 − |P'|²)/(d·d)): no cancellation however far P is.
        let (t0, near) = rebase(ray);
        let discriminant = 1.0 - near.origin.length_squared();
        if discriminant < 0.0 {
            return None;
        }
        let half_chord = (discriminant / ray.dir.length_squared()).sqrt();
        let t = nearest_root([t0 - half_chord, t0 + half_chord], t_max, |_| true)?;
        Some(ShapeHit { t, part: 0 })
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let (point, normal) = self.point_and_normal(ray, hit);
        let v = 0.5 + point.y.clamp(-1.0, 1.0).asin() / std::f32::consts::PI;
        SurfacePoint { point, normal, uv: Vec2::new(azimuth_u(point), v) }
    }

    #[inline(always)]
    fn point_and_normal(&self, ray: &Ray, hit: ShapeHit) -> (Vec3, Vec3) {
        let point = crate::math::unit_or(ray.at(hit.t), Vec3::Y);
        // ∇f = 2P; the factor 2 is irrelevant once normalized.
        (point, point)
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::splat(-1.0), Vec3::ONE)
    }
}

impl Solid for Sphere {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let (t0, near) = rebase(ray);
        let discriminant = 1.0 - near.origin.length_squared();
        let half_chord = (discriminant / ray.dir.length_squared()).sqrt();
        // A tangent line (zero chord) touches without entering.
        if half_chord > 0.0 {
            out.push(Span::new(t0 - half_chord, 0, t0 + half_chord, 0));
        }
    }
}

use glam::{Vec2, Vec3};

use super::cylinder::{cap_surface, clip, slab_span};
use super::span::{LocalRay, quadratic_spans};
use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint, azimuth_u, nearest_root, rebase};
use crate::math::roots::solve_quadratic;
use crate::math::{Aabb, Ray};

const BODY: u32 = 0;
const BASE: u32 = 2;

/// A finite cone: apex at `y = 1`, base of radius 1 at `y = −1`.
/// Body `f = x² + z² − ((1 − y)/2)² = 0` for `−1 ≤ y ≤ 1`, and the base cap.
#[derive(Clone, Copy, Debug, Default)]
pub struct Cone;

impl Primitive for Cone {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let mut best: Option<ShapeHit> = None;
        let (t0, near) = rebase(ray);
        let (o, d) = (near.origin, near.dir);
        // With Y = 1 − y: x² + z² − Y²/4 = 0.
        let (oy, dy) = (1.0 - o.y, -d.y);
        let a = d.x * d.x + d.z * d.z - 0.25 * dy * dy;
        let b = 2.0 * (o.x * d.x + o.z * d.z - 0.25 * oy * dy);
        let c = o.x * o.x + o.z * o.z - 0.25 * oy * oy;
        if let Some((s0, s1)) = solve_quadratic(a, b, c) {
            // Keep only the lower nappe between base and apex.
            let t = nearest_root([t0 + s0, t0 + s1], t_max, |t| (-1.0..=1.0).contains(&ray.at(t).y));
            best = t.map(|t| ShapeHit { t, part: BODY });
        }
        if ray.dir.y != 0.0 {
            let t = (-1.0 - ray.origin.y) / ray.dir.y;
            let p = ray.at(t);
            if t > 0.0 && t < best.map_or(t_max, |b| b.t) && p.x * p.x + p.z * p.z <= 1.0 {
                best = Some(ShapeHit { t, part: BASE });
            }
        }
        best
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        if hit.part == BASE {
            return cap_surface(ray.at(hit.t), false);
        }
        let (point, normal) = self.point_and_normal(ray, hit);
        SurfacePoint { point, normal, uv: Vec2::new(azimuth_u(point), 0.5 + 0.5 * point.y) }
    }

    #[inline(always)]
    fn point_and_normal(&self, ray: &Ray, hit: ShapeHit) -> (Vec3, Vec3) {
        let p = ray.at(hit.t);
        if hit.part == BASE {
            let cap = cap_surface(p, false);
            return (cap.point, cap.normal);
        }
        let y = p.y.clamp(-1.0, 1.0);
        // Project radially onto the body: radius (1 − y)/2 at height y.
        let radial = Vec2::new(p.x, p.z).normalize_or(Vec2::X) * (0.5 * (1.0 - y));
        let point = Vec3::new(radial.x, y, radial.y);
        // ∇f/2 = (x, (1 − y)/4, z); at the apex it vanishes, so use the axis there.
        let normal = Vec3::new(point.x, 0.25 * (1.0 - y), point.z);
        (point, if normal.length_squared() > 0.0 { normal } else { Vec3::Y })
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::splat(-1.0), Vec3::ONE)
    }
}

impl Solid for Cone {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        // The double cone x² + z² ≤ ((1 − y)/2)² meets the slab −1 ≤ y ≤ 1 only in its
        // lower nappe (the upper one touches it at the apex alone), so the finite cone is
        // the double cone's spans clipped to the slab.
        let Some(slab) = slab_span(ray) else { return };
        let local = LocalRay::new(ray, glam::Vec3::ZERO);
        let (o, d) = (local.origin, local.dir);
        let (oy, dy) = (1.0 - o.y, -d.y);
        let a = d.x * d.x + d.z * d.z - 0.25 * dy * dy;
        let b = 2.0 * (o.x * d.x + o.z * d.z - 0.25 * oy * dy);
        let c = o.x * o.x + o.z * o.z - 0.25 * oy * oy;
        let (body, n) = quadratic_spans(a, b, c, BODY);
        for mut s in body.into_iter().take(n) {
            s.enter.t = (local.t0 + s.enter.t as f64) as f32;
            s.exit.t = (local.t0 + s.exit.t as f64) as f32;
            clip(&mut s, slab);
            if s.enter.t < s.exit.t {
                // The slab's lower end is the base cap; its upper end can only be the apex.
                for end in [&mut s.enter, &mut s.exit] {
                    if end.part != BODY && end.part != BASE {
                        end.part = BODY;
                    }
                }
                out.push(s);
            }
        }
    }
}

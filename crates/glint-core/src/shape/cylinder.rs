use glam::{Vec2, Vec3};

use super::span::quadratic_spans;
use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint, azimuth_u, disk_uv, nearest_root};
use crate::math::{Aabb, Ray};

const BODY: u32 = 0;
const TOP: u32 = 1;
const BOTTOM: u32 = 2;

/// The lecture's finite cylinder: body `x² + z² − 1 = 0, −1 ≤ y ≤ 1` and the caps
/// `x² + z² ≤ 1` at `y = ±1`, solved case by case; the smallest surviving `t` wins.
#[derive(Clone, Copy, Debug, Default)]
pub struct Cylinder;

impl Primitive for Cylinder {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let mut best: Option<ShapeHit> = None;
        let mut consider = |t: f32, part: u32| {
            if t > 0.0 && t < best.map_or(t_max, |b| b.t) {
                best = Some(ShapeHit { t, part });
            }
        };
        // Body: the 2-D circle problem in xz, rebased to the closest point to the axis.
        let (o, d) = (ray.origin, ray.dir);
        let a = d.x * d.x + d.z * d.z;
        if a > 0.0 {
            let t0 = -(o.x * d.x + o.z * d.z) / a;
            let (cx, cz) = (o.x + t0 * d.x, o.z + t0 * d.z);
            let discriminant = 1.0 - (cx * cx + cz * cz);
            if discriminant >= 0.0 {
                let h = (discriminant / a).sqrt();
                if let Some(t) = nearest_root([t0 - h, t0 + h], t_max, |t| (o.y + t * d.y).abs() <= 1.0) {
                    consider(t, BODY);
                }
            }
        }
        // Caps: the planes y = ±1, kept inside the unit circle.
        if d.y != 0.0 {
            for (y, part) in [(1.0, TOP), (-1.0, BOTTOM)] {
                let t = (y - o.y) / d.y;
                let (x, z) = (o.x + t * d.x, o.z + t * d.z);
                if x * x + z * z <= 1.0 {
                    consider(t, part);
                }
            }
        }
        best
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        match hit.part {
            BODY => {
                let (point, normal) = self.point_and_normal(ray, hit);
                SurfacePoint { point, normal, uv: Vec2::new(azimuth_u(point), 0.5 + 0.5 * point.y) }
            }
            _ => cap_surface(ray.at(hit.t), hit.part == TOP),
        }
    }

    #[inline(always)]
    fn point_and_normal(&self, ray: &Ray, hit: ShapeHit) -> (Vec3, Vec3) {
        let p = ray.at(hit.t);
        match hit.part {
            BODY => {
                let radial = Vec2::new(p.x, p.z).normalize_or(Vec2::X);
                let point = Vec3::new(radial.x, p.y.clamp(-1.0, 1.0), radial.y);
                (point, Vec3::new(point.x, 0.0, point.z))
            }
            _ => {
                let cap = cap_surface(p, hit.part == TOP);
                (cap.point, cap.normal)
            }
        }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::splat(-1.0), Vec3::ONE)
    }
}

impl Solid for Cylinder {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        // The convex solid is (infinite cylinder x² + z² ≤ 1) ∩ (slab −1 ≤ y ≤ 1): the
        // intersection of two intervals, so no rim needs a tolerance.
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let a = d.x * d.x + d.z * d.z;
        let t0 = if a > 0.0 { -(o.x * d.x + o.z * d.z) / a } else { 0.0 };
        let (cx, cz) = (o.x + t0 * d.x, o.z + t0 * d.z);
        let (body, n) = quadratic_spans(a, 0.0, cx * cx + cz * cz - 1.0, BODY);
        if n == 0 {
            return;
        }
        let mut s = body[0];
        s.enter.t += t0 as f32;
        s.exit.t += t0 as f32;
        if let Some(slab) = slab_span(ray) {
            clip(&mut s, slab);
            if s.enter.t < s.exit.t {
                out.push(s);
            }
        }
    }
}

/// The span of the slab `−1 ≤ y ≤ 1`, its ends labelled as caps.
pub(super) fn slab_span(ray: &Ray) -> Option<Span> {
    let (o, d) = (ray.origin.y, ray.dir.y);
    if d == 0.0 {
        return (o.abs() <= 1.0).then_some(Span::ALL);
    }
    let (t_top, t_bottom) = ((1.0 - o) / d, (-1.0 - o) / d);
    Some(if d > 0.0 { Span::new(t_bottom, BOTTOM, t_top, TOP) } else { Span::new(t_top, TOP, t_bottom, BOTTOM) })
}

/// Narrows `s` to `clip`; ends cut off take `clip`'s labels.
pub(super) fn clip(s: &mut Span, clip: Span) {
    if clip.enter.t > s.enter.t {
        s.enter = clip.enter;
    }
    if clip.exit.t < s.exit.t {
        s.exit = clip.exit;
    }
}

/// A flat cap at `y = ±1` facing away from the solid.
pub(super) fn cap_surface(p: Vec3, top: bool) -> SurfacePoint {
    let y = if top { 1.0 } else { -1.0 };
    let point = Vec3::new(p.x, y, p.z);
    SurfacePoint { point, normal: Vec3::new(0.0, y, 0.0), uv: disk_uv(point, top) }
}

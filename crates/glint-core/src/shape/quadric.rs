//! The general quadric `A x² + B y² + C z² + D xy + E xz + F yz + G x + H y + I z + J = 0`
//! (POV-Ray's coefficient order), solved analytically, optionally clipped to a box.
//!
//! The solid is `{f ≤ 0} ∩ box`: without a box it is unbounded (a paraboloid, a
//! hyperboloid, an infinite cylinder); with one, the box faces close it where the
//! quadric's inside reaches them.

use bytemuck::NoUninit;
use glam::{DVec3, Vec3};

use super::span::{BOX_FACE, LocalRay, box_face, box_span, box_uv, first_crossing, quadratic_spans};
use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint};
use crate::math::{Aabb, Ray};

/// Part number of the quadric surface; box faces follow [`BOX_FACE`].
const SURFACE: u32 = 0;

/// A quadric as flat data: ten coefficients and a clipping box (infinite when none).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Quadric {
    /// `[A, B, C, D, E, F, G, H, I, J]`.
    pub coefficients: [f32; 10],
    pub min: Vec3,
    pub max: Vec3,
}

impl Quadric {
    /// The coefficients in f64: the symmetric matrix `Q`, the linear term `g` and `J`,
    /// so `f(p) = pᵀQp + g·p + J`.
    fn parts(&self) -> ([[f64; 3]; 3], DVec3, f64) {
        let c = self.coefficients.map(|x| x as f64);
        let q = [[c[0], 0.5 * c[3], 0.5 * c[4]], [0.5 * c[3], c[1], 0.5 * c[5]], [0.5 * c[4], 0.5 * c[5], c[2]]];
        (q, DVec3::new(c[6], c[7], c[8]), c[9])
    }

    /// `f(p)`.
    pub fn value(&self, p: DVec3) -> f64 {
        let (q, g, j) = self.parts();
        let qp = DVec3::new(
            q[0][0] * p.x + q[0][1] * p.y + q[0][2] * p.z,
            q[1][0] * p.x + q[1][1] * p.y + q[1][2] * p.z,
            q[2][0] * p.x + q[2][1] * p.y + q[2][2] * p.z,
        );
        p.dot(qp) + g.dot(p) + j
    }

    /// `∇f = 2Qp + g`.
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        let (q, g, _) = self.parts();
        let row = |r: [f64; 3]| 2.0 * (r[0] * p.x + r[1] * p.y + r[2] * p.z);
        DVec3::new(row(q[0]), row(q[1]), row(q[2])) + g
    }

    fn bounded(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// The line's spans in `{f ≤ 0} ∩ box`. Along the line `f(P + t·d)` is the quadratic
    /// `(dᵀQd)·s² + (2·PᵀQd + g·d)·s + f(P)` in `s`, from the line's point nearest the
    /// box centre (or the origin) so the constant term stays small.
    fn spans_array(&self, ray: &Ray) -> ([Span; 2], usize) {
        let mut out = [Span::ALL; 2];
        let clip = if self.bounded() {
            match box_span(ray, self.min, self.max) {
                Some(clip) => clip,
                None => return (out, 0),
            }
        } else {
            Span::ALL
        };
        let centre = if self.bounded() { 0.5 * (self.min + self.max) } else { Vec3::ZERO };
        let local = LocalRay::new(ray, centre);
        let (q, g, _) = self.parts();
        let d = local.dir;
        let qd = DVec3::new(
            q[0][0] * d.x + q[0][1] * d.y + q[0][2] * d.z,
            q[1][0] * d.x + q[1][1] * d.y + q[1][2] * d.z,
            q[2][0] * d.x + q[2][1] * d.y + q[2][2] * d.z,
        );
        let a = d.dot(qd);
        let b = 2.0 * local.origin.dot(qd) + g.dot(d);
        let c = self.value(local.origin);
        let (spans, n) = quadratic_spans(a, b, c, SURFACE);
        let mut kept = 0;
        for mut s in spans.into_iter().take(n) {
            s.enter.t = (local.t0 + s.enter.t as f64) as f32;
            s.exit.t = (local.t0 + s.exit.t as f64) as f32;
            if clip.enter.t > s.enter.t {
                s.enter = clip.enter;
            }
            if clip.exit.t < s.exit.t {
                s.exit = clip.exit;
            }
            if s.enter.t < s.exit.t {
                out[kept] = s;
                kept += 1;
            }
        }
        (out, kept)
    }
}

impl Primitive for Quadric {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let (spans, n) = self.spans_array(ray);
        first_crossing(&spans[..n], t_max)
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let p = ray.at(hit.t);
        if hit.part >= BOX_FACE {
            let (point, normal) = box_face(hit.part, p, self.min, self.max);
            return SurfacePoint { point, normal, uv: box_uv(point, self.min, self.max) };
        }
        // One Newton step along the gradient puts the point back on the surface.
        let p64 = p.as_dvec3();
        let g = self.gradient(p64);
        let step = g * (self.value(p64) / g.length_squared());
        let point = if step.is_finite() { (p64 - step).as_vec3() } else { p };
        let normal = self.gradient(point.as_dvec3()).as_vec3();
        let normal = if normal.is_finite() && normal.length_squared() > 0.0 { normal } else { -ray.dir };
        SurfacePoint { point, normal, uv: box_uv(point, self.min, self.max) }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }
}

impl Solid for Quadric {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let (spans, n) = self.spans_array(ray);
        out.extend_from_slice(&spans[..n]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quadric(coefficients: [f32; 10], bounds: Option<(Vec3, Vec3)>) -> Quadric {
        let (min, max) = bounds.unwrap_or((Vec3::NEG_INFINITY, Vec3::INFINITY));
        Quadric { coefficients, min, max }
    }

    #[test]
    fn sphere_as_a_quadric_matches_the_sphere() {
        let q = quadric([1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0], None);
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let hit = q.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.t - 4.0).abs() < 1e-6);
        let s = q.surface(&ray, hit);
        assert!((s.normal.normalize() - Vec3::Z).length() < 1e-6);
        // From inside: the far side.
        let inside = Ray::new(Vec3::ZERO, Vec3::X);
        assert!((q.intersect(&inside, f32::INFINITY).unwrap().t - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bounded_cylinder_gets_caps_from_the_box() {
        // x² + z² − 1 ≤ 0 clipped to |y| ≤ 1: the unit cylinder with caps.
        let q = quadric([1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0], Some((Vec3::splat(-1.0), Vec3::ONE)));
        let down = Ray::new(Vec3::new(0.3, 5.0, 0.0), Vec3::NEG_Y);
        let hit = q.intersect(&down, f32::INFINITY).unwrap();
        assert!((hit.t - 4.0).abs() < 1e-6);
        assert!((q.surface(&down, hit).normal - Vec3::Y).length() < 1e-6);
        let side = Ray::new(Vec3::new(5.0, 0.5, 0.0), Vec3::NEG_X);
        let hit = q.intersect(&side, f32::INFINITY).unwrap();
        assert!((hit.t - 4.0).abs() < 1e-6);
        assert!((q.surface(&side, hit).normal.normalize() - Vec3::X).length() < 1e-6);
        // The unbounded version has no caps: looking down the axis stays inside.
        let open = quadric(q.coefficients, None);
        assert!(open.intersect(&down, f32::INFINITY).is_none());
    }

    #[test]
    fn hyperboloid_of_two_sheets_gives_two_spans() {
        // −x² + y² − z² − 1 ≤ 0 is the region between the sheets... its complement along
        // the y axis: inside for |y| ≤ 1.
        let q = quadric([-1.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0], None);
        let mut spans = Vec::new();
        q.spans(&Ray::new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y), &mut spans);
        assert_eq!(spans.len(), 1);
        assert!((spans[0].enter.t - 4.0).abs() < 1e-6 && (spans[0].exit.t - 6.0).abs() < 1e-6);
        // Along x it is inside everywhere.
        spans.clear();
        q.spans(&Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), &mut spans);
        assert_eq!(spans, vec![Span::ALL]);
    }
}

//! Barr's superellipsoid ("Superquadrics and Angle-Preserving Transformations", 1981)
//! with the y axis as its pole, inside the cube [−1, 1]³.
//!
//! `g = (|x|^(2/e2) + |z|^(2/e2))^(e2/e1) + |y|^(2/e1)` and the solid is `g ≤ 1`: `e1`
//! shapes the cross-section from pole to pole ("north–south"), `e2` the cross-section
//! around the pole ("east–west"). 1, 1 is the sphere; towards 0 both become the cube;
//! 2 gives straight bevels (an octahedron at 2, 2); above 2 the sides cave in.
//!
//! There is no closed form for the ray parameter, so it is found numerically with the
//! interval solver of [`super::implicit::solve`]: `g` grows with `|x|`, `|y|` and `|z|`,
//! so its exact range over a ray segment comes from the segment's box corners nearest to
//! and farthest from the axis planes, and the sign of each partial derivative is the sign
//! of its coordinate, which gives monotonic pieces for free.

use crate::shape::span::pair_crossings;
use bytemuck::NoUninit;
use glam::{DVec3, Vec3};

use super::implicit::interval::{DualInterval, Interval};
use super::implicit::solve::{RayFunction, crossings};
use super::span::{box_span, box_uv};
use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint};
use crate::math::{Aabb, Ray};

/// Smallest and largest exponents accepted: below, `|x|^(2/e)` underflows to a cube
/// anyway; above, the shape is a thin star that no longer reads as a superellipsoid.
pub const EXPONENT_RANGE: (f32, f32) = (0.02, 4.0);

/// The cube is widened by this much so the solid's extreme points, which touch it, are
/// never cut by rounding.
const MARGIN: f32 = 1e-4;

#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Superellipsoid {
    /// The north–south exponent (along y).
    pub e1: f32,
    /// The east–west exponent (around y).
    pub e2: f32,
}

impl Superellipsoid {
    /// `f = g^(e1/2) − 1`: the same sign as `g − 1` but growing like a distance, so
    /// its values stay well scaled for any exponent.
    pub fn value(&self, p: DVec3) -> f64 {
        self.value_abs(p.x.abs(), p.y.abs(), p.z.abs())
    }

    fn value_abs(&self, ax: f64, ay: f64, az: f64) -> f64 {
        let (e1, e2) = (self.e1 as f64, self.e2 as f64);
        let a = ax.powf(2.0 / e2) + az.powf(2.0 / e2);
        let g = a.powf(e2 / e1) + ay.powf(2.0 / e1);
        g.powf(0.5 * e1) - 1.0
    }

    /// `∇g`, pointing out of the solid (`g` is increasing in each `|coordinate|`).
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        let (e1, e2) = (self.e1 as f64, self.e2 as f64);
        let a = p.x.abs().powf(2.0 / e2) + p.z.abs().powf(2.0 / e2);
        let ring = if a > 0.0 { (e2 / e1) * a.powf(e2 / e1 - 1.0) } else { 0.0 };
        let term = |c: f64, e: f64| {
            let slope = (2.0 / e) * c.abs().powf(2.0 / e - 1.0);
            if c == 0.0 { 0.0 } else { slope.copysign(c) }
        };
        DVec3::new(ring * term(p.x, e2), term(p.y, e1), ring * term(p.z, e2))
    }

    fn along<'a>(&'a self, ray: &Ray) -> AlongRay<'a> {
        AlongRay { shape: self, o: ray.origin.as_dvec3(), d: ray.dir.as_dvec3() }
    }

    fn box_span(&self, ray: &Ray) -> Option<Span> {
        box_span(ray, Vec3::splat(-1.0 - MARGIN), Vec3::splat(1.0 + MARGIN))
    }
}

struct AlongRay<'a> {
    shape: &'a Superellipsoid,
    o: DVec3,
    d: DVec3,
}

impl RayFunction for AlongRay<'_> {
    fn value(&self, t: f64) -> f64 {
        self.shape.value(self.o + t * self.d)
    }

    fn enclose(&self, t: Interval) -> DualInterval {
        let coord = |axis: usize| t.along(self.o[axis], self.d[axis]);
        let (x, y, z) = (coord(0), coord(1), coord(2));
        let (ax, ay, az) = (x.abs(), y.abs(), z.abs());
        // Exact range of a function increasing in each |coordinate|, widened for the
        // rounding of powf.
        let lo = self.shape.value_abs(ax.lo, ay.lo, az.lo);
        let hi = self.shape.value_abs(ax.hi, ay.hi, az.hi);
        let slack = 1e-12 * (1.0 + lo.abs().max(hi.abs()));
        let v = Interval::new(lo - slack, hi + slack);
        // df/dt = Σ ∂f/∂xᵢ·dᵢ, and ∂f/∂xᵢ has the sign of xᵢ.
        let (mut rising, mut falling, mut unknown) = (false, false, false);
        for (c, d) in [(x, self.d.x), (y, self.d.y), (z, self.d.z)] {
            if d == 0.0 {
                continue;
            }
            if c.lo > 0.0 || c.hi < 0.0 {
                if (c.lo > 0.0) == (d > 0.0) {
                    rising = true;
                } else {
                    falling = true;
                }
            } else {
                unknown = true;
            }
        }
        let d = match (rising, falling, unknown) {
            (true, false, false) => Interval::POSITIVE,
            (false, true, false) => Interval::NEGATIVE,
            _ => Interval::ENTIRE,
        };
        DualInterval { v, d }
    }
}

impl Primitive for Superellipsoid {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let b = self.box_span(ray)?;
        let (lo, hi) = (b.enter.t.max(0.0) as f64, b.exit.t.min(t_max) as f64);
        let mut hit = None;
        crossings(&self.along(ray), lo, hi, |t, _| {
            let t = t as f32;
            if t > 0.0 && t < t_max {
                hit = Some(ShapeHit { t, part: 0 });
            }
            hit.is_none()
        });
        hit
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let point = ray.at(hit.t);
        let g = self.gradient(point.as_dvec3()).as_vec3();
        let normal = if g.is_finite() && g.length_squared() > 0.0 { g } else { point };
        SurfacePoint { point, normal, uv: box_uv(point, Vec3::splat(-1.0), Vec3::ONE) }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::splat(-1.0), Vec3::ONE)
    }
}

impl Solid for Superellipsoid {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let Some(b) = self.box_span(ray) else { return };
        crossings(&self.along(ray), b.enter.t as f64, b.exit.t as f64, pair_crossings(out, &mut None, 0));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponents_one_make_the_unit_sphere() {
        let s = Superellipsoid { e1: 1.0, e2: 1.0 };
        for p in [DVec3::X, DVec3::Y, DVec3::new(0.6, 0.0, 0.8), DVec3::splat(3f64.sqrt().recip())] {
            assert!(s.value(p).abs() < 1e-12, "{p}");
            assert!((s.gradient(p).normalize() - p).length() < 1e-9);
        }
        let ray = Ray::new(Vec3::new(0.3, 0.2, 5.0), Vec3::new(0.0, 0.0, -2.0));
        let hit = s.intersect(&ray, f32::INFINITY).expect("hits");
        let want = 0.5 * (5.0 - (1.0f32 - 0.13).sqrt());
        assert!((hit.t - want).abs() < 1e-6, "{} vs {want}", hit.t);
        let mut spans = Vec::new();
        s.spans(&ray, &mut spans);
        assert_eq!(spans.len(), 1);
        assert!((spans[0].exit.t - 0.5 * (5.0 + 0.87f32.sqrt())).abs() < 1e-6);
    }

    #[test]
    fn small_exponents_approach_the_cube() {
        let s = Superellipsoid { e1: 0.05, e2: 0.05 };
        // Aimed at a point near the cube's corner region, which the sphere would miss.
        let ray = Ray::new(Vec3::new(0.9, 0.9, 5.0), Vec3::NEG_Z);
        let hit = s.intersect(&ray, f32::INFINITY).expect("hits near the corner");
        assert!((hit.t - 4.0).abs() < 0.05, "{}", hit.t);
        let n = s.surface(&ray, hit).normal.normalize();
        assert!(n.z > 0.99, "{n}");
    }

    #[test]
    fn octahedron_bevels_are_flat() {
        // e1 = e2 = 2: |x| + |y| + |z| ≤ 1.
        let s = Superellipsoid { e1: 2.0, e2: 2.0 };
        let ray = Ray::new(Vec3::new(0.2, 0.1, 5.0), Vec3::NEG_Z);
        let hit = s.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.t - (5.0 - 0.7)).abs() < 1e-5, "{}", hit.t);
        let n = s.surface(&ray, hit).normal.normalize();
        assert!((n - Vec3::ONE.normalize()).length() < 1e-4, "{n}");
    }
}

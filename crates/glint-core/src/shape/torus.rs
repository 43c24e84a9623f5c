use glam::{DVec3, Vec2, Vec3};

use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint};
use crate::math::roots::solve_quartic;
use crate::math::{Aabb, Ray};

/// A ring around the y axis: major radius 1, tube radius `minor_radius` (0 < r < 1).
/// `f = (|P|² + R² − r²)² − 4R²(x² + z²)`, a quartic in `t`.
#[derive(Clone, Copy, Debug)]
pub struct Torus {
    pub minor_radius: f32,
}

/// The torus quartic along a ray, in a unit-speed parameter `s` from the line's point
/// closest to the centre: `t = t0 + s/speed`.
struct AlongRay {
    t0: f64,
    speed: f64,
    /// Monic quartic `s⁴ + c[0]·s³ + c[1]·s² + c[2]·s + c[3]`.
    c: [f64; 4],
}

impl AlongRay {
    /// `None` when the line misses the bounding sphere.
    fn new(ray: &Ray, minor_radius: f32) -> Option<Self> {
        // In f64, from the line's point closest to the centre and with a unit-speed
        // parameter s, the quartic's coefficients stay well scaled; Newton polish in
        // the solver recovers full precision of the roots.
        let r = minor_radius as f64;
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let speed = d.length();
        let u = d / speed;
        let t0 = -o.dot(u) / speed;
        let p = o + u * (t0 * speed);
        let outer = 1.0 + r;
        if p.length_squared() > outer * outer {
            return None;
        }
        let k = p.length_squared() + 1.0 - r * r;
        let pu = p.dot(u);
        let radial_uu = u.x * u.x + u.z * u.z;
        let radial_pu = p.x * u.x + p.z * u.z;
        let radial_pp = p.x * p.x + p.z * p.z;
        let c = [
            4.0 * pu,
            4.0 * pu * pu + 2.0 * k - 4.0 * radial_uu,
            4.0 * pu * k - 8.0 * radial_pu,
            k * k - 4.0 * radial_pp,
        ];
        Some(AlongRay { t0, speed, c })
    }

    fn roots(&self) -> ([f64; 4], usize) {
        solve_quartic(self.c[0], self.c[1], self.c[2], self.c[3])
    }

    fn value(&self, s: f64) -> f64 {
        (((s + self.c[0]) * s + self.c[1]) * s + self.c[2]) * s + self.c[3]
    }

    fn t(&self, s: f64) -> f32 {
        (self.t0 + s / self.speed) as f32
    }
}

impl Primitive for Torus {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let along = AlongRay::new(ray, self.minor_radius)?;
        let (roots, n) = along.roots();
        roots[..n].iter().map(|&s| along.t(s)).find(|&t| t > 0.0 && t < t_max).map(|t| ShapeHit { t, part: 0 })
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let r = self.minor_radius;
        let p = ray.at(hit.t);
        // Project onto the tube: nearest point of the core circle, then out by r.
        let ring = Vec3::new(p.x, 0.0, p.z).normalize_or(Vec3::X);
        let tube = (p - ring).normalize_or(ring);
        let point = ring + r * tube;
        let normal = gradient(point.as_dvec3(), r as f64).as_vec3();
        let u = super::azimuth_u(point);
        let phi = tube.y.atan2(tube.dot(ring));
        let v = 0.5 + phi / std::f32::consts::TAU;
        SurfacePoint { point, normal, uv: Vec2::new(u, v) }
    }

    fn bounds(&self) -> Aabb {
        let r = self.minor_radius;
        Aabb::new(Vec3::new(-1.0 - r, -r, -1.0 - r), Vec3::new(1.0 + r, r, 1.0 + r))
    }
}

impl Solid for Torus {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let Some(along) = AlongRay::new(ray, self.minor_radius) else { return };
        let (roots, n) = along.roots();
        let start = out.len();
        // Inside where f < 0; deciding each gap by f at its middle stays right even
        // when rounding loses or doubles a root near a tangent.
        for pair in roots[..n].windows(2) {
            let (s0, s1) = (pair[0], pair[1]);
            let (t0, t1) = (along.t(s0), along.t(s1));
            if t0 < t1 && along.value(0.5 * (s0 + s1)) < 0.0 {
                let merge = out.len() > start && out.last().is_some_and(|last| last.exit.t >= t0);
                match out.last_mut() {
                    Some(last) if merge => last.exit.t = t1,
                    _ => out.push(Span::new(t0, 0, t1, 0)),
                }
            }
        }
    }
}

/// ∇f / 4 = (|P|² + R² − r²)·P − 2R²·(x, 0, z), with R = 1.
fn gradient(p: DVec3, r: f64) -> DVec3 {
    let k = p.length_squared() + 1.0 - r * r;
    k * p - 2.0 * DVec3::new(p.x, 0.0, p.z)
}

//! Analytic hits and normals for every primitive, and agreement between object-space
//! intersection and an independent world-space search under random transforms.

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::*;
use crate::math::Transform;

const TORUS_R: f32 = 0.25;

fn all_shapes() -> [Shape; 7] {
    [
        Shape::new(ShapeKind::Sphere),
        Shape::new(ShapeKind::Cube),
        Shape::new(ShapeKind::Cylinder),
        Shape::new(ShapeKind::Cone),
        Shape::new(ShapeKind::Plane),
        Shape::new(ShapeKind::Disk),
        Shape::torus(TORUS_R),
    ]
}

fn hit(shape: Shape, origin: [f32; 3], dir: [f32; 3]) -> Option<(f32, SurfacePoint)> {
    let ray = Ray::new(Vec3::from(origin), Vec3::from(dir));
    let h = shape.intersect(&ray, f32::INFINITY)?;
    Some((h.t, shape.surface(&ray, h)))
}

fn assert_hit(shape: Shape, origin: [f32; 3], dir: [f32; 3], t: f32, normal: [f32; 3]) {
    let (got_t, s) = hit(shape, origin, dir).unwrap_or_else(|| panic!("{shape:?} missed from {origin:?}"));
    assert!((got_t - t).abs() < 1e-5, "{shape:?}: t = {got_t}, expected {t}");
    let n = s.normal.normalize();
    assert!((n - Vec3::from(normal)).length() < 1e-5, "{shape:?}: n = {n}, expected {normal:?}");
}

#[test]
fn lecture_ray_is_tangent_to_the_unit_circle_at_t_3() {
    // P = (−3, 1), d = (0.8, −0.6) in the z = 0 plane: t² − 6t + 9 = 0, a double root.
    let ray = Ray::new(Vec3::new(-3.0, 1.0, 0.0), Vec3::new(0.8, -0.6, 0.0));
    let h = Sphere.intersect(&ray, f32::INFINITY).expect("a tangent ray touches the circle");
    assert!((h.t - 3.0).abs() < 1e-4, "t = {}", h.t);
    let s = Sphere.surface(&ray, h);
    assert!((s.point - Vec3::new(-0.6, -0.8, 0.0)).length() < 1e-3);
    // Tangent: the normal is perpendicular to the ray.
    assert!(s.normal.normalize().dot(ray.dir).abs() < 1e-3);
    // Nudged off the circle, the ray misses.
    let past = Ray::new(Vec3::new(-3.0, 0.99, 0.0), ray.dir); // distance 1.008 from the centre
    assert!(Sphere.intersect(&past, f32::INFINITY).is_none());
}

#[test]
fn analytic_hits_and_normals() {
    let [sphere, cube, cylinder, cone, plane, disk, torus] = all_shapes();
    assert_hit(sphere, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0], 4.0, [0.0, 0.0, 1.0]);
    assert_hit(sphere, [0.0, 0.0, 0.0], [0.0, 2.0, 0.0], 0.5, [0.0, 1.0, 0.0]); // from inside, d not unit
    assert_hit(cube, [0.5, 0.2, 5.0], [0.0, 0.0, -1.0], 4.0, [0.0, 0.0, 1.0]);
    assert_hit(cube, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0, [1.0, 0.0, 0.0]);
    assert_hit(cube, [0.0, -4.0, 0.0], [0.0, 1.0, 0.0], 3.0, [0.0, -1.0, 0.0]);
    assert_hit(cylinder, [5.0, 0.3, 0.0], [-1.0, 0.0, 0.0], 4.0, [1.0, 0.0, 0.0]);
    assert_hit(cylinder, [0.2, 5.0, 0.1], [0.0, -1.0, 0.0], 4.0, [0.0, 1.0, 0.0]);
    assert_hit(cylinder, [0.2, -5.0, 0.1], [0.0, 1.0, 0.0], 4.0, [0.0, -1.0, 0.0]);
    assert!(hit(cylinder, [5.0, 1.5, 0.0], [-1.0, 0.0, 0.0]).is_none());
    // Cone: radius 0.5 at y = 0; the slant normal is (1, 1/2, 0)/|·|.
    let slant = Vec3::new(1.0, 0.5, 0.0).normalize().to_array();
    assert_hit(cone, [5.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 4.5, slant);
    assert_hit(cone, [0.3, -5.0, 0.0], [0.0, 1.0, 0.0], 4.0, [0.0, -1.0, 0.0]);
    assert!(hit(cone, [0.7, 5.0, 0.0], [0.0, -1.0, 0.0]).map(|(t, _)| t) > Some(5.0)); // misses the body at y > -0.4
    assert!(hit(cone, [5.0, 1.2, 0.0], [-1.0, 0.0, 0.0]).is_none()); // above the apex: the other nappe
    assert_hit(plane, [3.0, 5.0, -2.0], [0.0, -2.0, 0.0], 2.5, [0.0, 1.0, 0.0]);
    assert!(hit(plane, [0.0, 5.0, 0.0], [1.0, 0.0, 0.0]).is_none());
    assert_hit(disk, [0.5, 1.0, 0.5], [0.0, -1.0, 0.0], 1.0, [0.0, 1.0, 0.0]);
    assert!(hit(disk, [0.9, 1.0, 0.9], [0.0, -1.0, 0.0]).is_none());
    assert_hit(torus, [5.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 3.75, [1.0, 0.0, 0.0]);
    assert_hit(torus, [1.0, 5.0, 0.0], [0.0, -1.0, 0.0], 4.75, [0.0, 1.0, 0.0]);
    assert_hit(torus, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 0.75, [0.0, 0.0, -1.0]); // from the hole
    assert!(hit(torus, [0.0, 5.0, 0.0], [0.0, -1.0, 0.0]).is_none());
}

#[test]
fn uv_stays_in_the_unit_square_on_bounded_shapes() {
    for shape in all_shapes().into_iter().filter(|s| s.kind != ShapeKind::Plane) {
        for i in 0..200 {
            let a = i as f32 * 0.37;
            let origin = Vec3::new(a.cos() * 4.0, (a * 1.7).sin() * 3.0, a.sin() * 4.0);
            if let Some((_, s)) = hit(shape, origin.to_array(), (-origin + Vec3::new(0.1, 0.05, 0.0)).to_array()) {
                assert!(s.uv.cmpge(Vec2::ZERO).all() && s.uv.cmple(Vec2::ONE).all(), "{shape:?}: {:?}", s.uv);
            }
        }
    }
}

/// Solid membership in object space, written independently of the intersectors.
fn inside(shape: Shape, p: DVec3) -> bool {
    let r = shape.param as f64;
    match shape.kind {
        ShapeKind::Sphere => p.length_squared() < 1.0,
        ShapeKind::Cube => p.abs().max_element() < 1.0,
        ShapeKind::Cylinder => p.x * p.x + p.z * p.z < 1.0 && p.y.abs() < 1.0,
        ShapeKind::Cone => p.y.abs() < 1.0 && p.x * p.x + p.z * p.z < 0.25 * (1.0 - p.y).powi(2),
        ShapeKind::Torus => (p.length_squared() + 1.0 - r * r).powi(2) < 4.0 * (p.x * p.x + p.z * p.z),
        ShapeKind::Plane | ShapeKind::Disk | ShapeKind::Mesh => unreachable!("not solids"),
        _ => unreachable!("kinds with side tables are tested beside their code"),
    }
}

/// The implicit function of the surface part that was hit, for its gradient.
fn implicit(shape: Shape, part: u32, p: DVec3) -> f64 {
    let r = shape.param as f64;
    match (shape.kind, part) {
        (ShapeKind::Sphere, _) => p.length_squared() - 1.0,
        (ShapeKind::Cube, face) => {
            let sign = if face % 2 == 1 { 1.0 } else { -1.0 };
            sign * p[(face / 2) as usize] - 1.0
        }
        (ShapeKind::Cylinder, 0) => p.x * p.x + p.z * p.z - 1.0,
        (ShapeKind::Cylinder, 1) => p.y - 1.0,
        (ShapeKind::Cylinder | ShapeKind::Cone, _) if part == 2 => -p.y - 1.0,
        (ShapeKind::Cone, _) => p.x * p.x + p.z * p.z - 0.25 * (1.0 - p.y).powi(2),
        (ShapeKind::Torus, _) => (p.length_squared() + 1.0 - r * r).powi(2) - 4.0 * (p.x * p.x + p.z * p.z),
        _ => unreachable!(),
    }
}

/// A world-space search along the ray that knows nothing of the intersectors: march
/// through `inside(M⁻¹(P + t·d))` and bisect the first change.
fn world_space_first_crossing(shape: Shape, xf: &Transform, ray: &Ray, t_end: f64) -> Option<f64> {
    let m_inv = xf.object_from_world.as_dmat4();
    let o = ray.origin.as_dvec3();
    let d = ray.dir.as_dvec3();
    let at = |t: f64| inside(shape, m_inv.transform_point3(o + t * d));
    let steps = 20_000;
    let start = at(0.0);
    let mut prev = 0.0;
    for i in 1..=steps {
        let t = t_end * i as f64 / steps as f64;
        if at(t) != start {
            let (mut lo, mut hi) = (prev, t);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if at(mid) == start { lo = mid } else { hi = mid }
            }
            return Some(0.5 * (lo + hi));
        }
        prev = t;
    }
    None
}

fn transform_from(
    scale: (f32, f32, f32),
    axis: (f32, f32, f32),
    degrees: f32,
    offset: (f32, f32, f32),
) -> Option<Transform> {
    Some(
        Transform::scale(Vec3::new(scale.0, scale.1, scale.2))?
            .then(&Transform::rotate(Vec3::new(axis.0, axis.1, axis.2), degrees)?)
            .then(&Transform::translate(Vec3::new(offset.0, offset.1, offset.2))),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Object-space t (ray carried by M⁻¹, direction NOT normalized) equals the
    /// world-space crossing; the hit lies on the transformed surface; the normal
    /// brought back by (M⁻¹)ᵀ equals the world-space gradient of f(M⁻¹x).
    #[test]
    fn object_and_world_space_agree(
        which in 0usize..5,
        scale in (0.3f32..3.0, 0.3f32..3.0, 0.3f32..3.0),
        axis in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        degrees in -180.0f32..180.0,
        offset in (-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0),
        target in (-0.6f32..0.6, -0.6f32..0.6, -0.6f32..0.6),
        from in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        speed in 0.1f32..5.0,
    ) {
        let shape = [Shape::new(ShapeKind::Sphere), Shape::new(ShapeKind::Cube), Shape::new(ShapeKind::Cylinder), Shape::new(ShapeKind::Cone), Shape::torus(0.4)][which];
        let xf = transform_from(scale, axis, degrees, offset);
        prop_assume!(xf.is_some());
        let xf = xf.unwrap();
        let from = Vec3::new(from.0, from.1, from.2);
        prop_assume!(from.length() > 0.1);
        // Aim at a point inside the solid (the torus's tube for the torus).
        let mut target_obj = Vec3::new(target.0, target.1, target.2);
        if shape.kind == ShapeKind::Torus { target_obj = Vec3::new(1.0, 0.0, 0.0) + 0.3 * target_obj; }
        if shape.kind == ShapeKind::Cone { target_obj *= Vec3::new(0.4, 1.0, 0.4) * 0.5; }
        let target_world = xf.point_to_world(target_obj);
        let origin = target_world + from.normalize() * 40.0;
        let ray = Ray::new(origin, (target_world - origin) / 40.0 * speed);
        let t_end = 80.0 / speed as f64;

        let local = xf.ray_to_object(&ray);
        let found = shape.intersect(&local, f32::INFINITY);
        let reference = world_space_first_crossing(shape, &xf, &ray, t_end);
        prop_assert!(reference.is_some(), "the ray aims inside the solid");
        let hit = found.expect("object-space intersection finds the solid the ray aims at");
        let t_ref = reference.unwrap();
        prop_assert!((hit.t as f64 - t_ref).abs() < 2e-4 * t_ref.max(1.0), "t {} vs world-space {}", hit.t, t_ref);

        let s = shape.surface(&local, hit);
        let p_world = xf.point_to_world(s.point);
        prop_assert!((p_world - ray.at(hit.t)).length() < 1e-3 * (1.0 + origin.length()));

        // Gradient of g(x) = f(M⁻¹x) by central differences in world space.
        let m_inv = xf.object_from_world.as_dmat4();
        let g = |x: DVec3| implicit(shape, hit.part, m_inv.transform_point3(x));
        let p = p_world.as_dvec3();
        let h = 1e-5;
        let grad = DVec3::new(
            g(p + DVec3::X * h) - g(p - DVec3::X * h),
            g(p + DVec3::Y * h) - g(p - DVec3::Y * h),
            g(p + DVec3::Z * h) - g(p - DVec3::Z * h),
        );
        prop_assume!(grad.length() > 1e-9); // the cone's apex has no gradient
        let n_world = xf.normal_to_world(s.normal).normalize().as_dvec3();
        prop_assert!((n_world - grad.normalize()).length() < 2e-3, "normal {:?} vs gradient {:?}", n_world, grad.normalize());
    }
}

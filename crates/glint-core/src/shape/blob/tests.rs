//! Field and gradient values, exact hits on a single ball, thin necks, and agreement of
//! the crossings with a direct evaluation of the field (no speckles).

use glam::{DVec3, Mat4, Quat, Vec3};

use super::*;
use crate::shape::first_crossing;

fn component(blob_from_component: Mat4, strength: f32, half_length: f32) -> BlobComponent {
    BlobComponent::new(blob_from_component, strength, half_length)
}

fn ball(center: Vec3, radius: f32, strength: f32) -> BlobComponent {
    component(Mat4::from_translation(center) * Mat4::from_scale(Vec3::splat(radius)), strength, 0.0)
}

fn blob_of(components: &[BlobComponent], threshold: f32) -> (Blob, Vec<BlobComponent>) {
    let bounds = components.iter().filter(|c| c.strength > 0.0).fold(Aabb::EMPTY, |b, c| b.union(c.support_bounds()));
    let blob = Blob { min: bounds.min, first: 0, max: bounds.max, count: components.len() as u32, threshold };
    (blob, components.to_vec())
}

#[test]
fn field_values_follow_the_falloff() {
    let c = ball(Vec3::new(1.0, 0.0, 0.0), 2.0, 3.0);
    assert!((c.field(DVec3::new(1.0, 0.0, 0.0)) - 3.0).abs() < 1e-12);
    // r = 1/2 of the radius: 3·(1 − 1/4)².
    assert!((c.field(DVec3::new(1.0, 1.0, 0.0)) - 3.0 * 0.5625).abs() < 1e-6);
    assert_eq!(c.field(DVec3::new(3.0, 0.0, 0.0)), 0.0);
    assert_eq!(c.field(DVec3::new(4.0, 0.0, 0.0)), 0.0);
    // An ellipsoid: radius 2 along x, 1 along y and z.
    let e = component(Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)), 1.0, 0.0);
    assert!((e.field(DVec3::new(1.0, 0.0, 0.0)) - 0.5625).abs() < 1e-6);
    assert!((e.field(DVec3::new(0.0, 0.5, 0.0)) - 0.5625).abs() < 1e-6);
    // A capsule of half length 2 (in units of its radius 0.5): the side at distance 0.25
    // from the axis and the cap at 0.25 beyond the end both give r = 1/2.
    let capsule = component(Mat4::from_scale(Vec3::splat(0.5)), 1.0, 2.0);
    for p in [DVec3::new(0.25, 0.7, 0.0), DVec3::new(0.0, -1.25, 0.0), DVec3::new(0.0, 0.0, -0.25)] {
        assert!((capsule.field(p) - 0.5625).abs() < 1e-6, "{p}");
    }
}

#[test]
fn gradients_match_central_differences() {
    let rotated =
        Mat4::from_rotation_translation(Quat::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7), Vec3::X);
    let components = [
        ball(Vec3::new(0.2, 0.1, -0.3), 1.5, 1.0),
        component(rotated * Mat4::from_scale(Vec3::new(1.2, 0.6, 0.9)), -0.7, 0.0),
        component(rotated * Mat4::from_scale(Vec3::splat(0.8)), 2.0, 1.3),
    ];
    let h = 1e-6;
    for c in &components {
        for p in [DVec3::new(0.3, 0.2, 0.1), DVec3::new(1.1, -0.4, 0.5), DVec3::new(0.9, 1.0, -0.2)] {
            let g = c.field_gradient(p);
            let numeric = DVec3::new(
                c.field(p + DVec3::X * h) - c.field(p - DVec3::X * h),
                c.field(p + DVec3::Y * h) - c.field(p - DVec3::Y * h),
                c.field(p + DVec3::Z * h) - c.field(p - DVec3::Z * h),
            ) / (2.0 * h);
            assert!((g - numeric).length() < 1e-6 * (1.0 + g.length()), "{p}: {g} vs {numeric}");
        }
    }
}

#[test]
fn a_single_ball_is_a_sphere_of_the_predicted_radius() {
    // (1 − r²)² = T gives r = √(1 − √T).
    let threshold = 0.25f32;
    let (blob, components) = blob_of(&[ball(Vec3::ZERO, 1.0, 1.0)], threshold);
    let shape = BlobShape { blob: &blob, components: &components };
    let radius = (1.0 - threshold.sqrt()).sqrt();
    let ray = Ray::new(Vec3::new(0.1, 0.2, 5.0), Vec3::new(0.0, 0.0, -1.0));
    let hit = shape.intersect(&ray, f32::INFINITY).expect("hits");
    let want = 5.0 - (radius * radius - 0.05).sqrt();
    assert!((hit.t - want).abs() < 1e-5, "{} vs {want}", hit.t);
    let s = shape.surface(&ray, hit);
    let n = s.normal.normalize();
    assert!((n - s.point.normalize()).length() < 1e-4, "{n}");
    let mut spans = Vec::new();
    shape.spans(&ray, &mut spans);
    assert_eq!(spans.len(), 1);
    assert!((spans[0].exit.t - (5.0 + (radius * radius - 0.05).sqrt())).abs() < 1e-5);
}

#[test]
fn a_thin_neck_is_found_and_a_broken_one_is_not() {
    // Two balls whose fields meet at the origin; the threshold set just below and just
    // above the field there gives a neck of width ~1e-3 or a gap.
    let components = [ball(Vec3::new(-0.8, 0.0, 0.0), 1.0, 1.0), ball(Vec3::new(0.8, 0.0, 0.0), 1.0, 1.0)];
    let middle = 2.0 * (1.0 - 0.64f64).powi(2);
    let ray = Ray::new(Vec3::new(0.0, 0.0, 4.0), Vec3::new(0.0, 0.0, -1.0));
    let (neck, components_neck) = blob_of(&components, (middle * (1.0 - 1e-5)) as f32);
    let shape = BlobShape { blob: &neck, components: &components_neck };
    assert!(shape.intersect(&ray, f32::INFINITY).is_some(), "the neck is missed");
    let (gap, components_gap) = blob_of(&components, (middle * (1.0 + 1e-5)) as f32);
    let shape = BlobShape { blob: &gap, components: &components_gap };
    assert!(shape.intersect(&ray, f32::INFINITY).is_none(), "a hit in the gap");
}

#[test]
fn spans_agree_with_the_field_everywhere_along_many_rays() {
    // Positive and negative balls, an ellipsoid and a capsule, overlapping.
    let tilt = Mat4::from_rotation_z(0.6);
    let components = [
        ball(Vec3::new(-0.6, 0.0, 0.0), 1.0, 1.0),
        ball(Vec3::new(0.6, 0.2, 0.1), 0.9, 1.2),
        ball(Vec3::new(0.0, 0.5, 0.3), 0.5, -0.8),
        component(
            Mat4::from_translation(Vec3::new(0.0, -0.6, 0.0)) * Mat4::from_scale(Vec3::new(1.5, 0.4, 0.6)),
            1.0,
            0.0,
        ),
        component(
            Mat4::from_translation(Vec3::new(0.2, 0.0, -0.4)) * tilt * Mat4::from_scale(Vec3::splat(0.35)),
            1.5,
            2.5,
        ),
    ];
    let (blob, components) = blob_of(&components, 0.4);
    let shape = BlobShape { blob: &blob, components: &components };
    let mut state = 12345u64;
    let mut random = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64) as f32 * 2.0 - 1.0
    };
    let mut spans = Vec::new();
    let mut checked = 0;
    for _ in 0..2000 {
        let origin = Vec3::new(random(), random(), random()) * 4.0;
        let target = Vec3::new(random(), random(), random()) * 1.2;
        let ray = Ray::new(origin, target - origin);
        spans.clear();
        shape.spans(&ray, &mut spans);
        for pair in spans.windows(2) {
            assert!(pair[0].exit.t < pair[1].enter.t, "overlapping spans {spans:?}");
        }
        // Sample the line; away from the surface, inside ⇔ field above threshold.
        for k in 0..200 {
            let t = k as f32 / 200.0 * 2.0;
            let value = shape.value(ray.at(t).as_dvec3());
            if value.abs() < 1e-4 {
                continue;
            }
            let in_spans = spans.iter().any(|s| s.enter.t < t && t < s.exit.t);
            assert_eq!(in_spans, value > 0.0, "t = {t}, value {value}, spans {spans:?}");
            checked += 1;
        }
        // The nearest hit is the first crossing, on the surface.
        if let Some(hit) = shape.intersect(&ray, f32::INFINITY) {
            assert_eq!(Some(hit), first_crossing(&spans, f32::INFINITY));
            let v = shape.value(ray.at(hit.t).as_dvec3());
            assert!(v.abs() < 1e-3, "value {v} at a hit");
        }
    }
    assert!(checked > 100_000);
}

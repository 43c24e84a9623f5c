//! Emitter sampling: densities integrate to one, samples follow them, and estimates of
//! solid angles and irradiance match closed forms.

use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

use super::*;
use crate::sampling::Rng;

fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let s = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

fn test_map() -> Environment {
    // 16×9 map: a sky gradient, a dark ground and one very bright "sun" texel.
    let (w, h) = (16, 9);
    let mut texels: Vec<Vec3> = (0..w * h)
        .map(|i| if i / w < 4 { Vec3::new(0.2, 0.4, 1.0) * (1.0 + (i % w) as f32 / 8.0) } else { Vec3::splat(0.05) })
        .collect();
    texels[2 * w + 5] = Vec3::splat(200.0);
    let rotation = Mat3::from_rotation_y(0.7) * Mat3::from_rotation_x(0.3);
    Environment::new(Vec3::splat(1.5), texels, w, h, rotation)
}

#[test]
fn environment_pdf_integrates_to_one_and_matches_its_samples() {
    let env = test_map();
    let mut rng = Rng::new(2);
    let n = 400_000;
    // ∫ pdf dω by uniform sphere sampling: E[pdf(d)·4π] = 1.
    let integral: f64 =
        (0..n).map(|_| env.pdf(uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()))) as f64).sum::<f64>()
            * 4.0
            * std::f64::consts::PI
            / n as f64;
    assert!((integral - 1.0).abs() < 0.02, "{integral}");
    // Samples report the pdf and radiance of their direction, and estimate the total
    // radiance the same as uniform sampling does.
    let (mut importance, mut uniform) = (Vec3::ZERO, Vec3::ZERO);
    for _ in 0..n {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let Some((d, l, pdf)) = env.sample(u) else {
            // Only at the poles, where sin θ = 0 leaves no density.
            continue;
        };
        assert!((pdf - env.pdf(d)).abs() <= 2e-3 * pdf, "{pdf} vs {}", env.pdf(d));
        assert!((l - env.radiance(d)).abs().max_element() <= 1e-3 * l.max_element().max(1.0));
        importance += l / pdf;
        uniform += env.radiance(uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()))) * 4.0 * PI;
    }
    let (a, b) = (importance / n as f32, uniform / n as f32);
    assert!((a - b).abs().max_element() < 0.05 * b.max_element(), "{a} vs {b}");
}

#[test]
fn environment_maps_directions_as_mitsuba_does() {
    let (w, h) = (8, 5);
    let mut texels = vec![Vec3::ZERO; w * h];
    // Column 2 of row 1 lies at u = 2.5/8, v = 1/4 (θ = 45°); Mitsuba 3.9 returns 1
    // there and 0.5 half a texel to either side (values probed from its `envmap`).
    texels[w + 2] = Vec3::ONE;
    let env = Environment::new(Vec3::ONE, texels, w, h, Mat3::IDENTITY);
    for (u, want) in [(2.5f32, 1.0f32), (2.0, 0.5), (3.0, 0.5), (1.5, 0.0)] {
        let d = env.direction(Vec2::new(u / 8.0, 0.25));
        assert!((env.radiance(d) - Vec3::splat(want)).length() < 1e-4, "u = {u}/8: {}", env.radiance(d));
    }
    // The top row is straight up; −z is u = 0.
    assert!((env.uv(Vec3::Y).y).abs() < 1e-6);
    assert!(env.uv(Vec3::NEG_Z).x.abs() < 1e-6);
    for uv in [Vec2::new(0.1, 0.3), Vec2::new(0.8, 0.9), Vec2::new(0.5, 0.5)] {
        assert!((env.uv(env.direction(uv)) - uv).length() < 1e-4);
    }
}

#[test]
fn constant_environment_is_uniform() {
    let env = Environment::new(Vec3::splat(2.0), Vec::new(), 0, 0, Mat3::IDENTITY);
    let (d, l, pdf) = env.sample(Vec2::new(0.3, 0.6)).unwrap();
    assert_eq!(l, Vec3::splat(2.0));
    assert!((pdf - 1.0 / (4.0 * PI)).abs() < 1e-7);
    assert!((d.length() - 1.0).abs() < 1e-5);
    assert!((env.power() - luminance(Vec3::splat(2.0)) * 4.0 * PI).abs() < 1e-3);
}

/// `E[1/pdf]` over samples from `p` estimates the solid angle the emitter subtends.
fn solid_angle(e: &Emitter, p: Vec3, n: u32) -> f32 {
    let mut rng = Rng::new(4);
    let mut sum = 0.0f64;
    for _ in 0..n {
        if let Some(s) = e.sample(p, Vec2::new(rng.next_f32(), rng.next_f32())) {
            let q = p + s.distance * s.wi;
            let normal = if e.kind == EmitterKind::Sphere { (q - e.p).normalize() } else { e.normal };
            assert!((e.pdf(p, q, normal) - s.pdf).abs() <= 1e-3 * s.pdf, "{:?}", e.kind);
            sum += 1.0 / s.pdf as f64;
        }
    }
    (sum / n as f64) as f32
}

#[test]
fn area_emitters_cover_the_solid_angle_they_subtend() {
    let (h, r) = (2.0f32, 1.5f32);
    let disk_angle = 2.0 * PI * (1.0 - h / (h * h + r * r).sqrt());
    let disk = Emitter {
        p: Vec3::new(0.0, h, 0.0),
        e1: Vec3::new(r, 0.0, 0.0),
        e2: Vec3::new(0.0, 0.0, r),
        normal: Vec3::NEG_Y,
        size: PI * r * r,
        radiance: Vec3::ONE,
        ..Emitter::empty(EmitterKind::Disk)
    };
    assert!((solid_angle(&disk, Vec3::ZERO, 100_000) - disk_angle).abs() < 0.01 * disk_angle);
    // Seen from behind, it gives nothing.
    assert!(disk.sample(Vec3::new(0.0, 5.0, 0.0), Vec2::splat(0.5)).is_none());
    // A sphere of radius r at distance d subtends 2π(1 − √(1 − r²/d²)), outside;
    // the whole sphere (4π) from inside.
    let d = 3.0f32;
    let sphere = Emitter {
        p: Vec3::new(0.0, 0.0, d),
        size: 1.0,
        radiance: Vec3::ONE,
        two_sided: 1,
        ..Emitter::empty(EmitterKind::Sphere)
    };
    let cone = 2.0 * PI * (1.0 - (1.0 - 1.0 / (d * d)).sqrt());
    assert!((solid_angle(&sphere, Vec3::ZERO, 50_000) - cone).abs() < 1e-3 * cone);
    let inside = solid_angle(&sphere, Vec3::new(0.2, 0.1, d), 100_000);
    assert!((inside - 4.0 * PI).abs() < 0.05 * 4.0 * PI, "{inside}");
    // A one-sided sphere emits outward only: nothing reaches its inside.
    let one_sided = Emitter { two_sided: 0, ..sphere };
    assert_eq!(solid_angle(&one_sided, Vec3::new(0.2, 0.1, d), 1000), 0.0);
    // A unit right triangle straight below the shading point, far away: Ω ≈ A/h².
    let tri = Emitter {
        p: Vec3::new(0.0, -100.0, 0.0),
        e1: Vec3::X,
        e2: Vec3::Z,
        normal: Vec3::Y,
        size: 0.5,
        radiance: Vec3::ONE,
        ..Emitter::empty(EmitterKind::Triangle)
    };
    let omega = solid_angle(&tri, Vec3::ZERO, 10_000);
    assert!((omega - 0.5e-4).abs() < 1e-3 * 0.5e-4, "{omega}");
}

#[test]
fn point_lights_fall_off_with_the_inverse_square() {
    let light = Emitter::from_light(&LightDesc::Point {
        position: Vec3::new(0.0, 4.0, 0.0),
        color: Vec3::splat(8.0),
        attenuation: Vec3::new(0.0, 0.0, 1.0),
    })
    .unwrap();
    let s = light.sample(Vec3::new(3.0, 0.0, 0.0), Vec2::ZERO).unwrap();
    assert!(s.delta && (s.distance - 5.0).abs() < 1e-5);
    assert!((s.radiance.x - 8.0 / 25.0).abs() < 1e-6);
    assert!((light.power(1.0, None) - 4.0 * PI * 8.0).abs() < 1e-3);
}

//! Properties every BSDF must have: energy conservation (white furnace), reciprocity,
//! agreement of `sample` with `eval`/`pdf`, and a chi-square goodness-of-fit test of the
//! sampled directions against the pdf (as PBRT's `bsdfs_test.cpp` and Mitsuba's `chi2`).

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

use super::*;
use crate::desc::{BsdfDesc, ColorParam, MaterialDesc, ScalarParam};
use crate::sampling::Rng;

/// Test BSDFs live for the whole test run.
fn leak(b: Bsdf) -> &'static Bsdf {
    Box::leak(Box::new(b))
}

fn surface(bsdf: BsdfDesc) -> SurfaceBsdf<'static> {
    let desc = MaterialDesc { bsdf: Some(bsdf), two_sided: false, ..MaterialDesc::default() };
    leak(Bsdf::compile(&desc)).at(Vec2::ZERO, |_, _| Vec3::ONE)
}

/// The same BSDF with Beckmann microfacets.
fn beckmann(bsdf: BsdfDesc) -> SurfaceBsdf<'static> {
    let desc = MaterialDesc {
        bsdf: Some(bsdf),
        two_sided: false,
        microfacet: crate::desc::MicrofacetKind::Beckmann,
        ..MaterialDesc::default()
    };
    leak(Bsdf::compile(&desc)).at(Vec2::ZERO, |_, _| Vec3::ONE)
}

fn phong(diffuse: f32, specular: f32, shininess: f32, mirror: f32, kt: f32, ior: f32) -> SurfaceBsdf<'static> {
    let desc = MaterialDesc {
        diffuse: Vec3::splat(diffuse),
        specular: Vec3::splat(specular),
        shininess,
        reflective: Some(Vec3::splat(mirror)),
        transmissive: Vec3::splat(kt),
        ior,
        ..MaterialDesc::default()
    };
    leak(Bsdf::compile(&desc)).at(Vec2::ZERO, |_, _| Vec3::ONE)
}

fn diffuse(r: f32) -> BsdfDesc {
    BsdfDesc::Diffuse { reflectance: ColorParam::constant(Vec3::splat(r)) }
}

/// A perfect mirror metal (η = k = 0 gives F = 1, Mitsuba's `none`).
fn mirror_metal(alpha: f32) -> BsdfDesc {
    BsdfDesc::Conductor {
        eta: Vec3::ZERO,
        k: Vec3::ZERO,
        specular: ColorParam::constant(Vec3::ONE),
        alpha: ScalarParam::constant(alpha),
    }
}

fn gold(alpha: f32) -> BsdfDesc {
    BsdfDesc::Conductor {
        eta: Vec3::new(0.143, 0.374, 1.442),
        k: Vec3::new(3.983, 2.385, 1.603),
        specular: ColorParam::constant(Vec3::ONE),
        alpha: ScalarParam::constant(alpha),
    }
}

fn glass(alpha: f32) -> BsdfDesc {
    BsdfDesc::Dielectric {
        int_ior: 1.5,
        ext_ior: 1.0,
        reflectance: Vec3::ONE,
        transmittance: Vec3::ONE,
        alpha: ScalarParam::constant(alpha),
    }
}

fn plastic(alpha: f32, nonlinear: bool) -> BsdfDesc {
    BsdfDesc::Plastic {
        diffuse: ColorParam::constant(Vec3::new(0.6, 0.3, 0.1)),
        int_ior: 1.49,
        ext_ior: 1.0,
        specular: Vec3::ONE,
        alpha: ScalarParam::constant(alpha),
        nonlinear,
    }
}

/// glTF's metallic-roughness material with an orange base.
fn metallic(metallic: f32, alpha: f32) -> BsdfDesc {
    BsdfDesc::MetallicRoughness {
        base: ColorParam::constant(Vec3::new(0.9, 0.5, 0.2)),
        metallic: ScalarParam::constant(metallic),
        alpha: ScalarParam::constant(alpha),
        ior: 1.5,
    }
}

fn direction(cos_theta: f32, phi: f32) -> Vec3 {
    let sin = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos_theta)
}

/// Mean sampled weight (the directional albedo) over `n` samples, with the radiance
/// scaling of refraction undone so that lossless surfaces give exactly 1.
fn albedo(s: &SurfaceBsdf<'static>, wo: Vec3, n: u32) -> Vec3 {
    let mut rng = Rng::new(11);
    let mut sum = Vec3::ZERO;
    for _ in 0..n {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        if let Some(smp) = s.sample(wo, rng.next_f32(), u) {
            sum += smp.weight * (smp.eta * smp.eta);
        }
    }
    sum / n as f32
}

#[test]
fn white_furnace_lossless_surfaces_return_all_light() {
    for cos in [1.0f32, 0.7, 0.3, 0.05] {
        let wo = direction(cos, 0.4);
        for (name, s) in [
            ("white diffuse", surface(diffuse(1.0))),
            ("smooth mirror metal", surface(mirror_metal(0.0))),
            ("smooth glass", surface(glass(0.0))),
            (
                "thin glass",
                surface(BsdfDesc::ThinDielectric {
                    int_ior: 1.5,
                    ext_ior: 1.0,
                    reflectance: Vec3::ONE,
                    transmittance: Vec3::ONE,
                }),
            ),
            ("phong mix summing to one", phong(0.5, 0.0, 1.0, 0.3, 0.2, 1.0)),
        ] {
            let a = albedo(&s, wo, 20_000);
            assert!((a - Vec3::ONE).abs().max_element() < 0.02, "{name} at cos {cos}: {a}");
        }
        // From inside the glass too.
        let a = albedo(&surface(glass(0.0)), -wo, 20_000);
        assert!((a - Vec3::ONE).abs().max_element() < 0.02, "glass from inside at {cos}: {a}");
    }
}

/// `∫ f(wo, wi) |cos θi| dωi` over the sphere by a midpoint rule fine enough for lobes of
/// α ≥ 0.05, with the radiance scaling of refraction undone (as in [`albedo`]).
fn integrated_albedo(s: &SurfaceBsdf<'static>, wo: Vec3) -> f32 {
    let (nc, np) = (1600, 400);
    let eta = s.record.eta.x;
    let mut sum = 0.0f64;
    for i in 0..nc {
        let cos = -1.0 + 2.0 * (i as f32 + 0.5) / nc as f32;
        let transmitted = cos * wo.z < 0.0;
        let etap = if !transmitted || s.record.kind != BsdfKind::Dielectric {
            1.0
        } else if wo.z > 0.0 {
            eta
        } else {
            1.0 / eta
        };
        for j in 0..np {
            let wi = direction(cos, 2.0 * PI * (j as f32 + 0.5) / np as f32);
            sum += (s.eval(wo, wi).x * cos.abs() * etap * etap) as f64;
        }
    }
    (sum * (2.0 / nc as f64) * (2.0 * std::f64::consts::PI / np as f64)) as f32
}

#[test]
fn rough_surfaces_lose_only_the_energy_single_scattering_misses() {
    // Single-scattering microfacet models lose energy (more at high roughness and
    // grazing angles), never gain; the sampled albedo equals the integral of f·cos.
    for alpha in [0.05f32, 0.2, 0.5] {
        for cos in [0.9f32, 0.5, 0.2] {
            let wo = direction(cos, 1.0);
            for (name, s, wo) in [
                ("metal", surface(mirror_metal(alpha)), wo),
                ("glass", surface(glass(alpha)), wo),
                ("glass from inside", surface(glass(alpha)), -wo),
                ("Beckmann metal", beckmann(mirror_metal(alpha)), wo),
                ("Beckmann glass", beckmann(glass(alpha)), wo),
                ("Beckmann glass from inside", beckmann(glass(alpha)), -wo),
            ] {
                let sampled = albedo(&s, wo, 40_000).x;
                let integrated = integrated_albedo(&s, wo);
                assert!(
                    sampled <= 1.01 && (sampled - integrated).abs() < 0.015,
                    "{name} α {alpha} cos {cos}: sampled {sampled}, integrated {integrated}"
                );
            }
        }
    }
}

#[test]
fn plastic_and_overfull_phong_conserve_energy() {
    for cos in [1.0f32, 0.5, 0.1] {
        let wo = direction(cos, 0.0);
        for s in [surface(plastic(0.0, false)), surface(plastic(0.3, true)), phong(0.9, 0.8, 10.0, 0.5, 0.0, 1.0)] {
            let a = albedo(&s, wo, 40_000);
            assert!(a.max_element() <= 1.01, "{:?} at {cos}: {a}", s.record.kind);
        }
    }
    // A white plastic reflects nearly everything: the coat's Fresnel plus the base.
    let white = surface(BsdfDesc::Plastic {
        diffuse: ColorParam::constant(Vec3::ONE),
        int_ior: 1.5,
        ext_ior: 1.0,
        specular: Vec3::ONE,
        alpha: ScalarParam::constant(0.0),
        nonlinear: false,
    });
    let a = albedo(&white, direction(0.8, 0.0), 40_000).x;
    assert!(a > 0.9 && a <= 1.01, "{a}");
}

#[test]
fn reflection_is_reciprocal() {
    let mut rng = Rng::new(5);
    let cases = [
        surface(diffuse(0.7)),
        surface(gold(0.3)),
        beckmann(gold(0.3)),
        surface(plastic(0.0, false)),
        surface(plastic(0.2, true)),
        surface(glass(0.3)),
        phong(0.3, 0.5, 30.0, 0.0, 0.0, 1.0),
        surface(metallic(0.4, 0.2)),
        surface(metallic(0.4, 0.0)),
    ];
    for s in &cases {
        for _ in 0..200 {
            let wo = direction(rng.next_f32().max(0.05), 2.0 * PI * rng.next_f32());
            let wi = direction(rng.next_f32().max(0.05), 2.0 * PI * rng.next_f32());
            let (a, b) = (s.eval(wo, wi), s.eval(wi, wo));
            assert!((a - b).abs().max_element() <= 1e-4 * a.max_element().max(1.0), "{:?}: {a} {b}", s.record.kind);
        }
    }
}

#[test]
fn one_sided_surfaces_are_black_from_behind_and_two_sided_ones_are_not() {
    let one = surface(diffuse(0.5));
    let wo = direction(-0.7, 0.0);
    assert!(one.sample(wo, 0.5, Vec2::splat(0.3)).is_none());
    assert_eq!(one.eval(wo, direction(-0.5, 1.0)), Vec3::ZERO);
    let desc = MaterialDesc { bsdf: Some(diffuse(0.5)), two_sided: true, ..MaterialDesc::default() };
    let two = leak(Bsdf::compile(&desc)).at(Vec2::ZERO, |_, _| Vec3::ONE);
    let s = two.sample(wo, 0.5, Vec2::splat(0.3)).unwrap();
    assert!(s.wi.z < 0.0, "scatters back to the side it came from");
    assert!((two.eval(wo, direction(-0.5, 1.0)) - Vec3::splat(0.5 / PI)).length() < 1e-6);
}

#[test]
fn samples_agree_with_eval_and_pdf() {
    let mut rng = Rng::new(8);
    for s in [
        surface(diffuse(0.5)),
        surface(gold(0.25)),
        surface(glass(0.3)),
        surface(plastic(0.15, false)),
        beckmann(gold(0.25)),
        beckmann(glass(0.3)),
        phong(0.3, 0.4, 12.0, 0.0, 0.0, 1.0),
        surface(metallic(0.5, 0.2)),
        surface(metallic(0.3, 0.0)),
        surface(metallic(1.0, 0.3)),
    ] {
        for _ in 0..500 {
            let wo = direction(2.0 * rng.next_f32() - 1.0, 2.0 * PI * rng.next_f32());
            let Some(smp) = s.sample(wo, rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32())) else {
                continue;
            };
            if smp.delta {
                continue;
            }
            let pdf = s.pdf(wo, smp.wi);
            assert!((pdf - smp.pdf).abs() <= 1e-3 * pdf.max(1.0), "{:?}: {pdf} vs {}", s.record.kind, smp.pdf);
            let expected = s.eval(wo, smp.wi) * smp.wi.z.abs() / smp.pdf;
            assert!((expected - smp.weight).abs().max_element() <= 1e-3 * expected.max_element().max(1.0));
        }
    }
}

/// Pearson's chi-square test of sampled directions against the pdf over a
/// (cos θ, φ) grid of the whole sphere, merging cells expected to get under 5 samples.
/// Passes at significance 1e-3 (Wilson–Hilferty quantile).
fn chi_square_fits(s: &SurfaceBsdf<'static>, wo: Vec3, seed: u32) -> Result<(), String> {
    let (n_theta, n_phi, samples) = (20usize, 40usize, 200_000u32);
    let cell = |w: Vec3| {
        let t = (((w.z + 1.0) * 0.5 * n_theta as f32) as usize).min(n_theta - 1);
        let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI);
        let p = ((phi / (2.0 * PI) * n_phi as f32) as usize).min(n_phi - 1);
        t * n_phi + p
    };
    let mut observed = vec![0f64; n_theta * n_phi];
    let mut rng = Rng::new(seed);
    for _ in 0..samples {
        if let Some(smp) = s.sample(wo, rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()))
            && !smp.delta
        {
            observed[cell(smp.wi)] += 1.0;
        }
    }
    // Expected counts: the pdf integrated over each cell by a 24×24 midpoint rule.
    let mut expected = vec![0f64; n_theta * n_phi];
    let sub = 24;
    for (c, e) in expected.iter_mut().enumerate() {
        let (t, p) = (c / n_phi, c % n_phi);
        let mut sum = 0.0f64;
        for i in 0..sub {
            for j in 0..sub {
                let cos = -1.0 + 2.0 * (t as f32 + (i as f32 + 0.5) / sub as f32) / n_theta as f32;
                let phi = 2.0 * PI * (p as f32 + (j as f32 + 0.5) / sub as f32) / n_phi as f32;
                sum += s.pdf(wo, direction(cos, phi)) as f64;
            }
        }
        let area = (2.0 / n_theta as f64) * (2.0 * std::f64::consts::PI / n_phi as f64);
        *e = sum / (sub * sub) as f64 * area * samples as f64;
    }
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut chi2, mut dof, mut pool_e, mut pool_o) = (0.0f64, 0i32, 0.0f64, 0.0f64);
    for &c in &order {
        if expected[c] == 0.0 && observed[c] > 0.0 {
            return Err(format!("{} samples where the pdf is zero", observed[c]));
        }
        pool_e += expected[c];
        pool_o += observed[c];
        if pool_e >= 5.0 {
            chi2 += (pool_o - pool_e).powi(2) / pool_e;
            dof += 1;
            pool_e = 0.0;
            pool_o = 0.0;
        }
    }
    let k = (dof - 1).max(1) as f64;
    let z = 3.09; // one-sided 1e-3
    let threshold = k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3);
    if chi2 > threshold { Err(format!("chi² = {chi2:.1} > {threshold:.1} ({dof} cells)")) } else { Ok(()) }
}

#[test]
fn sampled_directions_follow_the_pdf() {
    let mut cases = vec![("diffuse", surface(diffuse(0.8)))];
    for alpha in [0.1f32, 0.3, 0.7] {
        cases.push(("rough gold", surface(gold(alpha))));
        cases.push(("rough glass", surface(glass(alpha))));
        cases.push(("rough plastic", surface(plastic(alpha, false))));
        cases.push(("rough metallic-roughness", surface(metallic(0.5, alpha))));
    }
    for alpha in [0.1f32, 0.4] {
        cases.push(("Beckmann gold", beckmann(gold(alpha))));
        cases.push(("Beckmann glass", beckmann(glass(alpha))));
        cases.push(("Beckmann plastic", beckmann(plastic(alpha, false))));
    }
    cases.push(("smooth plastic's diffuse part", surface(plastic(0.0, false))));
    cases.push(("smooth metallic-roughness's diffuse part", surface(metallic(0.6, 0.0))));
    cases.push(("phong", phong(0.3, 0.5, 8.0, 0.1, 0.0, 1.0)));
    for (name, s) in &cases {
        for (i, cos) in [0.95f32, 0.6, 0.2, -0.5].into_iter().enumerate() {
            let wo = direction(cos, 0.3);
            if let Err(e) = chi_square_fits(s, wo, 100 + i as u32) {
                panic!("{name} (alpha {}) at cos θo = {cos}: {e}", s.alpha);
            }
        }
    }
}

#[test]
fn metallic_roughness_blends_a_schlick_metal_and_a_plastic_linearly() {
    let mut rng = Rng::new(21);
    for alpha in [0.0f32, 0.25] {
        let (blend, metal, plastic) =
            (surface(metallic(0.3, alpha)), surface(metallic(1.0, alpha)), surface(metallic(0.0, alpha)));
        // The dielectric end is glint's plastic: the base under a coat of index 1.5.
        let coat = surface(BsdfDesc::Plastic {
            diffuse: ColorParam::constant(Vec3::new(0.9, 0.5, 0.2)),
            int_ior: 1.5,
            ext_ior: 1.0,
            specular: Vec3::ONE,
            alpha: ScalarParam::constant(alpha),
            nonlinear: false,
        });
        for _ in 0..200 {
            let wo = direction(rng.next_f32().max(0.05), 2.0 * PI * rng.next_f32());
            let wi = direction(rng.next_f32().max(0.05), 2.0 * PI * rng.next_f32());
            let mixed = metal.eval(wo, wi) * 0.3 + plastic.eval(wo, wi) * 0.7;
            let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-4 * a.max_element().max(1.0);
            assert!(close(blend.eval(wo, wi), mixed), "α {alpha}: {} vs {mixed}", blend.eval(wo, wi));
            assert!(close(plastic.eval(wo, wi), coat.eval(wo, wi)));
            let pdf = metal.pdf(wo, wi) * 0.3 + plastic.pdf(wo, wi) * 0.7;
            assert!((blend.pdf(wo, wi) - pdf).abs() <= 1e-4 * pdf.max(1.0));
        }
    }
    // The metal end reflects its base colour at normal incidence and white at grazing.
    let metal = surface(metallic(1.0, 0.0));
    let head_on = metal.sample(Vec3::Z, 0.5, Vec2::splat(0.5)).unwrap();
    assert!(head_on.delta && (head_on.weight - Vec3::new(0.9, 0.5, 0.2)).abs().max_element() < 1e-5);
    let grazing = metal.sample(direction(0.01, 0.0), 0.5, Vec2::splat(0.5)).unwrap();
    assert!(grazing.weight.min_element() > 0.9, "{}", grazing.weight);
}

#[test]
fn metallic_roughness_conserves_energy_and_a_white_metal_loses_none_when_smooth() {
    for cos in [1.0f32, 0.5, 0.1] {
        let wo = direction(cos, 0.0);
        for (m, alpha) in [(0.0f32, 0.0f32), (0.5, 0.0), (0.5, 0.3), (1.0, 0.3), (0.2, 0.6)] {
            let a = albedo(&surface(metallic(m, alpha)), wo, 40_000);
            assert!(a.max_element() <= 1.01, "metallic {m} α {alpha} at {cos}: {a}");
        }
        let white = surface(BsdfDesc::MetallicRoughness {
            base: ColorParam::constant(Vec3::ONE),
            metallic: ScalarParam::constant(1.0),
            alpha: ScalarParam::constant(0.0),
            ior: 1.5,
        });
        assert!((albedo(&white, wo, 1_000) - Vec3::ONE).abs().max_element() < 1e-5);
    }
}

#[test]
fn a_metallic_texture_scales_the_metal_share_per_point() {
    let desc = MaterialDesc {
        bsdf: Some(BsdfDesc::MetallicRoughness {
            base: ColorParam::constant(Vec3::ONE),
            metallic: ScalarParam { value: 0.8, texture: Some(0) },
            alpha: ScalarParam::constant(0.2),
            ior: 1.5,
        }),
        ..MaterialDesc::default()
    };
    let record = leak(Bsdf::compile(&desc));
    let half = record.at(Vec2::ZERO, |_, _| Vec3::new(0.25, 0.5, 0.75));
    assert!((half.metallic - 0.4).abs() < 1e-6);
    let none = record.at(Vec2::ZERO, |_, _| Vec3::ZERO);
    assert_eq!(none.metallic, 0.0);
    assert!(none.has_non_delta());
}

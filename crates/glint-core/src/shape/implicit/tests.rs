//! Implicit surfaces against analytic ones, box closing, and interval enclosures of
//! random expressions.

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::interval::Interval;
use super::*;
use crate::shape::{Sphere, Torus, first_crossing};

fn implicit(text: &str, min: Vec3, max: Vec3, lipschitz: f32) -> (Implicit, Vec<ImplicitOp>) {
    let code = compile_expression(text).unwrap_or_else(|e| panic!("{text}: {e}"));
    (Implicit { min, first: 0, max, len: code.len() as u32, lipschitz }, code)
}

/// Deterministic rays aimed around the origin from all sides.
fn rays(count: usize, spread: f32) -> Vec<Ray> {
    let mut state = 99u64;
    let mut random = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64) as f32 * 2.0 - 1.0
    };
    (0..count)
        .map(|_| {
            let origin = Vec3::new(random(), random(), random()).normalize_or(Vec3::Z) * 4.0;
            let target = Vec3::new(random(), random(), random()) * spread;
            Ray::new(origin, (target - origin) * (0.5 + random().abs()))
        })
        .collect()
}

#[test]
fn sphere_expression_matches_the_sphere() {
    for lipschitz in [0.0, 2.0 * 3f32.sqrt() * 1.01] {
        let (record, code) = implicit("x^2 + y^2 + z^2 - 1", Vec3::splat(-1.01), Vec3::splat(1.01), lipschitz);
        let shape = ImplicitShape { record: &record, code: &code };
        let mut hits = 0;
        for ray in rays(2000, 1.2) {
            let want = Sphere.intersect(&ray, f32::INFINITY);
            let got = shape.intersect(&ray, f32::INFINITY);
            match (want, got) {
                (Some(w), Some(g)) => {
                    hits += 1;
                    assert!((w.t - g.t).abs() < 2e-5 * w.t, "t {} vs {}", g.t, w.t);
                    let n = shape.surface(&ray, g).normal.normalize();
                    assert!((n - ray.at(g.t).normalize()).length() < 1e-4, "{n}");
                }
                (None, None) => {}
                // Only grazing rays may disagree.
                (w, g) => {
                    let (_, near) = crate::shape::rebase(&ray);
                    assert!((near.origin.length() - 1.0).abs() < 1e-3, "{w:?} vs {g:?}");
                }
            }
        }
        assert!(hits > 1000);
    }
}

#[test]
fn torus_expression_matches_the_torus() {
    let r = 0.3f32;
    let text = format!("(x^2 + y^2 + z^2 + 1 - {r}^2)^2 - 4*(x^2 + z^2)");
    let bound = Vec3::new(1.0 + r, r, 1.0 + r) * 1.01;
    let (record, code) = implicit(&text, -bound, bound, 0.0);
    let shape = ImplicitShape { record: &record, code: &code };
    let torus = Torus { minor_radius: r };
    let mut hits = 0;
    for ray in rays(3000, 1.3) {
        let want = torus.intersect(&ray, f32::INFINITY);
        let got = shape.intersect(&ray, f32::INFINITY);
        if let (Some(w), Some(g)) = (want, got) {
            hits += 1;
            assert!((w.t - g.t).abs() < 1e-4 * w.t, "t {} vs {}", g.t, w.t);
            let n = shape.surface(&ray, g).normal.normalize();
            let analytic = torus.surface(&ray, w).normal.normalize();
            assert!((n - analytic).length() < 1e-3, "{n} vs {analytic}");
        } else {
            // A hit on one side only must be a graze: the ray never gets well inside.
            let deepest =
                (0..4000).map(|k| value(&code, ray.at(k as f32 * 0.002).as_dvec3())).fold(f64::INFINITY, f64::min);
            assert!(deepest > -1e-3, "{want:?} vs {got:?}: f reaches {deepest}");
        }
        // Spans and the nearest hit agree.
        let mut spans = Vec::new();
        shape.spans(&ray, &mut spans);
        assert_eq!(first_crossing(&spans, f32::INFINITY).map(|h| h.t), got.map(|h| h.t));
    }
    assert!(hits > 1000);
}

#[test]
fn the_box_closes_the_solid_where_the_function_is_negative() {
    // Negative all over the box: the solid is the box itself.
    let (record, code) = implicit("x^2 + y^2 + z^2 - 9", Vec3::splat(-1.0), Vec3::ONE, 0.0);
    let shape = ImplicitShape { record: &record, code: &code };
    let ray = Ray::new(Vec3::new(0.2, 0.3, 5.0), Vec3::NEG_Z);
    let hit = shape.intersect(&ray, f32::INFINITY).unwrap();
    assert_eq!(hit.t, 4.0);
    assert_eq!(shape.surface(&ray, hit).normal, Vec3::Z);
    // From inside, the exit face.
    let inside = Ray::new(Vec3::ZERO, Vec3::X);
    let hit = shape.intersect(&inside, f32::INFINITY).unwrap();
    assert_eq!((hit.t, shape.surface(&inside, hit).normal), (1.0, Vec3::X));
    let mut spans = Vec::new();
    shape.spans(&ray, &mut spans);
    assert_eq!((spans.len(), spans[0].enter.t, spans[0].exit.t), (1, 4.0, 6.0));
}

#[test]
fn many_thin_shells_are_all_found() {
    // sin(20x) has 13 roots in [-1, 1]: every one must be a crossing.
    let (record, code) = implicit("sin(20*x) + 0*y*z", Vec3::splat(-1.0), Vec3::ONE, 0.0);
    let shape = ImplicitShape { record: &record, code: &code };
    let ray = Ray::new(Vec3::new(-3.0, 0.1, 0.2), Vec3::X);
    let mut spans = Vec::new();
    shape.spans(&ray, &mut spans);
    let crossings = spans.iter().map(|s| 2 - (s.enter.t == 2.0) as usize - (s.exit.t == 4.0) as usize).sum::<usize>();
    assert_eq!(crossings, 13, "{spans:?}");
    for s in &spans {
        let mid = ray.at(0.5 * (s.enter.t + s.exit.t)).as_dvec3();
        assert!(value(&code, mid) < 0.0);
    }
}

/// Random expressions in the language, as text.
fn expression() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_owned()),
        Just("y".to_owned()),
        Just("z".to_owned()),
        (-3.0f32..3.0).prop_map(|c| format!("({c})")),
    ];
    leaf.prop_recursive(5, 40, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone(), prop::sample::select(vec!["+", "-", "*", "/"]))
                .prop_map(|(a, b, op)| format!("({a} {op} {b})")),
            (inner.clone(), 0u32..5).prop_map(|(a, n)| format!("({a})^{n}")),
            (inner.clone(), prop::sample::select(vec!["sqrt", "abs", "sin", "cos", "exp", "-"]))
                .prop_map(|(a, f)| format!("{f}({a})")),
            (inner.clone(), inner, prop::sample::select(vec!["min", "max"]))
                .prop_map(|(a, b, f)| format!("{f}({a}, {b})")),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// The interval extension over a ray segment contains the value, and the derivative
    /// enclosure contains `∇f·d`, at every sampled point of the segment.
    #[test]
    fn intervals_enclose_sampled_values(
        text in expression(),
        o in (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0),
        d in (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0),
        t0 in -1.0f64..1.0,
        width in 0.0f64..1.0,
    ) {
        let code = compile_expression(&text).unwrap();
        let (o, d) = (DVec3::new(o.0, o.1, o.2), DVec3::new(d.0, d.1, d.2));
        let t = Interval::new(t0, t0 + width);
        let e = bytecode::enclose_along(&code, o, d, t);
        for k in 0..=32 {
            let s = t0 + width * k as f64 / 32.0;
            let p = o + s * d;
            let v = value(&code, p);
            prop_assert!(v.is_nan() || e.v.contains(v), "{text}: f({s}) = {v} not in {:?}", e.v);
            let g = gradient(&code, p);
            let slope = g.g.dot(d);
            // Kinks (abs at 0, min/max switching) have one-sided slopes; skip non-finite.
            // The reference slope is itself a rounded dot product whose terms may cancel:
            // allow it a few ulps of the terms' magnitude outside the enclosure.
            let magnitude = (g.g * d).abs().element_sum();
            let slack = 8.0 * f64::EPSILON * magnitude.max(f64::MIN_POSITIVE);
            let near = e.d.lo - slack <= slope && slope <= e.d.hi + slack;
            if slope.is_finite() && v.is_finite() {
                prop_assert!(near || e.d.lo.is_nan(), "{text}: f'({s}) = {slope} not in {:?}", e.d);
            }
        }
    }
}

//! Polynomial root finders for ray–surface equations `f(P + t·d) = 0`.

/// Real roots of `a·t² + b·t + c = 0`, smallest first; a double root is returned twice.
///
/// Uses the cancellation-free form `q = −(b + sign(b)·√D)/2`, `t = q/a`, `t = c/q`
/// (Numerical Recipes §5.6), so a tiny root is not lost next to a large one. `None`
/// when the discriminant `D = b² − 4ac` is negative (the lecture's "imaginary roots").
pub fn solve_quadratic(a: f32, b: f32, c: f32) -> Option<(f32, f32)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let t = -c / b;
        return Some((t, t));
    }
    let discriminant = (b as f64).mul_add(b as f64, -4.0 * a as f64 * c as f64);
    if discriminant < 0.0 {
        return None;
    }
    let root = discriminant.sqrt() as f32;
    let q = -0.5 * (b + root.copysign(b));
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// Real roots of the monic quartic `t⁴ + a·t³ + b·t² + c·t + d = 0`, ascending, each
/// polished by Newton steps on the original polynomial.
///
/// Ferrari's method: depress to `y⁴ + p·y² + q·y + r` (t = y − a/4), take the largest
/// root `m > 0` of the resolvent cubic and split into two quadratics
/// `(y² + p/2 + m)² = 2m·(y − q/4m)²`. Returns at most four roots in a fixed array.
pub fn solve_quartic(a: f64, b: f64, c: f64, d: f64) -> ([f64; 4], usize) {
    let a2 = a * a;
    let p = b - 3.0 * a2 / 8.0;
    let q = c - a * b / 2.0 + a2 * a / 8.0;
    let r = d - a * c / 4.0 + a2 * b / 16.0 - 3.0 * a2 * a2 / 256.0;
    let mut roots = [0.0; 4];
    let mut n = 0;
    let push_quadratic = |qa: f64, qb: f64, qc: f64, out: &mut [f64; 4], n: &mut usize| {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            return;
        }
        let s = disc.sqrt();
        let qq = -0.5 * (qb + s.copysign(qb));
        if qq == 0.0 {
            out[*n] = 0.0;
            out[*n + 1] = 0.0;
        } else {
            out[*n] = qq / qa;
            out[*n + 1] = qc / qq;
        }
        *n += 2;
    };
    if q.abs() < 1e-12 * (1.0 + p.abs() + r.abs()) {
        // Biquadratic: z² + p·z + r = 0 with z = y².
        let mut z = [0.0; 4];
        let mut nz = 0;
        push_quadratic(1.0, p, r, &mut z, &mut nz);
        for &zi in &z[..nz] {
            if zi >= 0.0 {
                let y = zi.sqrt();
                roots[n] = y;
                roots[n + 1] = -y;
                n += 2;
            }
        }
    } else {
        let m = largest_cubic_root(p, p * p / 4.0 - r, -q * q / 8.0);
        let m = m.max(f64::MIN_POSITIVE);
        let s = (2.0 * m).sqrt();
        let k = q / (2.0 * s);
        push_quadratic(1.0, s, p / 2.0 + m - k, &mut roots, &mut n);
        push_quadratic(1.0, -s, p / 2.0 + m + k, &mut roots, &mut n);
    }
    let poly = |t: f64| (((t + a) * t + b) * t + c) * t + d;
    let dpoly = |t: f64| ((4.0 * t + 3.0 * a) * t + 2.0 * b) * t + c;
    for root in &mut roots[..n] {
        let mut t = *root - a / 4.0;
        for _ in 0..3 {
            let slope = dpoly(t);
            if slope == 0.0 {
                break;
            }
            let step = poly(t) / slope;
            if !step.is_finite() {
                break;
            }
            t -= step;
        }
        *root = t;
    }
    roots[..n].sort_by(f64::total_cmp);
    (roots, n)
}

/// The largest real root of `m³ + b·m² + c·m + d = 0` (Cardano / trigonometric form,
/// then a Newton polish).
fn largest_cubic_root(b: f64, c: f64, d: f64) -> f64 {
    // Depress: m = x − b/3 → x³ + p·x + q = 0.
    let p = c - b * b / 3.0;
    let q = 2.0 * b * b * b / 27.0 - b * c / 3.0 + d;
    let half_q = q / 2.0;
    let third_p = p / 3.0;
    let disc = half_q * half_q + third_p * third_p * third_p;
    let x = if disc > 0.0 {
        let s = disc.sqrt();
        (-half_q + s).cbrt() + (-half_q - s).cbrt()
    } else if third_p == 0.0 {
        0.0
    } else {
        // Three real roots; the largest is at angle k = 0.
        let rho = (-third_p).sqrt();
        let cos_arg = (-half_q / (rho * rho * rho)).clamp(-1.0, 1.0);
        2.0 * rho * (cos_arg.acos() / 3.0).cos()
    };
    let mut m = x - b / 3.0;
    for _ in 0..2 {
        let f = ((m + b) * m + c) * m + d;
        let df = (3.0 * m + 2.0 * b) * m + c;
        if df == 0.0 {
            break;
        }
        m -= f / df;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lecture_example_is_a_double_root_at_three() {
        // t² − 6t + 9 = 0 from P = (−3, 1), d = (0.8, −0.6) against the unit circle.
        assert_eq!(solve_quadratic(1.0, -6.0, 9.0), Some((3.0, 3.0)));
    }

    #[test]
    fn quadratic_keeps_tiny_roots() {
        // Roots 1e-6 and 1e6: the naive formula loses the small one entirely.
        let (t0, t1) = solve_quadratic(1.0, -(1e6 + 1e-6), 1.0).unwrap();
        assert!((t0 - 1e-6).abs() < 1e-12, "{t0}");
        assert!((t1 - 1e6).abs() < 1.0);
        assert_eq!(solve_quadratic(1.0, 0.0, 1.0), None);
    }

    #[test]
    fn quartic_recovers_known_roots() {
        for expected in [[-3.0, -1.0, 0.5, 2.0], [1.0, 1.0, 2.0, 3.0], [-0.1, 0.1, 4.0, 4.5]] {
            let [r0, r1, r2, r3] = expected;
            // Expand (t−r0)(t−r1)(t−r2)(t−r3).
            let a = -(r0 + r1 + r2 + r3);
            let b = r0 * r1 + r0 * r2 + r0 * r3 + r1 * r2 + r1 * r3 + r2 * r3;
            let c = -(r0 * r1 * r2 + r0 * r1 * r3 + r0 * r2 * r3 + r1 * r2 * r3);
            let d = r0 * r1 * r2 * r3;
            let (roots, n) = solve_quartic(a, b, c, d);
            assert_eq!(n, 4, "{expected:?}");
            for (got, want) in roots.iter().zip(expected) {
                assert!((got - want).abs() < 1e-6, "{roots:?} vs {expected:?}");
            }
        }
    }

    #[test]
    fn quartic_with_two_real_roots() {
        // (t² + 1)(t − 1)(t − 2) = t⁴ − 3t³ + 3t² − 3t + 2.
        let (roots, n) = solve_quartic(-3.0, 3.0, -3.0, 2.0);
        assert_eq!(n, 2);
        assert!((roots[0] - 1.0).abs() < 1e-9 && (roots[1] - 2.0).abs() < 1e-9, "{roots:?}");
    }
}

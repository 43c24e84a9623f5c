//! Robust real roots of low-degree polynomials on an interval, and bracketed refinement.
//!
//! Closed forms (Ferrari, Cardano) lose roots near tangencies, which is exactly where a
//! blob's thin neck or a grazing ray lives. Instead, following Yuksel ("High-Performance
//! Polynomial Root Finding for Graphics", HPG 2022), the roots of `p′` split the interval
//! into pieces on which `p` is monotonic; each piece holds a root iff `p` changes sign
//! across it, and a sign change on a monotonic piece is found by bracketing, which cannot
//! fail. The derivative's roots come from the same procedure one degree lower.

/// Highest degree [`roots_in`] handles.
pub const MAX_DEGREE: usize = 4;

/// `p(x) = Σ c[i]·xⁱ` by Horner's rule.
#[inline]
pub fn eval(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc.mul_add(x, ci))
}

/// The roots of `p(x) = Σ c[i]·xⁱ` (at most degree [`MAX_DEGREE`]) in `[lo, hi]` where `p`
/// changes sign, ascending, written to `out`; returns how many. A root where `p` touches
/// zero without crossing (an exact double root) is not a crossing and is not reported.
pub fn roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
    if c.len() < 2 || lo.is_nan() || hi.is_nan() || lo >= hi {
        return 0;
    }
    let degree = (c.len() - 1).min(MAX_DEGREE);
    let c = &c[..=degree];
    // The critical points split [lo, hi] into monotonic pieces.
    let mut derivative = [0.0; MAX_DEGREE];
    for i in 1..=degree {
        derivative[i - 1] = i as f64 * c[i];
    }
    let mut critical = [0.0; MAX_DEGREE];
    let n_critical = if degree >= 2 { roots_in(&derivative[..degree], lo, hi, &mut critical) } else { 0 };
    let mut n = 0;
    let mut a = lo;
    let mut fa = eval(c, a);
    for &b in critical[..n_critical].iter().chain(std::iter::once(&hi)) {
        let fb = eval(c, b);
        if (fa < 0.0) != (fb < 0.0) && n < MAX_DEGREE {
            out[n] = refine_root(|x| eval(c, x), a, b, fa, fb);
            n += 1;
        }
        (a, fa) = (b, fb);
    }
    n
}

/// Where `f` changes sign in `[a, b]`, given `f(a) = fa` and `f(b) = fb` on opposite
/// sides (`fa < 0` differs from `fb < 0`). The Illinois variant of regula falsi (Dowell &
/// Jarratt, 1971): superlinear, and the bracket never lets the root escape. Stops when
/// the bracket is as narrow as the numbers allow.
pub fn refine_root(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, mut fa: f64, mut fb: f64) -> f64 {
    let a_negative = fa < 0.0;
    let mut side = 0i8;
    for iteration in 0..256 {
        let width = b - a;
        if width.is_nan() || width <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) {
            break;
        }
        // A secant step kept inside the bracket; every fourth step (and whenever the
        // values are not usable) a bisection, so the bracket at least halves every four
        // steps even for a step-like function.
        let secant = a - fa * width / (fb - fa);
        let margin = 1e-3 * width;
        let x =
            if secant.is_finite() && iteration % 4 != 3 { secant.clamp(a + margin, b - margin) } else { 0.5 * (a + b) };
        // Zero counts with the positive side, so a function that is 0 on a whole
        // stretch is bracketed to where it turns negative.
        let fx = f(x);
        if (fx < 0.0) == a_negative {
            (a, fa) = (x, fx);
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb) = (x, fx);
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    if fa.abs() <= fb.abs() { a } else { b }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coefficients of `Π (x − r)` for the given roots, lowest degree first.
    fn from_roots(roots: &[f64]) -> Vec<f64> {
        let mut c = vec![1.0];
        for &r in roots {
            let mut next = vec![0.0; c.len() + 1];
            for (i, &ci) in c.iter().enumerate() {
                next[i + 1] += ci;
                next[i] -= r * ci;
            }
            c = next;
        }
        c
    }

    #[test]
    fn finds_every_simple_root_in_order() {
        let roots = [-1.5, -0.2, 0.7, 2.0];
        let c = from_roots(&roots);
        let mut out = [0.0; MAX_DEGREE];
        let n = roots_in(&c, -10.0, 10.0, &mut out);
        assert_eq!(n, 4);
        for (got, want) in out.iter().zip(roots) {
            assert!((got - want).abs() < 1e-12, "{out:?}");
        }
        // Only those inside the interval.
        assert_eq!(roots_in(&c, 0.0, 1.0, &mut out), 1);
        assert!((out[0] - 0.7).abs() < 1e-12);
    }

    #[test]
    fn close_roots_of_a_thin_bump_are_both_found() {
        // −(x − 1)² + 1e-8 is positive only on a band of width 2e-4 around 1 — the kind of
        // neck closed forms miss.
        let c = [-1.0 + 1e-8, 2.0, -1.0];
        let mut out = [0.0; MAX_DEGREE];
        assert_eq!(roots_in(&c, -5.0, 5.0, &mut out), 2);
        assert!((out[0] - (1.0 - 1e-4)).abs() < 1e-10 && (out[1] - (1.0 + 1e-4)).abs() < 1e-10, "{out:?}");
        // Also as a factor of a quartic.
        let quartic = from_roots(&[-3.0, 3.0]);
        let product: Vec<f64> = {
            let mut p = vec![0.0; 5];
            for (i, a) in c.iter().enumerate() {
                for (j, b) in quartic.iter().enumerate() {
                    p[i + j] += a * b;
                }
            }
            p
        };
        assert_eq!(roots_in(&product, -5.0, 5.0, &mut out), 4);
    }

    #[test]
    fn refinement_handles_steep_and_flat_functions() {
        let r = refine_root(|x: f64| x.powi(9) - 1e-9, 0.0, 1.0, -1e-9, 1.0 - 1e-9);
        assert!((r - 0.1).abs() < 1e-12, "{r}");
        let r = refine_root(|x: f64| if x < 0.3 { -1.0 } else { 1.0 }, 0.0, 1.0, -1.0, 1.0);
        assert!((r - 0.3).abs() < 1e-12, "{r}");
    }
}

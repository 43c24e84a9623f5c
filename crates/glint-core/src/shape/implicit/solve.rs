//! Every sign change of a function along a ray segment, in order, by interval
//! subdivision: a method that cannot step over a root.
//!
//! The segment is bisected depth-first, nearest half first. A piece is dropped only when
//! the interval extension proves `f ≠ 0` on all of it (Mitchell, "Robust Ray Intersection
//! with Interval Arithmetic", 1990; Knoll et al., "Fast Ray Tracing of Arbitrary Implicit
//! Surfaces with Interval and Affine Arithmetic", 2009). A piece whose derivative
//! enclosure excludes 0 is monotonic, so it holds a root exactly when its ends differ in
//! sign, and that root is refined inside its bracket. Since a dropped piece cannot hold a
//! root and every kept piece ends either monotonic or narrower than the resolution, every
//! sign change is found; only an even number of roots closer together than the
//! resolution (a graze thinner than a float) is passed over, as the solid it bounds has no
//! thickness.

use super::interval::{DualInterval, Interval};
use crate::math::polynomial::refine_root;

/// A scalar function of the ray parameter: `f(P + t·d)`.
pub trait RayFunction {
    /// The value at `t`.
    fn value(&self, t: f64) -> f64;
    /// Enclosures of the value and of `df/dt` over all of `t`.
    fn enclose(&self, t: Interval) -> DualInterval;
}

/// Whether a value is inside the solid (`f < 0`; NaN counts as outside).
#[inline]
pub fn inside(v: f64) -> bool {
    v < 0.0
}

/// Most bisection levels; `2⁻⁴⁰` of the segment is far below float resolution.
const MAX_DEPTH: u32 = 40;

/// Most enclosures evaluated for one segment. A typical ray needs a few dozen; a function
/// that is exactly 0 on a whole region (`max(f, 0)`) would otherwise be split down to the
/// resolution everywhere there. Past the budget, pieces are no longer split but still
/// checked for a sign change at their ends, so the search always ends, at a coarser
/// resolution.
const MAX_ENCLOSURES: u32 = 1 << 14;

/// Calls `visit(t, entering)` for each sign change of `f` in `[t0, t1]`, in increasing
/// order, until `visit` returns `false`. `entering` is true when `f` goes from outside
/// (≥ 0) to inside (< 0).
pub fn crossings(f: &impl RayFunction, t0: f64, t1: f64, mut visit: impl FnMut(f64, bool) -> bool) {
    if !(t0.is_finite() && t1.is_finite()) || t0 >= t1 {
        return;
    }
    // Resolution: a float's worth of the segment or of the parameter's magnitude.
    let resolution = ((t1 - t0) * (1.0 / 16_777_216.0)).max(8.0 * f64::EPSILON * t0.abs().max(t1.abs()));
    // Depth-first with an explicit stack: at most one pending sibling per level.
    let mut stack = [(0.0, 0.0, 0.0, 0.0, 0u32); MAX_DEPTH as usize + 2];
    stack[0] = (t0, t1, f.value(t0), f.value(t1), 0);
    let mut top = 1;
    let mut budget = MAX_ENCLOSURES;
    while top > 0 {
        top -= 1;
        let (a, b, fa, fb, depth) = stack[top];
        let exhausted = budget == 0;
        if !exhausted {
            budget -= 1;
            let e = f.enclose(Interval::new(a, b));
            if !e.v.contains_zero() {
                continue;
            }
            if e.d.contains_zero() && b - a > resolution && depth < MAX_DEPTH {
                let m = 0.5 * (a + b);
                let fm = f.value(m);
                // Far half below the near half on the stack, so the near half comes out first.
                stack[top] = (m, b, fm, fb, depth + 1);
                stack[top + 1] = (a, m, fa, fm, depth + 1);
                top += 2;
                continue;
            }
        }
        // Monotonic, at the resolution, or out of budget: one crossing iff the ends differ.
        {
            if inside(fa) != inside(fb) {
                let root = refine_root(|t| f.value(t), a, b, fa, fb);
                if !visit(root, inside(fb)) {
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(t − 1)(t − 1 − gap)(t − 5)`, an explicit polynomial with exact enclosures.
    struct Cubic {
        gap: f64,
    }

    impl RayFunction for Cubic {
        fn value(&self, t: f64) -> f64 {
            (t - 1.0) * (t - 1.0 - self.gap) * (t - 5.0)
        }
        fn enclose(&self, t: Interval) -> DualInterval {
            let var = DualInterval { v: t, d: Interval::point(1.0) };
            let c = |x: f64| DualInterval::constant(x);
            (var - c(1.0)) * (var - c(1.0 + self.gap)) * (var - c(5.0))
        }
    }

    #[test]
    fn finds_close_roots_in_order() {
        for gap in [1.0, 1e-3, 1e-5] {
            let mut found = Vec::new();
            crossings(&Cubic { gap }, -10.0, 10.0, |t, entering| {
                found.push((t, entering));
                true
            });
            assert_eq!(found.len(), 3, "gap {gap}: {found:?}");
            let want = [1.0, 1.0 + gap, 5.0];
            for ((t, _), w) in found.iter().zip(want) {
                assert!((t - w).abs() < 1e-9, "gap {gap}: {found:?}");
            }
            // f < 0 before 1, so the first crossing leaves the inside.
            assert_eq!(found.iter().map(|f| f.1).collect::<Vec<_>>(), [false, true, false]);
        }
    }

    /// `max(t − 3, 0) − 2·max(t − 5, 0)`: exactly 0 on all of [−10, 3], where every
    /// piece may hold a root, then a bump that falls through 0 at t = 7.
    struct FlatRegion;

    impl FlatRegion {
        fn eval(t: DualInterval) -> DualInterval {
            let c = DualInterval::constant;
            (t - c(3.0)).max(c(0.0)) - c(2.0) * (t - c(5.0)).max(c(0.0))
        }
    }

    impl RayFunction for FlatRegion {
        fn value(&self, t: f64) -> f64 {
            (t - 3.0).max(0.0) - 2.0 * (t - 5.0).max(0.0)
        }
        fn enclose(&self, t: Interval) -> DualInterval {
            Self::eval(DualInterval { v: t, d: Interval::point(1.0) })
        }
    }

    #[test]
    fn a_function_flat_at_zero_ends_in_bounded_time() {
        let mut found = Vec::new();
        crossings(&FlatRegion, -10.0, 10.0, |t, entering| {
            found.push((t, entering));
            true
        });
        // Zero counts as outside: the only sign change is the entry at 7.
        assert_eq!(found.len(), 1, "{found:?}");
        assert!((found[0].0 - 7.0).abs() < 1e-12 && found[0].1, "{found:?}");
    }

    #[test]
    fn stops_when_asked() {
        let mut count = 0;
        crossings(&Cubic { gap: 1.0 }, -10.0, 10.0, |_, _| {
            count += 1;
            false
        });
        assert_eq!(count, 1);
    }
}

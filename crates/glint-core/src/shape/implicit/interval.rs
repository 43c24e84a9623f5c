//! Interval arithmetic: each operation returns an interval that contains every value the
//! exact operation takes on its argument intervals (Moore, "Interval Analysis", 1966).
//!
//! Results are computed in f64 with round-to-nearest and then widened outward by one ulp
//! (a few for the transcendental functions, whose library results are not correctly
//! rounded), so the enclosure holds for the values a point evaluation in f64 produces.
//! A NaN bound means "anything": [`Interval::contains_zero`] then answers yes, so an
//! undefined operation can only make the solver look closer, never skip a root.

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The closed interval `[lo, hi]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

/// The next f64 towards +∞ (`f64::next_up`, kept local for the crate's minimum Rust).
#[inline]
pub fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let bits = x.to_bits();
    f64::from_bits(if x > 0.0 { bits + 1 } else { bits - 1 })
}

/// The next f64 towards −∞.
#[inline]
pub fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// `a·b` with `0·∞ = 0`: an exact zero times an unbounded end is zero in interval
/// arithmetic (the zero is attained, the infinity only approached).
#[inline]
fn mul_end(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 { 0.0 } else { a * b }
}

impl Interval {
    pub const ENTIRE: Interval = Interval { lo: f64::NEG_INFINITY, hi: f64::INFINITY };
    /// Every positive number (for "strictly increasing").
    pub const POSITIVE: Interval = Interval { lo: f64::MIN_POSITIVE, hi: f64::INFINITY };
    /// Every negative number.
    pub const NEGATIVE: Interval = Interval { lo: f64::NEG_INFINITY, hi: -f64::MIN_POSITIVE };

    #[inline]
    pub const fn new(lo: f64, hi: f64) -> Self {
        Interval { lo, hi }
    }

    #[inline]
    pub const fn point(x: f64) -> Self {
        Interval { lo: x, hi: x }
    }

    /// `[lo, hi]` widened outward by `ulps` steps.
    #[inline]
    fn outward(lo: f64, hi: f64, ulps: u32) -> Self {
        let (mut lo, mut hi) = (lo, hi);
        for _ in 0..ulps {
            lo = next_down(lo);
            hi = next_up(hi);
        }
        Interval { lo, hi }
    }

    /// Whether 0 may be a value (always true when a bound is NaN).
    #[inline]
    pub fn contains_zero(self) -> bool {
        !(self.lo > 0.0 || self.hi < 0.0)
    }

    #[inline]
    pub fn contains(self, x: f64) -> bool {
        !(self.lo > x || self.hi < x)
    }

    /// The smallest interval holding both.
    #[inline]
    pub fn hull(self, o: Interval) -> Interval {
        Interval { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    /// The common part; empty (lo > hi) when they do not overlap.
    #[inline]
    pub fn meet(self, o: Interval) -> Interval {
        Interval { lo: self.lo.max(o.lo), hi: self.hi.min(o.hi) }
    }

    /// `o + t·d` for `t` in `self`: the interval of one coordinate along a ray segment.
    #[inline]
    pub fn along(self, o: f64, d: f64) -> Interval {
        let (a, b) = (o + mul_end(self.lo, d), o + mul_end(self.hi, d));
        Interval::outward(a.min(b), a.max(b), 1)
    }

    /// `1/self`; everything when the divisor may be zero.
    #[inline]
    pub fn recip(self) -> Interval {
        if self.contains_zero() {
            return Interval::ENTIRE;
        }
        Interval::outward(1.0 / self.hi, 1.0 / self.lo, 1)
    }

    /// `selfⁿ` for an integer `n ≥ 0`, exact in shape (an even power of an interval
    /// around zero starts at zero).
    pub fn powi(self, n: u32) -> Interval {
        if n == 0 {
            return Interval::point(1.0);
        }
        let p = |x: f64| x.powi(n as i32);
        // powi rounds once per multiplication: widen by as many ulps.
        let ulps = n.min(64);
        if n % 2 == 1 || self.lo >= 0.0 {
            Interval::outward(p(self.lo), p(self.hi), ulps)
        } else if self.hi <= 0.0 {
            Interval::outward(p(self.hi), p(self.lo), ulps)
        } else {
            Interval::outward(0.0, p(self.lo.abs().max(self.hi)), ulps).max_zero_lo()
        }
    }

    /// Clamps the lower end at zero (for values that cannot be negative).
    #[inline]
    fn max_zero_lo(self) -> Interval {
        Interval { lo: self.lo.max(0.0), hi: self.hi }
    }

    /// `√max(x, 0)`: the implicit language's square root is defined everywhere.
    #[inline]
    pub fn sqrt(self) -> Interval {
        Interval::outward(self.lo.max(0.0).sqrt(), self.hi.max(0.0).sqrt(), 1).max_zero_lo()
    }

    #[inline]
    pub fn abs(self) -> Interval {
        if self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            -self
        } else {
            Interval { lo: 0.0, hi: (-self.lo).max(self.hi) }
        }
    }

    #[inline]
    pub fn exp(self) -> Interval {
        Interval::outward(self.lo.exp(), self.hi.exp(), 2).max_zero_lo()
    }

    #[inline]
    pub fn min(self, o: Interval) -> Interval {
        Interval { lo: self.lo.min(o.lo), hi: self.hi.min(o.hi) }
    }

    #[inline]
    pub fn max(self, o: Interval) -> Interval {
        Interval { lo: self.lo.max(o.lo), hi: self.hi.max(o.hi) }
    }

    /// `sin` over the interval: the end values, plus ±1 where a crest `π/2 + 2kπ` or a
    /// trough `−π/2 + 2kπ` lies inside.
    pub fn sin(self) -> Interval {
        self.periodic(f64::sin, FRAC_PI_2)
    }

    /// `cos(x) = sin(x + π/2)`: crests at `2kπ`, troughs at `π + 2kπ`.
    pub fn cos(self) -> Interval {
        self.periodic(f64::cos, 0.0)
    }

    /// A sine-like function with its maxima at `crest + 2kπ` and minima half a period on.
    fn periodic(self, f: fn(f64) -> f64, crest: f64) -> Interval {
        // Beyond 2^50 the spacing of f64 exceeds the period: no useful bound.
        let width = self.hi - self.lo;
        if width.is_nan() || width >= TAU || self.lo.abs().max(self.hi.abs()) > 1.0e15 {
            return Interval::new(-1.0, 1.0);
        }
        let (a, b) = (f(self.lo), f(self.hi));
        let (mut lo, mut hi) = (a.min(b), a.max(b));
        // Some crest/trough x with lo ≤ x ≤ hi? Tested with a little slack so rounding in
        // the comparison can only add an extremum, never drop one.
        let hits = |phase: f64| {
            let k = ((self.lo - phase) / TAU).ceil();
            let x = phase + k * TAU;
            x <= self.hi + 1e-12 * (1.0 + self.hi.abs()) || x - TAU >= self.lo - 1e-12 * (1.0 + self.lo.abs())
        };
        if hits(crest) {
            hi = 1.0;
        }
        if hits(crest + PI) {
            lo = -1.0;
        }
        let widened = Interval::outward(lo, hi, 2);
        Interval { lo: widened.lo.max(-1.0), hi: widened.hi.min(1.0) }
    }
}

impl Add for Interval {
    type Output = Interval;
    #[inline]
    fn add(self, o: Interval) -> Interval {
        Interval::outward(self.lo + o.lo, self.hi + o.hi, 1)
    }
}

impl Sub for Interval {
    type Output = Interval;
    #[inline]
    fn sub(self, o: Interval) -> Interval {
        Interval::outward(self.lo - o.hi, self.hi - o.lo, 1)
    }
}

impl Neg for Interval {
    type Output = Interval;
    #[inline]
    fn neg(self) -> Interval {
        Interval { lo: -self.hi, hi: -self.lo }
    }
}

impl Mul for Interval {
    type Output = Interval;
    #[inline]
    fn mul(self, o: Interval) -> Interval {
        let p = [mul_end(self.lo, o.lo), mul_end(self.lo, o.hi), mul_end(self.hi, o.lo), mul_end(self.hi, o.hi)];
        if p.iter().any(|x| x.is_nan()) {
            return Interval::new(f64::NAN, f64::NAN);
        }
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::outward(lo, hi, 1)
    }
}

impl Div for Interval {
    type Output = Interval;
    /// Everything when the divisor may be zero.
    #[inline]
    fn div(self, o: Interval) -> Interval {
        if o.contains_zero() {
            return Interval::ENTIRE;
        }
        Mul::mul(self, o.recip())
    }
}

/// A value and its derivative with respect to the ray parameter `t`, both as intervals
/// (forward-mode automatic differentiation over intervals). When the derivative's
/// interval excludes 0 over a ray segment, `f` is strictly monotonic there and holds at
/// most one root (Mitchell, "Robust Ray Intersection with Interval Arithmetic", 1990).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DualInterval {
    pub v: Interval,
    pub d: Interval,
}

impl DualInterval {
    #[inline]
    pub const fn constant(c: f64) -> Self {
        DualInterval { v: Interval::point(c), d: Interval::point(0.0) }
    }

    /// The symmetric hull `[−m, m]` of a derivative interval, for kinks (abs, min, max)
    /// where either side's slope may apply.
    #[inline]
    fn both_signs(d: Interval) -> Interval {
        let m = d.lo.abs().max(d.hi.abs());
        Interval::new(-m, m)
    }

    pub fn recip(self) -> Self {
        let r = self.v.recip();
        // (1/u)′ = −u′/u²
        DualInterval { v: r, d: -self.d * (r * r) }
    }

    pub fn powi(self, n: u32) -> Self {
        if n == 0 {
            return DualInterval::constant(1.0);
        }
        let d = Interval::point(n as f64) * self.v.powi(n - 1) * self.d;
        DualInterval { v: self.v.powi(n), d }
    }

    pub fn sqrt(self) -> Self {
        let v = self.v.sqrt();
        // Where the argument may be ≤ 0 the slope is unbounded (or 0 after the clamp).
        let d = if self.v.lo > 0.0 { self.d * (Interval::point(2.0) * v).recip() } else { Interval::ENTIRE };
        DualInterval { v, d }
    }

    pub fn abs(self) -> Self {
        if self.v.lo > 0.0 {
            self
        } else if self.v.hi < 0.0 {
            -self
        } else {
            DualInterval { v: self.v.abs(), d: Self::both_signs(self.d) }
        }
    }

    pub fn sin(self) -> Self {
        DualInterval { v: self.v.sin(), d: self.v.cos() * self.d }
    }

    pub fn cos(self) -> Self {
        DualInterval { v: self.v.cos(), d: -self.v.sin() * self.d }
    }

    pub fn exp(self) -> Self {
        let v = self.v.exp();
        DualInterval { v, d: v * self.d }
    }

    pub fn min(self, o: Self) -> Self {
        if self.v.hi < o.v.lo {
            self
        } else if o.v.hi < self.v.lo {
            o
        } else {
            DualInterval { v: self.v.min(o.v), d: self.d.hull(o.d) }
        }
    }

    pub fn max(self, o: Self) -> Self {
        if self.v.lo > o.v.hi {
            self
        } else if o.v.lo > self.v.hi {
            o
        } else {
            DualInterval { v: self.v.max(o.v), d: self.d.hull(o.d) }
        }
    }
}

impl Add for DualInterval {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        DualInterval { v: self.v + o.v, d: self.d + o.d }
    }
}

impl Sub for DualInterval {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        DualInterval { v: self.v - o.v, d: self.d - o.d }
    }
}

impl Neg for DualInterval {
    type Output = Self;
    fn neg(self) -> Self {
        DualInterval { v: -self.v, d: -self.d }
    }
}

impl Mul for DualInterval {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        DualInterval { v: self.v * o.v, d: self.v * o.d + self.d * o.v }
    }
}

impl Div for DualInterval {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        Mul::mul(self, o.recip())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(i: Interval) -> impl Iterator<Item = f64> {
        (0..=64).map(move |k| i.lo + (i.hi - i.lo) * k as f64 / 64.0)
    }

    #[test]
    fn elementary_functions_enclose_their_samples() {
        let cases = [
            Interval::new(-3.0, 2.0),
            Interval::new(0.1, 0.2),
            Interval::new(-7.5, -7.4),
            Interval::new(1.0, 8.0),
            Interval::new(-1e-3, 1e-3),
        ];
        for i in cases {
            let check = |name: &str, e: Interval, f: &dyn Fn(f64) -> f64| {
                for x in samples(i) {
                    assert!(e.contains(f(x)), "{name}({x}) = {} not in {e:?} for {i:?}", f(x));
                }
            };
            check("sin", i.sin(), &f64::sin);
            check("cos", i.cos(), &f64::cos);
            check("exp", i.exp(), &f64::exp);
            check("sqrt", i.sqrt(), &|x: f64| x.max(0.0).sqrt());
            check("abs", i.abs(), &f64::abs);
            for n in 0..6 {
                check("powi", i.powi(n), &|x: f64| x.powi(n as i32));
            }
            let j = Interval::new(0.5, 1.5);
            check("mul", i * j, &|x| x * 0.75);
            check("div", i / j, &|x| x / 0.75);
        }
    }

    #[test]
    fn sine_extrema_inside_are_found() {
        let s = Interval::new(1.0, 2.0).sin(); // contains π/2
        assert_eq!(s.hi, 1.0);
        assert!(s.lo > 0.8);
        let c = Interval::new(3.0, 3.3).cos(); // contains π
        assert_eq!(c.lo, -1.0);
        assert_eq!(Interval::new(0.0, 100.0).sin(), Interval::new(-1.0, 1.0));
    }

    #[test]
    fn division_by_an_interval_around_zero_is_everything() {
        assert_eq!(Interval::new(1.0, 2.0) / Interval::new(-1.0, 1.0), Interval::ENTIRE);
        assert!(Interval::new(f64::NAN, f64::NAN).contains_zero());
    }

    #[test]
    fn next_up_and_down_step_one_ulp() {
        assert!(next_up(1.0) > 1.0 && next_up(1.0) - 1.0 == f64::EPSILON);
        assert!(next_down(0.0) < 0.0);
        assert_eq!(next_up(f64::INFINITY), f64::INFINITY);
        assert!(next_down(-1.0) < -1.0);
    }
}

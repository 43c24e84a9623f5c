//! Eight lanes of `f32` and of 3-vectors, structure of arrays, for shading a wave of
//! paths side by side.
//!
//! Every operation is a plain loop over the lanes doing exactly what the scalar `f32`
//! or glam `Vec3` operation does, in the same order (glam's `dot` is
//! `(x·x' + y·y') + z·z'`, its `normalize` multiplies by `1/√(v·v)`), so a lane's value
//! is bit for bit the scalar one. Inlined into code compiled for AVX2, the loops become
//! 8-wide vector instructions: one division or square root serves eight paths.

// Lane loops index several arrays by the same lane: written so, they vectorize.
#![allow(clippy::needless_range_loop)]

use glam::Vec3;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Lanes side by side.
pub const WIDTH: usize = 8;

/// Eight `f32`s.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct F8(pub [f32; WIDTH]);

/// A lane mask: all ones where true. (Integer masks, not `bool`s, keep selects in
/// vector registers.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct M8(pub [u32; WIDTH]);

impl F8 {
    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        F8([v; WIDTH])
    }

    /// `f` of each lane.
    #[inline(always)]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        let mut out = [0.0; WIDTH];
        for k in 0..WIDTH {
            out[k] = f(self.0[k]);
        }
        F8(out)
    }

    /// `f` of each pair of lanes.
    #[inline(always)]
    pub fn zip(self, other: F8, f: impl Fn(f32, f32) -> f32) -> Self {
        let mut out = [0.0; WIDTH];
        for k in 0..WIDTH {
            out[k] = f(self.0[k], other.0[k]);
        }
        F8(out)
    }

    /// `f` of each pair of lanes, as a mask.
    #[inline(always)]
    pub fn test(self, other: F8, f: impl Fn(f32, f32) -> bool) -> M8 {
        let mut out = [0; WIDTH];
        for k in 0..WIDTH {
            out[k] = 0u32.wrapping_sub(u32::from(f(self.0[k], other.0[k])));
        }
        M8(out)
    }

    #[inline(always)]
    pub fn sqrt(self) -> Self {
        self.map(f32::sqrt)
    }

    #[inline(always)]
    pub fn abs(self) -> Self {
        self.map(f32::abs)
    }

    /// `f32::max` lane by lane (the other operand where one is NaN).
    #[inline(always)]
    pub fn max(self, other: F8) -> Self {
        self.zip(other, f32::max)
    }

    /// Set where the lane is finite: `x − x = 0` fails for ∞ and NaN. (Written as
    /// `f32::is_finite` or `< ∞`, LLVM turns the test into integer checks of each
    /// lane's bits, one lane at a time.)
    #[inline(always)]
    pub fn is_finite(self) -> M8 {
        #[allow(clippy::eq_op)]
        (self - self).is_eq(F8::splat(0.0))
    }

    #[inline(always)]
    pub fn is_lt(self, other: F8) -> M8 {
        self.test(other, |a, b| a < b)
    }

    #[inline(always)]
    pub fn is_gt(self, other: F8) -> M8 {
        self.test(other, |a, b| a > b)
    }

    #[inline(always)]
    pub fn is_le(self, other: F8) -> M8 {
        self.test(other, |a, b| a <= b)
    }

    #[inline(always)]
    pub fn is_eq(self, other: F8) -> M8 {
        self.test(other, |a, b| a == b)
    }
}

impl M8 {
    /// `a` where the mask is set, else `b`: bit for bit, NaNs and signed zeros kept.
    #[inline(always)]
    pub fn select(self, a: F8, b: F8) -> F8 {
        let mut out = [0.0; WIDTH];
        for k in 0..WIDTH {
            let bits = (a.0[k].to_bits() & self.0[k]) | (b.0[k].to_bits() & !self.0[k]);
            out[k] = f32::from_bits(bits);
        }
        F8(out)
    }

    /// [`M8::select`] of whole vectors.
    #[inline(always)]
    pub fn select3(self, a: V8, b: V8) -> V8 {
        V8 { x: self.select(a.x, b.x), y: self.select(a.y, b.y), z: self.select(a.z, b.z) }
    }

    #[inline(always)]
    pub fn and(self, other: M8) -> M8 {
        self.combine(other, |a, b| a & b)
    }

    #[inline(always)]
    pub fn or(self, other: M8) -> M8 {
        self.combine(other, |a, b| a | b)
    }

    /// Set where `self` is set and `other` is not.
    #[inline(always)]
    pub fn and_not(self, other: M8) -> M8 {
        self.combine(other, |a, b| a & !b)
    }

    #[inline(always)]
    fn combine(self, other: M8, f: impl Fn(u32, u32) -> u32) -> M8 {
        let mut out = [0; WIDTH];
        for k in 0..WIDTH {
            out[k] = f(self.0[k], other.0[k]);
        }
        M8(out)
    }

    /// Whether lane `k` is set.
    #[inline(always)]
    pub fn get(self, k: usize) -> bool {
        self.0[k] != 0
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F8 {
            type Output = F8;
            #[inline(always)]
            fn $method(self, rhs: F8) -> F8 {
                self.zip(rhs, |a, b| a $op b)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl Neg for F8 {
    type Output = F8;
    #[inline(always)]
    fn neg(self) -> F8 {
        self.map(|a| -a)
    }
}

/// Eight 3-vectors, one per lane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V8 {
    pub x: F8,
    pub y: F8,
    pub z: F8,
}

impl V8 {
    #[inline(always)]
    pub fn new(x: F8, y: F8, z: F8) -> Self {
        V8 { x, y, z }
    }

    /// `v` in lane `k`.
    #[inline(always)]
    pub fn set(&mut self, k: usize, v: Vec3) {
        (self.x.0[k], self.y.0[k], self.z.0[k]) = (v.x, v.y, v.z);
    }

    /// Lane `k`.
    #[inline(always)]
    pub fn get(&self, k: usize) -> Vec3 {
        Vec3::new(self.x.0[k], self.y.0[k], self.z.0[k])
    }

    /// glam's `dot`: `(x·x' + y·y') + z·z'`.
    #[inline(always)]
    pub fn dot(self, other: V8) -> F8 {
        self.x * other.x + self.y * other.y + self.z * other.z
    }

    /// Each lane times its own scalar.
    #[inline(always)]
    pub fn scale(self, s: F8) -> V8 {
        V8 { x: self.x * s, y: self.y * s, z: self.z * s }
    }

    /// glam's `normalize`: times `1/√(v·v)`.
    #[inline(always)]
    pub fn normalize(self) -> V8 {
        self.scale(F8::splat(1.0) / self.dot(self).sqrt())
    }

    /// glam's `normalize_or_zero`: zero where `1/|v|` is not a finite positive number.
    #[inline(always)]
    pub fn normalize_or_zero(self) -> V8 {
        let rcp = F8::splat(1.0) / self.dot(self).sqrt();
        let usable = rcp.is_gt(F8::splat(0.0)).and(rcp.is_finite());
        usable.select3(self.scale(rcp), V8::default())
    }
}

/// Component by component.
impl Mul for V8 {
    type Output = V8;
    #[inline(always)]
    fn mul(self, rhs: V8) -> V8 {
        V8 { x: self.x * rhs.x, y: self.y * rhs.y, z: self.z * rhs.z }
    }
}

impl Add for V8 {
    type Output = V8;
    #[inline(always)]
    fn add(self, rhs: V8) -> V8 {
        V8 { x: self.x + rhs.x, y: self.y + rhs.y, z: self.z + rhs.z }
    }
}

impl Neg for V8 {
    type Output = V8;
    #[inline(always)]
    fn neg(self) -> V8 {
        V8 { x: -self.x, y: -self.y, z: -self.z }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lanes(vs: &[Vec3; WIDTH]) -> V8 {
        let mut out = V8::default();
        for (k, v) in vs.iter().enumerate() {
            out.set(k, *v);
        }
        out
    }

    #[test]
    fn lane_operations_give_glams_bits() {
        let vs: [Vec3; WIDTH] = std::array::from_fn(|k| {
            let t = k as f32 * 0.731 + 0.1;
            Vec3::new(t.sin() * 3.7, (t * 1.3).cos() * 1e-3, -t * 17.0)
        });
        let ws: [Vec3; WIDTH] = std::array::from_fn(|k| Vec3::new(0.2 + k as f32, -0.5, 1.0 / (k as f32 + 0.3)));
        let (v, w) = (lanes(&vs), lanes(&ws));
        for k in 0..WIDTH {
            assert_eq!(v.dot(w).0[k].to_bits(), vs[k].dot(ws[k]).to_bits());
            assert_eq!(v.normalize().get(k), vs[k].normalize());
            assert_eq!(v.normalize_or_zero().get(k), vs[k].normalize_or_zero());
            assert_eq!((v * w + w).get(k), vs[k] * ws[k] + ws[k]);
        }
        let zero = V8::default().normalize_or_zero();
        assert_eq!(zero, V8::default());
    }

    #[test]
    fn finite_lanes_are_those_f32_calls_finite() {
        let v = F8([0.0, -0.0, 1e38, f32::MAX, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, f32::MIN_POSITIVE / 4.0]);
        let finite = v.is_finite();
        for k in 0..WIDTH {
            assert_eq!(finite.get(k), v.0[k].is_finite(), "{}", v.0[k]);
        }
    }

    #[test]
    fn select_keeps_bits_and_masks_combine() {
        let a = F8([-0.0, f32::NAN, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let b = F8::splat(9.0);
        let m = a.is_gt(F8::splat(2.5)).or(a.is_eq(F8::splat(-0.0)));
        let s = m.select(a, b);
        assert_eq!(s.0[0].to_bits(), (-0.0f32).to_bits());
        assert_eq!(s.0[1], 9.0, "NaN > 2.5 is false");
        assert_eq!(&s.0[2..], &[9.0, 9.0, 3.0, 4.0, 5.0, 6.0]);
        assert!(m.and_not(a.is_lt(F8::splat(4.5))).get(7) && !m.and_not(a.is_lt(F8::splat(4.5))).get(4));
    }
}

//! Eight `f32` lanes, the width of one [`super::WideNode`]: one AVX register where the
//! CPU has AVX2 (checked at run time), two 4-lane `glam` vectors (SSE, NEON) elsewhere.
//! The traversal is written once over [`Lanes`] and compiled for both, so a binary built
//! for the x86-64 baseline still runs 8-wide on the machines that can.
//!
//! Lane values are made only through a [`Lanes`] token, and the AVX2 token only by
//! [`Avx2::detect`] on a CPU that has AVX2: safe code cannot reach an AVX instruction
//! on a CPU without one.

use glam::Vec4;

/// A way to make eight-lane values, and the proof that this CPU runs the instructions
/// behind them: a zero-sized token passed down the traversal.
pub trait Lanes: Copy {
    /// The values these lanes make.
    type V: F32x8;
    /// The eight values, lane `i` = `values[i]`.
    fn load(self, values: &[f32; 8]) -> Self::V;
    /// `x` in every lane.
    fn splat(self, x: f32) -> Self::V;
}

/// The few operations a slab test over eight boxes needs. Results are the same, lane
/// for lane and bit for bit, in every implementation (plain IEEE operations, no FMA).
pub trait F32x8: Copy {
    /// Lane-wise `self − other`.
    fn sub(self, other: Self) -> Self;
    /// Lane-wise `self · other`.
    fn mul(self, other: Self) -> Self;
    /// The smaller of each pair (the second operand where either is NaN).
    fn min(self, other: Self) -> Self;
    /// The larger of each pair (the second operand where either is NaN).
    fn max(self, other: Self) -> Self;
    /// Bit `i` set where lane `i` of `self` ≤ lane `i` of `other`.
    fn le_mask(self, other: Self) -> u32;
    /// `yes` in the lanes where `self` ≤ `other`, `no` in the others.
    fn select_le(self, other: Self, yes: Self, no: Self) -> Self;
    /// The lanes back as an array, lane `i` at index `i`.
    fn to_array(self) -> [f32; 8];
}

/// The lanes every CPU runs: two `glam::Vec4` halves (SSE on x86-64, NEON on AArch64,
/// scalar elsewhere).
#[derive(Clone, Copy, Debug, Default)]
pub struct Portable;

/// Eight lanes of [`Portable`].
#[derive(Clone, Copy, Debug)]
pub struct PortableF32x8([Vec4; 2]);

impl Lanes for Portable {
    type V = PortableF32x8;
    #[inline(always)]
    fn load(self, v: &[f32; 8]) -> PortableF32x8 {
        PortableF32x8([Vec4::new(v[0], v[1], v[2], v[3]), Vec4::new(v[4], v[5], v[6], v[7])])
    }
    #[inline(always)]
    fn splat(self, x: f32) -> PortableF32x8 {
        PortableF32x8([Vec4::splat(x); 2])
    }
}

impl F32x8 for PortableF32x8 {
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        PortableF32x8([self.0[0] - o.0[0], self.0[1] - o.0[1]])
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        PortableF32x8([self.0[0] * o.0[0], self.0[1] * o.0[1]])
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        // `a < b ? a : b`, the semantics of SSE's `minps` and AVX's `vminps`.
        PortableF32x8([0, 1].map(|h| Vec4::select(self.0[h].cmplt(o.0[h]), self.0[h], o.0[h])))
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        PortableF32x8([0, 1].map(|h| Vec4::select(self.0[h].cmpgt(o.0[h]), self.0[h], o.0[h])))
    }
    #[inline(always)]
    fn le_mask(self, o: Self) -> u32 {
        self.0[0].cmple(o.0[0]).bitmask() | self.0[1].cmple(o.0[1]).bitmask() << 4
    }
    #[inline(always)]
    fn select_le(self, o: Self, yes: Self, no: Self) -> Self {
        PortableF32x8([0, 1].map(|h| Vec4::select(self.0[h].cmple(o.0[h]), yes.0[h], no.0[h])))
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let (a, b) = (self.0[0].to_array(), self.0[1].to_array());
        [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx::Avx2;

/// The body of a query with an AVX2 twin: returns `$avx2` (a call of a
/// `#[target_feature(enable = "avx2")]` function, given the [`Avx2`] token as `$token`)
/// where the CPU has AVX2, and `$portable` elsewhere. Detection is cached by `std`, so
/// the check costs a load.
macro_rules! on_avx2_or {
    (|$token:ident| $avx2:expr, $portable:expr) => {{
        #[cfg(target_arch = "x86_64")]
        if let Some($token) = $crate::accel::lanes::Avx2::detect() {
            // SAFETY: the token exists, so this CPU has AVX2, the one target feature `$avx2` needs.
            return unsafe { $avx2 };
        }
        $portable
    }};
}
pub(crate) use on_avx2_or;

/// For tests that compare the AVX2 lanes with the portable ones: whether this CPU runs
/// AVX2. Where it does not, the comparison cannot run (the dispatched path *is* the
/// portable one), so the test says once on stderr that it skipped it rather than pass
/// by comparing the portable path with itself.
#[cfg(test)]
pub(crate) fn avx2_or_skip(test: &'static str) -> bool {
    #[cfg(target_arch = "x86_64")]
    if Avx2::detect().is_some() {
        return true;
    }
    static NOTED: std::sync::Mutex<Vec<&'static str>> = std::sync::Mutex::new(Vec::new());
    let mut noted = NOTED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if !noted.contains(&test) {
        noted.push(test);
        eprintln!("SKIPPED: no AVX2: {test} compares only the portable lanes");
    }
    false
}

/// [`avx2_or_skip`] that hands over the token, for tests that call AVX2 code directly.
#[cfg(all(test, target_arch = "x86_64"))]
pub(crate) fn avx2_token_or_skip(test: &'static str) -> Option<Avx2> {
    avx2_or_skip(test).then(Avx2::detect).flatten()
}

/// Asks the CPU to start loading the `bytes` at `value` into cache now: a node the
/// traversal will test soon is then (mostly) there when it gets to it, as Embree's
/// traversal prefetches the children it pushes. A hint only; a no-op off x86-64.
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let base = (value as *const T).cast::<i8>();
        for line in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: a prefetch never faults and reads nothing; the addresses lie within `value`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(base.wrapping_add(line)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::*;

    use super::{F32x8, Lanes};

    /// Proof that this CPU has AVX2: made only by [`Avx2::detect`], so every AVX2 lane
    /// value, made through it, exists only on a CPU that runs its instructions.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx2 {
        _detected: (),
    }

    impl Avx2 {
        /// The token, where this CPU has AVX2 (the answer is cached by `std`).
        #[inline]
        pub(crate) fn detect() -> Option<Self> {
            std::arch::is_x86_feature_detected!("avx2").then_some(Avx2 { _detected: () })
        }
    }

    /// One 256-bit AVX register, made only through an [`Avx2`] token. The methods are
    /// `inline(always)` so they melt into the `#[target_feature(enable = "avx2")]`
    /// functions that call them (elsewhere they would not inline).
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx2F32x8(__m256);

    // SAFETY (every block below): the intrinsics need AVX, which the CPU has: a value
    // of `Avx2F32x8` comes from an `Avx2` token, which only `detect` makes; the loads
    // read exactly the eight floats of the array they are given.
    impl Lanes for Avx2 {
        type V = Avx2F32x8;
        #[inline(always)]
        fn load(self, v: &[f32; 8]) -> Avx2F32x8 {
            Avx2F32x8(unsafe { _mm256_loadu_ps(v.as_ptr()) })
        }
        #[inline(always)]
        fn splat(self, x: f32) -> Avx2F32x8 {
            Avx2F32x8(unsafe { _mm256_set1_ps(x) })
        }
    }

    impl F32x8 for Avx2F32x8 {
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            Avx2F32x8(unsafe { _mm256_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            Avx2F32x8(unsafe { _mm256_mul_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            Avx2F32x8(unsafe { _mm256_min_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            Avx2F32x8(unsafe { _mm256_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn le_mask(self, o: Self) -> u32 {
            unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) as u32 }
        }
        #[inline(always)]
        fn select_le(self, o: Self, yes: Self, no: Self) -> Self {
            Avx2F32x8(unsafe { _mm256_blendv_ps(no.0, yes.0, _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) })
        }
        #[inline(always)]
        fn to_array(self) -> [f32; 8] {
            let mut out = [0.0; 8];
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both implementations agree bit for bit, NaNs and infinities included.
    #[test]
    fn implementations_agree() {
        let a = [1.0, -0.0, f32::NAN, f32::INFINITY, 3.5, -2.0, 0.0, f32::NEG_INFINITY];
        let b = [2.0, 0.0, 1.0, f32::NAN, -3.5, -2.0, -0.0, 7.0];
        type Pv = PortableF32x8;
        let p = |f: fn(Pv, Pv) -> Pv| f(Portable.load(&a), Portable.load(&b)).to_array();
        assert_eq!(Portable.load(&a).le_mask(Portable.load(&b)), 0b1110_0011);
        let pick = |x: Pv, y: Pv| x.select_le(y, Portable.splat(1.0), Portable.splat(2.0));
        assert_eq!(p(pick), [1.0, 1.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0]);
        #[cfg(target_arch = "x86_64")]
        if let Some(lanes) = avx2_token_or_skip("lanes::implementations_agree") {
            type Av = avx::Avx2F32x8;
            #[target_feature(enable = "avx2")]
            fn avx(lanes: Avx2, a: &[f32; 8], b: &[f32; 8], f: fn(Av, Av) -> Av) -> [f32; 8] {
                f(lanes.load(a), lanes.load(b)).to_array()
            }
            #[target_feature(enable = "avx2")]
            fn avx_mask(lanes: Avx2, a: &[f32; 8], b: &[f32; 8]) -> u32 {
                lanes.load(a).le_mask(lanes.load(b))
            }
            #[target_feature(enable = "avx2")]
            fn avx_pick(lanes: Avx2, a: &[f32; 8], b: &[f32; 8]) -> [f32; 8] {
                lanes.load(a).select_le(lanes.load(b), lanes.splat(1.0), lanes.splat(2.0)).to_array()
            }
            let bits = |v: [f32; 8]| v.map(f32::to_bits);
            // SAFETY: the token says this CPU has AVX2.
            unsafe {
                assert_eq!(bits(p(F32x8::min)), bits(avx(lanes, &a, &b, F32x8::min)));
                assert_eq!(bits(p(F32x8::max)), bits(avx(lanes, &a, &b, F32x8::max)));
                assert_eq!(bits(p(F32x8::sub)), bits(avx(lanes, &a, &b, F32x8::sub)));
                assert_eq!(bits(p(F32x8::mul)), bits(avx(lanes, &a, &b, F32x8::mul)));
                assert_eq!(avx_mask(lanes, &a, &b), 0b1110_0011);
                assert_eq!(bits(p(pick)), bits(avx_pick(lanes, &a, &b)));
            }
        }
    }
}

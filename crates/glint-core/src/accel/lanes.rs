//! Eight `f32` lanes, the width of one [`super::WideNode`]: one AVX register where the
//! CPU has AVX2 (checked at run time), two 4-lane `glam` vectors (SSE, NEON) elsewhere.
//! The traversal is written once over [`F32x8`] and compiled for both, so a binary built
//! for the x86-64 baseline still runs 8-wide on the machines that can.

use glam::Vec4;

/// The few operations a slab test over eight boxes needs. Results are the same, lane
/// for lane and bit for bit, in every implementation (plain IEEE operations, no FMA).
pub trait F32x8: Copy {
    /// The eight values, lane `i` = `values[i]`.
    fn load(values: &[f32; 8]) -> Self;
    /// `x` in every lane.
    fn splat(x: f32) -> Self;
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

/// Two `glam::Vec4` halves: SSE on x86-64, NEON on AArch64, scalar elsewhere.
#[derive(Clone, Copy, Debug)]
pub struct Portable([Vec4; 2]);

impl F32x8 for Portable {
    #[inline(always)]
    fn load(v: &[f32; 8]) -> Self {
        Portable([Vec4::new(v[0], v[1], v[2], v[3]), Vec4::new(v[4], v[5], v[6], v[7])])
    }
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Portable([Vec4::splat(x); 2])
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Portable([self.0[0] - o.0[0], self.0[1] - o.0[1]])
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Portable([self.0[0] * o.0[0], self.0[1] * o.0[1]])
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        // `a < b ? a : b`, the semantics of SSE's `minps` and AVX's `vminps`.
        Portable([0, 1].map(|h| Vec4::select(self.0[h].cmplt(o.0[h]), self.0[h], o.0[h])))
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Portable([0, 1].map(|h| Vec4::select(self.0[h].cmpgt(o.0[h]), self.0[h], o.0[h])))
    }
    #[inline(always)]
    fn le_mask(self, o: Self) -> u32 {
        self.0[0].cmple(o.0[0]).bitmask() | self.0[1].cmple(o.0[1]).bitmask() << 4
    }
    #[inline(always)]
    fn select_le(self, o: Self, yes: Self, no: Self) -> Self {
        Portable([0, 1].map(|h| Vec4::select(self.0[h].cmple(o.0[h]), yes.0[h], no.0[h])))
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let (a, b) = (self.0[0].to_array(), self.0[1].to_array());
        [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx::{Avx2, has_avx2};

/// The body of a query with an AVX2 twin: returns `$avx2` (a call of a
/// `#[target_feature(enable = "avx2")]` function) where the CPU has AVX2, and
/// `$portable` elsewhere. Detection is cached by `std`, so the check costs a load.
macro_rules! on_avx2_or {
    ($avx2:expr, $portable:expr) => {{
        #[cfg(target_arch = "x86_64")]
        if $crate::accel::lanes::has_avx2() {
            // SAFETY: this CPU has AVX2, the one target feature `$avx2` needs.
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
    if has_avx2() {
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

    use super::F32x8;

    /// One 256-bit AVX register. Its methods run AVX instructions, so they are sound only
    /// on a CPU that has them: crate-private, and used only after [`has_avx2`] said yes.
    /// They are `inline(always)` so they melt into the `#[target_feature(enable =
    /// "avx2")]` functions that call them (elsewhere they would not inline).
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx2(__m256);

    /// Whether this CPU runs the AVX2 code paths (the answer is cached by `std`).
    #[inline]
    pub(crate) fn has_avx2() -> bool {
        std::arch::is_x86_feature_detected!("avx2")
    }

    // SAFETY (every block below): the intrinsics need AVX, which the caller guarantees
    // (see `Avx2`); the loads read exactly the eight floats of the array they are given.
    impl F32x8 for Avx2 {
        #[inline(always)]
        fn load(v: &[f32; 8]) -> Self {
            Avx2(unsafe { _mm256_loadu_ps(v.as_ptr()) })
        }
        #[inline(always)]
        fn splat(x: f32) -> Self {
            Avx2(unsafe { _mm256_set1_ps(x) })
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            Avx2(unsafe { _mm256_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            Avx2(unsafe { _mm256_mul_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            Avx2(unsafe { _mm256_min_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            Avx2(unsafe { _mm256_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn le_mask(self, o: Self) -> u32 {
            unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) as u32 }
        }
        #[inline(always)]
        fn select_le(self, o: Self, yes: Self, no: Self) -> Self {
            Avx2(unsafe { _mm256_blendv_ps(no.0, yes.0, _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) })
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
        let p = |f: fn(Portable, Portable) -> Portable| f(Portable::load(&a), Portable::load(&b)).to_array();
        assert_eq!(Portable::load(&a).le_mask(Portable::load(&b)), 0b1110_0011);
        let pick = |x: Portable, y: Portable| x.select_le(y, Portable::splat(1.0), Portable::splat(2.0));
        assert_eq!(p(pick), [1.0, 1.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0]);
        #[cfg(target_arch = "x86_64")]
        if avx2_or_skip("lanes::implementations_agree") {
            #[target_feature(enable = "avx2")]
            fn avx(a: &[f32; 8], b: &[f32; 8], f: fn(Avx2, Avx2) -> Avx2) -> [f32; 8] {
                f(Avx2::load(a), Avx2::load(b)).to_array()
            }
            #[target_feature(enable = "avx2")]
            fn avx_mask(a: &[f32; 8], b: &[f32; 8]) -> u32 {
                Avx2::load(a).le_mask(Avx2::load(b))
            }
            let bits = |v: [f32; 8]| v.map(f32::to_bits);
            // SAFETY: AVX2 was detected just above.
            unsafe {
                assert_eq!(bits(p(F32x8::min)), bits(avx(&a, &b, F32x8::min)));
                assert_eq!(bits(p(F32x8::max)), bits(avx(&a, &b, F32x8::max)));
                assert_eq!(bits(p(F32x8::sub)), bits(avx(&a, &b, F32x8::sub)));
                assert_eq!(bits(p(F32x8::mul)), bits(avx(&a, &b, F32x8::mul)));
                assert_eq!(avx_mask(&a, &b), 0b1110_0011);
                let avx_pick = |x: Avx2, y: Avx2| x.select_le(y, Avx2::splat(1.0), Avx2::splat(2.0));
                assert_eq!(bits(p(pick)), bits(avx(&a, &b, avx_pick)));
            }
        }
    }
}

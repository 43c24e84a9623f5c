//! Normalizing with a fallback, as glam does it, without leaving the vector registers.
//!
//! glam's `normalize_or` tests its reciprocal length with `is_finite`, which compiles to
//! integer checks of the float's bits: the value leaves the vector registers and the
//! test waits there for the division. A hit's normal and every offset ray origin pass
//! through it, so in the Whitted waves it was a visible share of the time. `0 < r < ∞`
//! is the same test (false for NaN, both infinities and zero). Written as two scalar
//! compares and a branch, LLVM turned it back into integer checks; as a vector compare
//! and a blend it stays in the registers and takes no branch (2.5% fewer instructions
//! on the Whitted scene of `bench/povray_whitted.sh`, the image the same).

use glam::{Vec3, Vec3A};

/// `v.normalize_or(fallback)`, bit for bit.
#[inline(always)]
pub fn unit_or(v: Vec3, fallback: Vec3) -> Vec3 {
    let rcp = Vec3A::splat(v.length_recip());
    let usable = rcp.cmpgt(Vec3A::ZERO) & rcp.cmplt(Vec3A::INFINITY);
    Vec3A::select(usable, Vec3A::from(v) * rcp, Vec3A::from(fallback)).into()
}

/// `v.normalize_or_zero()`, bit for bit.
#[inline(always)]
pub fn unit_or_zero(v: Vec3) -> Vec3 {
    unit_or(v, Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_glam_bit_for_bit_down_to_the_degenerate_vectors() {
        let mut rng = crate::sampling::Rng::new(13);
        let mut next = || (rng.next_f32() - 0.5) * 10f32.powi((rng.next_u32() % 60) as i32 - 30);
        let special = [0.0, -0.0, f32::MIN_POSITIVE, 1e-30, 1e30, f32::MAX, f32::INFINITY, f32::NAN, -1.0];
        let mut vectors: Vec<Vec3> = (0..20_000).map(|_| Vec3::new(next(), next(), next())).collect();
        for &x in &special {
            for &y in &special {
                vectors.push(Vec3::new(x, y, 1.0));
                vectors.push(Vec3::new(x, y, 0.0));
            }
        }
        for v in vectors {
            let bits = |u: Vec3| u.to_array().map(f32::to_bits);
            assert_eq!(bits(unit_or(v, Vec3::Y)), bits(v.normalize_or(Vec3::Y)), "{v}");
            assert_eq!(bits(unit_or_zero(v)), bits(v.normalize_or_zero()), "{v}");
        }
    }
}

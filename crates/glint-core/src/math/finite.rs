//! `Vec3::is_finite` in the vector registers.
//!
//! glam tests each component with `f32::is_finite`, which compiles to integer checks of
//! the float's bits, one component after another, each behind a branch. The Whitted
//! waves ask it of every hit's light and every shadow ray's: `v − v` is zero in each
//! finite lane and NaN in the others, so one vector compare answers for all three.

use glam::{Vec3, Vec3A};

/// `v.is_finite()`, the same answer for every `v`.
#[inline(always)]
#[allow(clippy::eq_op)] // `v − v` is the test, not a slip.
pub fn all_finite(v: Vec3) -> bool {
    let v = Vec3A::from(v);
    (v - v).cmpeq(Vec3A::ZERO).all()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_glam_on_every_kind_of_component() {
        let values =
            [0.0, -0.0, 1.0, -3.5, f32::MAX, f32::MIN_POSITIVE, 1e-45, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        for &x in &values {
            for &y in &values {
                for &z in &values {
                    let v = Vec3::new(x, y, z);
                    assert_eq!(all_finite(v), v.is_finite(), "{v:?}");
                }
            }
        }
    }
}

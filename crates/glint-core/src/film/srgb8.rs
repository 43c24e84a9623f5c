//! 8-bit sRGB encoding by table, exactly equal to `(linear_to_srgb(c)·255 + 0.5) as u8`.
//!
//! Encoding every pixel with `powf` costs a viewer frame about 10 ms at 640×360 (three
//! `powf` per pixel). The 8-bit code is a step function of the linear value with 255
//! steps, so it is found from the value's top 16 bits (sign, exponent and 7 mantissa
//! bits: buckets narrow enough that at most one step falls in each) and one comparison
//! with that step's exact threshold.

use std::sync::OnceLock;

use super::{linear_to_srgb, srgb_to_linear};

/// Buckets cover the bit patterns of 0.0 through 1.0.
const BUCKETS: usize = (1.0f32.to_bits() >> 16) as usize + 1;

struct Tables {
    /// The code of each bucket's smallest value.
    base: Vec<u8>,
    /// `threshold[k]`: the smallest value whose code is at least `k` (`threshold[0]` is
    /// 0); `threshold[256]` is above every value, so code 255 never steps further.
    threshold: [f32; 257],
}

/// The slow, defining encoding.
fn reference(c: f32) -> u8 {
    (linear_to_srgb(c) * 255.0 + 0.5) as u8
}

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(|| {
        let mut threshold = [f32::INFINITY; 257];
        for (code, t) in threshold.iter_mut().enumerate().take(256) {
            *t = first_value_reaching(code as u8);
        }
        // A bucket's code is that of its first value: the last step at or below it
        // (the steps rise with the value), found without a `powf` per bucket.
        let mut code = 0;
        let base = (0..BUCKETS)
            .map(|b| {
                let start = f32::from_bits((b as u32) << 16);
                while code < 255 && threshold[code + 1] <= start {
                    code += 1;
                }
                code as u8
            })
            .collect();
        Tables { base, threshold }
    })
}

/// The smallest value in [0, 1] whose code is at least `code`, searched over bit
/// patterns, which order non-negative floats as their values. The inverse transfer
/// function lands within a few units in the last place of it: bracketed from there by
/// doubling steps, then bisected, the search costs a sixth of the `powf` calls of a
/// bisection over all of [0, 1] (which every process paid at its first 8-bit image).
fn first_value_reaching(code: u8) -> f32 {
    if code == 0 {
        return 0.0;
    }
    let one = 1.0f32.to_bits();
    // Every code is reached by 1.0 (code 255), so the walk up ends.
    let reaches = |bits: u32| reference(f32::from_bits(bits)) >= code;
    let guess = srgb_to_linear((f32::from(code) - 0.5) / 255.0).clamp(0.0, 1.0).to_bits();
    let (mut high, mut step) = (guess, 1u32);
    while !reaches(high) {
        high = high.saturating_add(step).min(one);
        step = step.saturating_mul(2);
    }
    // Down from `high` to a value that does not reach the code (0 does not: its code is 0).
    let (mut low, mut step) = (high, 1u32);
    while reaches(low) {
        high = low;
        low = low.saturating_sub(step);
        step = step.saturating_mul(2);
    }
    bisect(low, high, reaches)
}

/// The smallest bit pattern in `(low, high]` that `reaches`, where `low` does not and
/// `high` does.
fn bisect(mut low: u32, mut high: u32, reaches: impl Fn(u32) -> bool) -> f32 {
    while high - low > 1 {
        let mid = low + (high - low) / 2;
        if reaches(mid) { high = mid } else { low = mid }
    }
    f32::from_bits(high)
}

/// `(linear_to_srgb(c)·255 + 0.5) as u8`, by table (what the tests check [`encoder`]'s
/// function against).
#[cfg(test)]
fn encode(c: f32) -> u8 {
    encode_with(tables(), c)
}

/// `(linear_to_srgb(c)·255 + 0.5) as u8`, by table: the function for a whole image, its
/// tables fetched once rather than checked for their one-time initialization per value.
pub fn encoder() -> impl Fn(f32) -> u8 + Copy {
    let t = tables();
    move |c| encode_with(t, c)
}

#[inline]
fn encode_with(t: &Tables, c: f32) -> u8 {
    // NaN and values at or below 0 give 0, values at or above 1 give 255.
    if c.is_nan() || c <= 0.0 {
        return 0;
    }
    if c >= 1.0 {
        return 255;
    }
    let base = t.base[(c.to_bits() >> 16) as usize];
    base + u8::from(c >= t.threshold[base as usize + 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_step_is_where_a_bisection_over_all_of_0_to_1_finds_it() {
        for code in 1..=255u8 {
            let whole_range = bisect(0, 1.0f32.to_bits(), |bits| reference(f32::from_bits(bits)) >= code);
            assert_eq!(first_value_reaching(code).to_bits(), whole_range.to_bits(), "code {code}");
        }
    }

    #[test]
    fn each_bucket_holds_at_most_one_step() {
        let t = tables();
        for b in 0..BUCKETS - 1 {
            let last = f32::from_bits(((b as u32 + 1) << 16) - 1);
            assert!(u16::from(reference(last)) <= u16::from(t.base[b]) + 1, "bucket {b} spans two steps");
        }
    }

    #[test]
    fn the_table_agrees_with_powf_around_every_step_and_across_the_range() {
        let t = tables();
        for code in 1..256 {
            let bits = t.threshold[code].to_bits();
            for near in bits.saturating_sub(300)..=bits + 300 {
                let c = f32::from_bits(near);
                assert_eq!(encode(c), reference(c), "{c:e} near the step to {code}");
            }
        }
        // Every 97th bit pattern from 0 to 1 (about 11 million values).
        for bits in (0..=1.0f32.to_bits()).step_by(97) {
            let c = f32::from_bits(bits);
            assert_eq!(encode(c), reference(c), "{c:e}");
        }
        for c in [f32::NAN, -0.0, -1.0, f32::NEG_INFINITY, 1.0, 1.5, f32::INFINITY, f32::MAX] {
            assert_eq!(encode(c), reference(c), "{c}");
        }
    }
}

//! Pixel sample patterns: where inside a pixel the sub-pixel samples are taken.

use glam::Vec2;
use serde::{Deserialize, Serialize};

use super::sequence::{hash32, unit_float};

/// The sampling strategies of the lecture and of production renderers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum SamplePattern {
    /// n×n regular supersampling (n = 1: the pixel centre).
    #[default]
    Grid,
    /// The lecture's five points: the four pixel corners and the centre.
    CornersAndCentre,
    /// n×n strata with one uniformly jittered sample in each (stochastic sampling).
    Jittered,
    /// The 2-D Sobol (0,2)-sequence with Owen scrambling seeded per pixel: every
    /// power-of-two prefix is stratified, so it also serves adaptive sampling.
    Sobol,
}

/// The sample positions of one pixel for a given pattern, count and seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelSampler {
    pub pattern: SamplePattern,
    /// Samples along each axis for the grid-based patterns (n×n in total).
    pub per_axis: u32,
    pub seed: u32,
}

impl PixelSampler {
    /// How many samples one pixel gets (before adaptive refinement).
    pub fn count(&self) -> u32 {
        match self.pattern {
            SamplePattern::CornersAndCentre => 5,
            _ => self.per_axis * self.per_axis,
        }
    }

    /// Sample `index` of pixel (`px`, `py`) as an offset in [0, 1]² from the pixel's
    /// top-left corner. Sobol accepts any index (for adaptive refinement); the others
    /// wrap around their fixed set.
    pub fn offset(&self, px: u32, py: u32, index: u32) -> Vec2 {
        let n = self.per_axis.max(1);
        match self.pattern {
            // One sample a pixel: its centre, without the integer divisions below (a
            // chain of them per camera sample, ten percent of a Whitted render's time).
            SamplePattern::Grid if n == 1 => Vec2::splat(0.5),
            SamplePattern::Grid => {
                let i = index % (n * n);
                Vec2::new((i % n) as f32 + 0.5, (i / n) as f32 + 0.5) / n as f32
            }
            SamplePattern::CornersAndCentre => {
                const POINTS: [Vec2; 5] =
                    [Vec2::new(0.5, 0.5), Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0), Vec2::ONE];
                POINTS[(index % 5) as usize]
            }
            SamplePattern::Jittered => {
                let i = index % (n * n);
                let h = hash32(&[px, py, index / (n * n), self.seed]);
                let jitter = Vec2::new(unit_float(hash32(&[h, i, 0])), unit_float(hash32(&[h, i, 1])));
                (Vec2::new((i % n) as f32, (i / n) as f32) + jitter) / n as f32
            }
            SamplePattern::Sobol => {
                let (x, y) = sobol_2d(index);
                let seed = hash32(&[px, py, self.seed]);
                Vec2::new(unit_float(owen_scramble(x, seed)), unit_float(owen_scramble(y, seed ^ 0x9e37_79b9)))
            }
        }
    }
}

/// The first two Sobol dimensions as 32-bit fixed-point fractions: dimension 0 is the
/// van der Corput sequence (bit reversal); dimension 1 uses the direction numbers of
/// the primitive polynomial x + 1, `v_j = v_{j−1} ⊕ (v_{j−1} ≫ 1)`.
///
/// Dimension 1 is the XOR of the direction numbers of the index's set bits, taken a
/// byte at a time from precomputed tables (no per-bit loop or branch).
#[inline]
pub fn sobol_2d(index: u32) -> (u32, u32) {
    let b = index.to_le_bytes();
    let y =
        SOBOL_Y[0][b[0] as usize] ^ SOBOL_Y[1][b[1] as usize] ^ SOBOL_Y[2][b[2] as usize] ^ SOBOL_Y[3][b[3] as usize];
    (index.reverse_bits(), y)
}

/// Dimension 1 of the Sobol sequence with its bits reversed (least significant bit
/// first), the form Owen scrambling works on.
#[inline]
pub(crate) fn sobol_y_reversed(index: u32) -> u32 {
    let b = index.to_le_bytes();
    let t = &SOBOL_Y_REVERSED;
    t[0][b[0] as usize] ^ t[1][b[1] as usize] ^ t[2][b[2] as usize] ^ t[3][b[3] as usize]
}

/// [`SOBOL_Y`] with every entry's bits reversed.
static SOBOL_Y_REVERSED: [[u32; 256]; 4] = {
    let mut tables = sobol_y_tables();
    let mut k = 0;
    while k < 4 {
        let mut byte = 0;
        while byte < 256 {
            tables[k][byte] = tables[k][byte].reverse_bits();
            byte += 1;
        }
        k += 1;
    }
    tables
};

/// `SOBOL_Y[k][byte]`: XOR of dimension 1's direction numbers `v_{8k+j}` for each set bit
/// `j` of `byte`.
static SOBOL_Y: [[u32; 256]; 4] = sobol_y_tables();

const fn sobol_y_tables() -> [[u32; 256]; 4] {
    let mut directions = [0u32; 32];
    let mut v = 1u32 << 31;
    let mut j = 0;
    while j < 32 {
        directions[j] = v;
        v ^= v >> 1;
        j += 1;
    }
    let mut tables = [[0u32; 256]; 4];
    let mut k = 0;
    while k < 4 {
        let mut byte = 0;
        while byte < 256 {
            let mut y = 0;
            let mut bit = 0;
            while bit < 8 {
                if byte & (1 << bit) != 0 {
                    y ^= directions[8 * k + bit];
                }
                bit += 1;
            }
            tables[k][byte] = y;
            byte += 1;
        }
        k += 1;
    }
    tables
}

/// Nested uniform (Owen) scrambling by hashing, after Burley, "Practical Hash-based
/// Owen Scrambling" (JCGT 2020): a Laine–Karras style permutation on the bit-reversed
/// value, where each output bit depends only on the bits above it.
fn owen_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// The Laine–Karras permutation of bit-reversed values: each bit is flipped by a hash
/// of the bits below it (which, reversed, are the bits above it).
#[inline]
pub(crate) fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts samples per cell of a `cells`×`cells` grid over the pixel.
    fn strata(sampler: &PixelSampler, px: u32, count: u32, cells: u32) -> Vec<u32> {
        let mut hist = vec![0; (cells * cells) as usize];
        for i in 0..count {
            let o = sampler.offset(px, 3, i);
            assert!(o.cmpge(Vec2::ZERO).all() && o.cmplt(Vec2::ONE).all(), "{o}");
            let (cx, cy) = ((o.x * cells as f32) as u32, (o.y * cells as f32) as u32);
            hist[(cy * cells + cx) as usize] += 1;
        }
        hist
    }

    #[test]
    fn jittered_puts_one_sample_in_each_stratum() {
        let s = PixelSampler { pattern: SamplePattern::Jittered, per_axis: 4, seed: 1 };
        for px in 0..20 {
            assert!(strata(&s, px, 16, 4).iter().all(|&c| c == 1));
        }
    }

    #[test]
    fn sobol_prefixes_are_stratified_in_every_elementary_interval() {
        let s = PixelSampler { pattern: SamplePattern::Sobol, per_axis: 4, seed: 5 };
        for px in 0..20 {
            // 16 points: one in each 4×4 cell, and one in each 16×1 and 1×16 strip.
            assert!(strata(&s, px, 16, 4).iter().all(|&c| c == 1));
            let mut columns = [0; 16];
            let mut rows = [0; 16];
            for i in 0..16 {
                let o = s.offset(px, 3, i);
                columns[(o.x * 16.0) as usize] += 1;
                rows[(o.y * 16.0) as usize] += 1;
            }
            assert!(columns.iter().chain(&rows).all(|&c| c == 1));
            // And the next 16 complete a 32-point net: the first 64 fill 8×8.
            assert!(strata(&s, px, 64, 8).iter().all(|&c| c == 1));
        }
    }

    #[test]
    fn sobol_is_decorrelated_between_pixels() {
        let s = PixelSampler { pattern: SamplePattern::Sobol, per_axis: 1, seed: 5 };
        let firsts: Vec<Vec2> = (0..64).map(|px| s.offset(px, 0, 0)).collect();
        let distinct = firsts.iter().filter(|a| firsts.iter().filter(|b| b == a).count() == 1).count();
        assert_eq!(distinct, 64);
    }

    #[test]
    fn sobol_tables_match_the_direction_number_recurrence() {
        for index in [0u32, 1, 2, 3, 255, 256, 12345, 0xdead_beef, u32::MAX] {
            let (mut y, mut v, mut i) = (0u32, 1u32 << 31, index);
            while i != 0 {
                if i & 1 != 0 {
                    y ^= v;
                }
                v ^= v >> 1;
                i >>= 1;
            }
            assert_eq!(sobol_2d(index), (index.reverse_bits(), y), "{index}");
            assert_eq!(sobol_y_reversed(index), y.reverse_bits());
        }
    }

    #[test]
    fn grid_and_corners_are_regular() {
        let g = PixelSampler { pattern: SamplePattern::Grid, per_axis: 2, seed: 0 };
        assert_eq!(g.offset(0, 0, 0), Vec2::splat(0.25));
        assert_eq!(g.offset(0, 0, 3), Vec2::splat(0.75));
        let c = PixelSampler { pattern: SamplePattern::CornersAndCentre, per_axis: 1, seed: 0 };
        assert_eq!(c.count(), 5);
        assert_eq!(c.offset(9, 9, 0), Vec2::splat(0.5));
        assert_eq!(c.offset(9, 9, 4), Vec2::ONE);
    }
}

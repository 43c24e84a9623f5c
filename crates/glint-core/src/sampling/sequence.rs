//! The path sampler: one stream of numbers in [0, 1) that serves every dimension of a
//! path (pixel position, lens, time, light choice, BSDF lobe and direction, roulette).
//!
//! Everything here is 32-bit integer arithmetic, so a GPU shader draws exactly the same
//! numbers: a sample is a pure function of (pixel, sample index, dimension, seed).

use glam::Vec2;

use super::pattern::{laine_karras, sobol_y_reversed};
use crate::desc::SamplerKind;

/// A 32-bit integer hash with good avalanche (Wellons' "lowbias32", bias ≈ 0.17):
/// two xor-shift-multiply rounds.
#[inline]
pub fn mix32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Folds words into one hash, each mixed with the state so far (order matters).
#[inline]
pub fn hash32(words: &[u32]) -> u32 {
    words.iter().fold(0x6a09_e667, |h, &w| mix32(h ^ mix32(w.wrapping_add(0x9e37_79b9))))
}

/// The top 24 bits as a float in [0, 1): every value exactly representable.
#[inline]
pub fn unit_float(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The numbers of one sample of one pixel, drawn dimension by dimension.
///
/// `Sobol` pads 2-D Owen-scrambled Sobol points: each pair of dimensions is the
/// (0,2)-sequence with its own per-pixel scrambling and its own shuffle of the sample
/// index (Burley 2020, "Practical Hash-based Owen Scrambling"), so every power-of-two
/// prefix of the samples is stratified in every pair while pairs stay uncorrelated.
/// `Independent` hashes (pixel, index, dimension) into each number.
#[derive(Clone, Copy, Debug)]
pub struct PathSampler {
    kind: SamplerKind,
    /// Hash of the pixel, seed and sample index (the independent sampler's base).
    sample_seed: u32,
    dimension: u32,
    /// The Sobol draws of this sample, computed together when it starts (see
    /// [`sobol_draws`]); empty for the independent sampler.
    sobol: [Vec2; SOBOL_DIMENSIONS as usize],
}

/// Dimensions (counted in draws: the pixel, then three per vertex, so the camera, the
/// first two vertices and the third's choice of light and lobe) that take Sobol points:
/// one 8-lane vector of them per sample. Later ones — the deep bounces of long paths,
/// whose contributions are small and barely gain from stratification — take hashed
/// numbers, which cost a fraction of a scrambled point. (Ten, the whole third vertex,
/// gave the same error on the Cornell box, 1.2478e-3 against 1.2490e-3 over four seeds
/// at 64 spp, for a second vector of scrambling per sample and 3 % more time.)
pub const SOBOL_DIMENSIONS: u32 = 8;

/// What every sample of one pixel shares: the pixel's hash and each Sobol dimension's
/// scrambling seed. A loop over a pixel's samples computes it once.
#[derive(Clone, Copy, Debug)]
pub struct PixelStream {
    kind: SamplerKind,
    pixel_seed: u32,
    dimension_seeds: [u32; SOBOL_LANES],
}

impl PixelStream {
    /// The streams of pixel (`px`, `py`) under `seed`.
    #[inline(always)]
    pub fn new(kind: SamplerKind, px: u32, py: u32, seed: u32) -> Self {
        let pixel_seed = hash32(&[px, py, seed]);
        let dimension_seeds = std::array::from_fn(|d| mix32(pixel_seed ^ salt(d as u32)));
        Self { kind, pixel_seed, dimension_seeds }
    }

    /// The stream of this pixel's sample `index`.
    #[inline(always)]
    pub fn sample(&self, index: u32) -> PathSampler {
        let sample_seed = mix32(self.pixel_seed ^ mix32(index));
        let sobol = match self.kind {
            // The hashes take the index with its bits reversed, the form Owen scrambling
            // shuffles.
            SamplerKind::Sobol => sobol_draws(&self.dimension_seeds, index.reverse_bits()),
            SamplerKind::Independent => [Vec2::ZERO; SOBOL_DIMENSIONS as usize],
        };
        PathSampler { kind: self.kind, sample_seed, dimension: 0, sobol }
    }
}

impl PathSampler {
    /// The stream of sample `index` of pixel (`px`, `py`).
    #[inline(always)]
    pub fn new(kind: SamplerKind, px: u32, py: u32, index: u32, seed: u32) -> Self {
        PixelStream::new(kind, px, py, seed).sample(index)
    }

    /// The next dimension, one number.
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let sobol = self.kind == SamplerKind::Sobol && self.dimension < SOBOL_DIMENSIONS;
        let dimension = self.dimension as usize;
        let salt = self.next_salt();
        match sobol {
            false => unit_float(mix32(self.sample_seed ^ salt)),
            // A Sobol dimension drawn alone is its pair's first number.
            true => self.sobol[dimension].x,
        }
    }

    /// A distinct odd multiple per dimension, to mix with the pixel's or sample's hash.
    #[inline]
    fn next_salt(&mut self) -> u32 {
        let salt = salt(self.dimension);
        self.dimension += 1;
        salt
    }

    /// The next pair of dimensions, stratified together.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let sobol = self.kind == SamplerKind::Sobol && self.dimension < SOBOL_DIMENSIONS;
        let dimension = self.dimension as usize;
        let salt = self.next_salt();
        match sobol {
            false => {
                let h = mix32(self.sample_seed ^ salt);
                Vec2::new(unit_float(h), unit_float(mix32(h ^ 0x5bd1_e995)))
            }
            true => self.sobol[dimension],
        }
    }
}

/// A distinct odd multiple per dimension, to mix with the pixel's or sample's hash.
#[inline(always)]
fn salt(dimension: u32) -> u32 {
    dimension.wrapping_mul(0x9e37_79b9).wrapping_add(0x7f4a_7c15)
}

/// Lanes of the batched Sobol computation: [`SOBOL_DIMENSIONS`] rounded up to whole
/// 8-lane vectors.
const SOBOL_LANES: usize = (SOBOL_DIMENSIONS as usize).div_ceil(8) * 8;

/// Every Sobol pair of one sample, computed side by side: each is the (0,2)-sequence at
/// the sample index under its own nested uniform shuffle, Owen-scrambled (Burley 2020),
/// and the hashes of all dimensions run as one loop that the compiler turns into 8-wide
/// integer vectors (the path loop is compiled for AVX2), a fraction of the cost of
/// drawing them one by one, where each pair's three hashes and three bit reversals wait
/// on each other.
#[inline(always)]
fn sobol_draws(seed: &[u32; SOBOL_LANES], index_reversed: u32) -> [Vec2; SOBOL_DIMENSIONS as usize] {
    let mut shuffled = [0u32; SOBOL_LANES];
    for (seed, shuffled) in seed.iter().zip(&mut shuffled) {
        // The index under this dimension's nested uniform scramble: power-of-two
        // prefixes of the samples stay whole in every pair.
        *shuffled = laine_karras(index_reversed, *seed).reverse_bits();
    }
    // Dimension 1 of the Sobol sequence, bits reversed (the form Owen scrambling takes);
    // dimension 0 reversed is the index itself.
    // (A table lookup, which does not vectorize: only for the dimensions drawn.)
    let mut second = [0u32; SOBOL_LANES];
    for (y, &i) in second.iter_mut().zip(&shuffled).take(SOBOL_DIMENSIONS as usize) {
        *y = sobol_y_reversed(i);
    }
    let (mut x, mut y) = ([0u32; SOBOL_LANES], [0u32; SOBOL_LANES]);
    for d in 0..SOBOL_LANES {
        x[d] = laine_karras(shuffled[d], seed[d] ^ 0x68bc_21eb).reverse_bits();
        y[d] = laine_karras(second[d], seed[d] ^ 0x02e5_be93).reverse_bits();
    }
    std::array::from_fn(|d| Vec2::new(unit_float(x[d]), unit_float(y[d])))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(kind: SamplerKind, px: u32, count: u32, skip: u32) -> Vec<Vec2> {
        (0..count)
            .map(|i| {
                let mut s = PathSampler::new(kind, px, 7, i, 3);
                for _ in 0..skip {
                    s.next_2d();
                }
                s.next_2d()
            })
            .collect()
    }

    #[test]
    fn every_dimension_pair_of_a_power_of_two_prefix_is_stratified() {
        for dim in [0, 1, 5, SOBOL_DIMENSIONS - 1] {
            for px in 0..8 {
                let p = points(SamplerKind::Sobol, px, 64, dim);
                // A (0,6,2)-net: one point in each of the 64 cells of every elementary
                // shape 64×1, 32×2, …, 1×64.
                for k in 0..=6 {
                    let (cx, cy) = (1u32 << k, 1u32 << (6 - k));
                    let mut cells = vec![0; 64];
                    for q in &p {
                        let (x, y) = ((q.x * cx as f32) as u32, (q.y * cy as f32) as u32);
                        cells[(y * cx + x) as usize] += 1;
                    }
                    assert!(cells.iter().all(|&c| c == 1), "dim {dim} px {px} shape {cx}x{cy}");
                }
            }
        }
    }

    #[test]
    fn dimensions_and_pixels_are_decorrelated() {
        // Pairing dimension 0's x with dimension 1's x over 4096 samples must not put
        // them on a line: check the sample correlation is small.
        let a = points(SamplerKind::Sobol, 3, 4096, 0);
        let b = points(SamplerKind::Sobol, 3, 4096, 1);
        let c = points(SamplerKind::Sobol, 4, 4096, 0);
        let corr = |u: &[Vec2], v: &[Vec2]| {
            let n = u.len() as f32;
            let (mu, mv) = (u.iter().map(|p| p.x).sum::<f32>() / n, v.iter().map(|p| p.x).sum::<f32>() / n);
            let cov: f32 = u.iter().zip(v).map(|(p, q)| (p.x - mu) * (q.x - mv)).sum::<f32>() / n;
            cov / (1.0 / 12.0)
        };
        // Independent streams: |r| ~ 1/√4096 = 0.016; allow four standard deviations.
        assert!(corr(&a, &b).abs() < 0.0625, "{}", corr(&a, &b));
        assert!(corr(&a, &c).abs() < 0.0625, "{}", corr(&a, &c));
        assert_ne!(a[0], c[0]);
    }

    /// Sobol pair `dimension` of sample `index` drawn on its own, step by step: the
    /// reference for [`sobol_draws`], which computes all of them side by side.
    fn sobol_pair(pixel_seed: u32, index: u32, dimension: u32) -> Vec2 {
        let seed = mix32(pixel_seed ^ salt(dimension));
        let shuffled = laine_karras(index.reverse_bits(), seed).reverse_bits();
        let x = laine_karras(shuffled, seed ^ 0x68bc_21eb).reverse_bits();
        let y = laine_karras(sobol_y_reversed(shuffled), seed ^ 0x02e5_be93).reverse_bits();
        Vec2::new(unit_float(x), unit_float(y))
    }

    #[test]
    fn the_batched_sobol_draws_are_the_pairs_drawn_one_by_one() {
        for (px, index) in [(0, 0), (3, 1), (17, 255), (4096, 65_537), (u32::MAX, u32::MAX)] {
            let pixel_seed = hash32(&[px, 9, 5]);
            let s = PathSampler::new(SamplerKind::Sobol, px, 9, index, 5);
            for d in 0..SOBOL_DIMENSIONS {
                let want = sobol_pair(pixel_seed, index, d);
                assert_eq!(s.sobol[d as usize], want, "pixel {px} sample {index} dimension {d}");
            }
            let (mut pairs, mut singles) = (s, s);
            for d in 0..SOBOL_DIMENSIONS {
                let want = sobol_pair(pixel_seed, index, d);
                assert_eq!(pairs.next_2d(), want, "next_2d at dimension {d}");
                assert_eq!(singles.next_1d(), want.x, "next_1d at dimension {d}");
            }
        }
    }

    #[test]
    fn independent_numbers_are_uniform_and_deterministic() {
        let p = points(SamplerKind::Independent, 1, 20_000, 2);
        let mean = p.iter().map(|q| q.x + q.y).sum::<f32>() / (2.0 * p.len() as f32);
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
        assert!(p.iter().all(|q| q.cmpge(Vec2::ZERO).all() && q.cmplt(Vec2::ONE).all()));
        assert_eq!(p, points(SamplerKind::Independent, 1, 20_000, 2));
    }
}

//! Deterministic random streams.
//!
//! Every stream is derived from (pixel, sample index, seed) by hashing, never from a
//! shared generator, so a pixel's samples do not depend on which thread renders it or
//! in what order: the image is a pure function of the scene and the seed.

/// Mixes any number of words into one well-distributed 32-bit value: each word is
/// folded into a 64-bit state by the SplitMix64 finalizer (Steele et al. 2014), whose
/// every output bit depends on every input bit.
pub fn hash(words: &[u32]) -> u32 {
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    for &w in words {
        state = splitmix64(state ^ (w as u64).wrapping_add(0x9e37_79b9_7f4a_7c15));
    }
    (state >> 32) as u32
}

fn splitmix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn permute(state: u64) -> u32 {
    let xorshifted = (((state >> 18) ^ state) >> 27) as u32;
    let rot = (state >> 59) as u32;
    xorshifted.rotate_right(rot)
}

/// A small PCG32 generator for the few extra numbers one sample needs (light samples,
/// lens positions); seed it from [`hash`] of the sample's identity.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    const MULTIPLIER: u64 = 6_364_136_223_846_793_005;
    const INCREMENT: u64 = 1_442_695_040_888_963_407;

    pub fn new(seed: u32) -> Self {
        let mut rng = Self { state: 0 };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed as u64);
        rng.next_u32();
        rng
    }

    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(Self::MULTIPLIER).wrapping_add(Self::INCREMENT);
        permute(old)
    }

    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_numbers_have_the_right_mean_and_range() {
        let mut rng = Rng::new(7);
        let n = 100_000;
        let values: Vec<f32> = (0..n).map(|_| rng.next_f32()).collect();
        assert!(values.iter().all(|&v| (0.0..1.0).contains(&v)));
        let mean = values.iter().sum::<f32>() / n as f32;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
    }

    #[test]
    fn hashes_of_neighbouring_inputs_differ() {
        let a = hash(&[1, 2, 3]);
        assert_ne!(a, hash(&[1, 2, 4]));
        assert_ne!(a, hash(&[2, 2, 3]));
        assert_eq!(a, hash(&[1, 2, 3]));
    }
}

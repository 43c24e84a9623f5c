//! Deterministic random streams.
//!
//! Every stream is derived from (pixel, sample index, seed) by hashing, never from a
//! shared generator, so a pixel's samples do not depend on which thread renders it or
//! in what order: the image is a pure function of the scene and the seed. Everything
//! is 32-bit integer arithmetic, so a GPU shader draws exactly the same numbers.

use super::sequence::{hash32, mix32, unit_float};

/// Mixes any number of words into one well-distributed 32-bit value
/// ([`hash32`]: each word folded in by two rounds of [`mix32`]).
#[inline]
pub fn hash(words: &[u32]) -> u32 {
    hash32(words)
}

/// A small 32-bit PCG generator (O'Neill 2014, "PCG-RXS-M-XS-32": a 32-bit LCG
/// whose state is output through a random xorshift, a multiply and a fixed xorshift)
/// for the few extra numbers one sample needs (light samples, lens positions); seed it
/// from [`hash`] of the sample's identity.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u32,
}

impl Rng {
    const MULTIPLIER: u32 = 747_796_405;
    const INCREMENT: u32 = 2_891_336_453;

    pub fn new(seed: u32) -> Self {
        Self { state: mix32(seed) }
    }

    pub fn next_u32(&mut self) -> u32 {
        self.state = self.state.wrapping_mul(Self::MULTIPLIER).wrapping_add(Self::INCREMENT);
        let s = self.state;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        (word >> 22) ^ word
    }

    /// Uniform in [0, 1): the top 24 bits, every value exactly representable.
    pub fn next_f32(&mut self) -> f32 {
        unit_float(self.next_u32())
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
    fn the_generator_visits_every_state_once_per_period() {
        // A full-period LCG over 2^32 states: its outputs are a permutation of the
        // states, so 2^16 consecutive draws repeat no more than chance allows.
        let mut rng = Rng::new(1);
        let mut seen = std::collections::HashSet::new();
        let repeats = (0..1 << 16).filter(|_| !seen.insert(rng.next_u32())).count();
        // Birthday bound for 2^16 draws from 2^32: about 0.5 expected.
        assert!(repeats <= 4, "{repeats}");
    }

    #[test]
    fn neighbouring_seeds_give_unrelated_streams() {
        let first: Vec<u32> = (0..64).map(|s| Rng::new(s).next_u32()).collect();
        let distinct = first.iter().collect::<std::collections::HashSet<_>>().len();
        assert_eq!(distinct, 64);
        // The low bits of consecutive seeds' first draws are balanced.
        let odd = first.iter().filter(|&&x| x & 1 == 1).count();
        assert!((20..=44).contains(&odd), "{odd}");
    }

    #[test]
    fn hashes_of_neighbouring_inputs_differ() {
        let a = hash(&[1, 2, 3]);
        assert_ne!(a, hash(&[1, 2, 4]));
        assert_ne!(a, hash(&[2, 2, 3]));
        assert_eq!(a, hash(&[1, 2, 3]));
    }
}

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
/// from [`hash`] of the sample's identity, or let [`Rng::keyed`] do so when needed.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u32,
    /// For a generator made by [`Rng::keyed`] that has drawn nothing yet: the words
    /// its seed is the hash of, and the steps skipped meanwhile.
    deferred: Option<([u32; 4], u32)>,
}

impl Rng {
    const MULTIPLIER: u32 = 747_796_405;
    const INCREMENT: u32 = 2_891_336_453;

    pub fn new(seed: u32) -> Self {
        Self { state: mix32(seed), deferred: None }
    }

    /// `Rng::new(hash(&key))`, the hash taken at the first draw. A Whitted sample seen
    /// through a pinhole under point lights draws nothing, and hashing its identity was
    /// most of its camera sample's cost.
    #[inline]
    pub fn keyed(key: [u32; 4]) -> Self {
        Self { state: 0, deferred: Some((key, 0)) }
    }

    /// Passes over `n` numbers without computing them: where a number is not needed
    /// (the jitter of a point light), the ones after it stay those drawn in its place.
    #[inline]
    pub fn skip(&mut self, n: u32) {
        match &mut self.deferred {
            Some((_, skipped)) => *skipped += n,
            None => (0..n).for_each(|_| self.step()),
        }
    }

    pub fn next_u32(&mut self) -> u32 {
        if let Some((key, skipped)) = self.deferred.take() {
            self.state = mix32(hash32(&key));
            self.skip(skipped);
        }
        self.step();
        let s = self.state;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        (word >> 22) ^ word
    }

    /// Uniform in [0, 1): the top 24 bits, every value exactly representable.
    pub fn next_f32(&mut self) -> f32 {
        unit_float(self.next_u32())
    }

    #[inline]
    fn step(&mut self) {
        self.state = self.state.wrapping_mul(Self::MULTIPLIER).wrapping_add(Self::INCREMENT);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_keyed_generator_draws_what_a_seeded_one_does_and_skipping_passes_over_draws() {
        let key = [3, 5, 7, 11];
        let mut seeded = Rng::new(hash(&key));
        let mut keyed = Rng::keyed(key);
        assert_eq!(
            (0..5).map(|_| keyed.next_u32()).collect::<Vec<_>>(),
            (0..5).map(|_| seeded.next_u32()).collect::<Vec<_>>()
        );
        // Skipped before the first draw, and after it.
        let (mut drawn, mut skipping) = (Rng::new(hash(&key)), Rng::keyed(key));
        let drawn_values: Vec<u32> = (0..9).map(|_| drawn.next_u32()).collect();
        skipping.skip(2);
        assert_eq!(skipping.next_u32(), drawn_values[2]);
        skipping.skip(3);
        assert_eq!(skipping.next_u32(), drawn_values[6]);
        assert_eq!(skipping.next_u32(), drawn_values[7]);
    }

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

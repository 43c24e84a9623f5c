//! Samples whose radiance came back NaN or infinite: kept out of the film, counted by
//! the surface that produced them, so a render reports its faults once instead of
//! silently blackening or whitening pixels.

use std::collections::BTreeMap;

use crate::integrator::SurfaceId;

/// Non-finite samples of a tile or a whole render, by the surface whose shading first
/// made each one non-finite (`None`: no surface — the background or environment).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NonFiniteSamples {
    by_source: BTreeMap<Option<SurfaceId>, SourceTally>,
}

/// How often one source produced a non-finite sample, and one pixel where it did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SourceTally {
    pub count: u64,
    /// The first such pixel in render order (tile by tile): where to look.
    pub example_pixel: (u32, u32),
}

impl NonFiniteSamples {
    /// Counts one non-finite sample of pixel `pixel`, blamed on `source`.
    pub fn record(&mut self, source: Option<SurfaceId>, pixel: (u32, u32)) {
        self.add(source, SourceTally { count: 1, example_pixel: pixel });
    }

    /// Adds another tally (a later tile's) to this one.
    pub fn merge(&mut self, other: &NonFiniteSamples) {
        for (&source, &tally) in &other.by_source {
            self.add(source, tally);
        }
    }

    /// Adds `tally` to `source`'s (a saved tally read back); the example pixel already
    /// kept stays.
    pub fn add(&mut self, source: Option<SurfaceId>, tally: SourceTally) {
        self.by_source.entry(source).and_modify(|mine| mine.count += tally.count).or_insert(tally);
    }

    /// Non-finite samples in all.
    pub fn total(&self) -> u64 {
        self.by_source.values().map(|t| t.count).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.by_source.is_empty()
    }

    /// Each source with its tally, most frequent first (ties in source order).
    pub fn by_source(&self) -> Vec<(Option<SurfaceId>, SourceTally)> {
        let mut sources: Vec<_> = self.by_source.iter().map(|(&s, &t)| (s, t)).collect();
        sources.sort_by_key(|&(source, tally)| (std::cmp::Reverse(tally.count), source));
        sources
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_keeps_counts_and_the_first_example() {
        let sphere = Some(SurfaceId { instance: 2, material: 1 });
        let mut first = NonFiniteSamples::default();
        first.record(sphere, (3, 4));
        first.record(None, (0, 0));
        let mut second = NonFiniteSamples::default();
        second.record(sphere, (9, 9));
        second.record(sphere, (9, 10));
        first.merge(&second);
        assert_eq!(first.total(), 4);
        let sources = first.by_source();
        assert_eq!(sources[0], (sphere, SourceTally { count: 3, example_pixel: (3, 4) }));
        assert_eq!(sources[1], (None, SourceTally { count: 1, example_pixel: (0, 0) }));
    }
}

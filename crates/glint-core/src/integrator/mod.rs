//! Integrators: what colour a ray brings back.

pub mod path;
pub mod whitted;

use crate::sampling::Rng;

/// What one camera sample carries through its whole ray tree: its own random stream
/// (derived from pixel, sample index and seed) and its work counters.
#[derive(Clone, Debug)]
pub struct TraceContext {
    pub counters: Counters,
    pub rng: Rng,
}

/// Work counted while tracing, summed per tile (no shared atomics in the hot path).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Primary, reflected, refracted and shadow rays traced.
    pub rays: u64,
}

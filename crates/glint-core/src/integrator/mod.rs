//! Integrators: what colour a ray brings back.

pub mod whitted;

/// Work counted while tracing, summed per tile (no shared atomics in the hot path).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Primary, reflected, refracted and shadow rays traced.
    pub rays: u64,
}

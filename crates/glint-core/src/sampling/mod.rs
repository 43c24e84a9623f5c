//! Where samples go: pixel sample patterns, random streams and reconstruction filters.

mod distribution;
mod filter;
mod pattern;
mod rng;
mod sequence;

pub use distribution::{Distribution1D, Distribution2D};
pub use filter::{Filter, FilterKind};
pub use pattern::{PixelSampler, SamplePattern};
pub use rng::{Rng, hash};
pub use sequence::{PathSampler, PixelStream, hash32, mix32, unit_float};

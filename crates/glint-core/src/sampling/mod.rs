//! Where samples go: pixel sample patterns, random streams and reconstruction filters.

mod filter;
mod pattern;
mod rng;

pub use filter::{Filter, FilterKind};
pub use pattern::{PixelSampler, SamplePattern};
pub use rng::{Rng, hash};

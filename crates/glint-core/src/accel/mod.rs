//! Acceleration structures.

mod bvh;
mod bvh4;

pub use bvh::{Bvh, BvhNode};
pub use bvh4::{Bvh4, Bvh4Node, EMPTY};

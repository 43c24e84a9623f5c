//! Acceleration structures: a binned-SAH binary BVH, built first, and the 8-wide BVH
//! collapsed from it that rays traverse.

mod bvh;
mod huge_pages;
pub mod lanes;
mod packet;
mod wide;

pub use bvh::{Bvh, BvhNode};
pub use huge_pages::{on_huge_pages, with_capacity_on_huge_pages};
pub use packet::{PACKET, bits, one_octant};
pub use wide::{EMPTY, Order, WIDTH, WideBvh, WideNode};

//! Packets of up to eight coherent rays (camera rays of neighbouring pixels) traversing
//! the wide BVH together: each node is fetched, its hit children sorted and pushed once
//! for the whole packet, and only the rays that entered a child go on with it. Each ray
//! still tests the node's eight boxes in one SIMD slab test and reaches every leaf its
//! closest hit lies in, so it finds the closest hit its single-ray traversal finds; only
//! the order of the visits differs, which decides between surfaces hit at exactly the
//! same distance. What the packet saves is the per-node bookkeeping (Wald et al., "Interactive Rendering with Coherent
//! Ray Tracing", 2001, with the rays rather than the boxes in the SIMD lanes reversed,
//! as wide BVHs need).

use std::mem::MaybeUninit;

use super::lanes::{F32x8, Lanes};
use super::wide::{STACK, SlabRay, WIDTH, WideBvh, insert_farthest_first};
use crate::math::Ray;

/// Rays in one packet.
pub const PACKET: usize = 8;

/// One stack entry: a node or leaf, the rays that entered it, and the nearest of their
/// entry distances.
#[derive(Clone, Copy)]
struct Entry {
    index: u32,
    count: u32,
    rays: u32,
    t_enter: f32,
}

/// Iterates over the set bits of `mask`, lowest first.
#[inline(always)]
pub fn bits(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let bit = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            bit
        })
    })
}

/// Transposes an 8×8 bit matrix whose row `i` is byte `i`: bit `j` of byte `i` moves
/// to bit `i` of byte `j` (Warren, "Hacker's Delight", §7-3).
#[inline(always)]
fn transpose_8x8(mut x: u64) -> u64 {
    let t = (x ^ (x >> 7)) & 0x00AA_00AA_00AA_00AA;
    x ^= t ^ (t << 7);
    let t = (x ^ (x >> 14)) & 0x0000_CCCC_0000_CCCC;
    x ^= t ^ (t << 14);
    let t = (x ^ (x >> 28)) & 0x0000_0000_F0F0_F0F0;
    x ^ t ^ (t << 28)
}

impl WideBvh {
    /// Traverses with the rays of `rays` (at most [`PACKET`]) whose bit is set in
    /// `active`, children in nearest-first order of the packet's nearest entry.
    /// `visit(primitive, rays, t_max)` is called for each primitive of a leaf that the
    /// rays in the mask `rays` entered; it may shrink their `t_max` and returns the
    /// rays that are done (an any-hit query's blocked rays), which then leave the packet.
    #[inline(always)]
    pub fn traverse_packet<L: Lanes, P>(
        &self,
        lanes: L,
        leaves: &[P],
        rays: &[Ray],
        active: u32,
        t_max: &mut [f32; PACKET],
        mut visit: impl FnMut(u32, u32, &mut [f32; PACKET]) -> u32,
    ) {
        assert!(rays.len() <= PACKET, "a packet holds at most {PACKET} rays");
        let active = active & ((1u32 << rays.len()) - 1);
        if self.nodes.is_empty() || active == 0 {
            return;
        }
        let slabs: [SlabRay<L>; PACKET] = std::array::from_fn(|r| SlabRay::new(lanes, &rays[r.min(rays.len() - 1)]));
        let mut done = 0u32;
        // Left uninitialized, as in the single-ray traversal.
        let mut stack = [MaybeUninit::<Entry>::uninit(); STACK];
        let mut top = 0;
        let mut next = Some(Entry { index: 0, count: 0, rays: active, t_enter: 0.0 });
        loop {
            let entry = match next.take() {
                Some(entry) => entry,
                None if top > 0 => {
                    top -= 1;
                    // SAFETY: entries below `top` were all written by a push.
                    unsafe { stack[top].assume_init() }
                }
                None => return,
            };
            // Rays done, or whose closest hit so far is nearer than the node.
            let rays = bits(entry.rays & !done).fold(0, |m, r| m | u32::from(entry.t_enter <= t_max[r]) << r);
            if rays == 0 {
                continue;
            }
            if entry.count > 0 {
                for prim in entry.index..entry.index + entry.count {
                    done |= visit(prim, rays & !done, t_max);
                    if rays & !done == 0 {
                        break;
                    }
                }
                if done == active {
                    return;
                }
                continue;
            }
            let n = &self.nodes[entry.index as usize];
            // Row r of `entered` (byte r) is the mask of children ray r entered.
            let mut entered = 0u64;
            let mut child_near = lanes.splat(f32::INFINITY);
            for r in bits(rays) {
                let (near, mask) = slabs[r].test_or_infinity(n, t_max[r]);
                entered |= u64::from(mask) << (8 * r);
                child_near = child_near.min(near);
            }
            if entered == 0 {
                continue;
            }
            // Transposed, byte `lane` is the mask of rays that entered child `lane`.
            let child_rays = transpose_8x8(entered).to_le_bytes();
            let hit = child_rays.iter().enumerate().fold(0u32, |m, (lane, &r)| m | u32::from(r != 0) << lane);
            let child_near = child_near.to_array();
            // Farthest first into `sorted`; all but the nearest are pushed.
            let mut sorted = [Entry { index: 0, count: 0, rays: 0, t_enter: 0.0 }; WIDTH];
            let mut k = 0;
            for lane in bits(hit) {
                let (index, count) = (n.child[lane], n.count[lane]);
                self.prefetch_child(leaves, index, count);
                let e = Entry { index, count, rays: u32::from(child_rays[lane]), t_enter: child_near[lane] };
                insert_farthest_first(&mut sorted, &mut k, e, |e| e.t_enter);
            }
            for &e in &sorted[..k - 1] {
                stack[top].write(e);
                top += 1;
            }
            next = Some(sorted[k - 1]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transpose_moves_each_bit_across_the_diagonal() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..100 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let t = transpose_8x8(state);
            for i in 0..8 {
                for j in 0..8 {
                    assert_eq!(state >> (8 * i + j) & 1, t >> (8 * j + i) & 1);
                }
            }
        }
    }
}

//! Packets of up to eight coherent rays (camera rays of neighbouring pixels) traversing
//! the wide BVH together: each node is fetched, its hit children sorted and pushed once
//! for the whole packet, and only the rays that entered a child go on with it. Each ray
//! still makes its own slab test of every box it may enter (rays of one octant side by
//! side, box by box, after the packet's frustum has ruled boxes out; others the node's
//! eight boxes at once) and reaches every leaf its closest hit lies in, so it finds the
//! closest hit its single-ray traversal finds; only the order of the visits differs,
//! which decides between surfaces hit at exactly the same distance. What the packet saves is the per-node bookkeeping (Wald et al., "Interactive Rendering with Coherent
//! Ray Tracing", 2001, with the rays rather than the boxes in the SIMD lanes reversed,
//! as wide BVHs need).

use std::mem::MaybeUninit;

use super::lanes::{F32x8, Lanes};
use super::wide::{Order, STACK, SlabRay, WIDTH, WideBvh, WideNode, insert_farthest_first};
use crate::math::{ROBUST_FAR, Ray};

/// Rays in one packet.
pub const PACKET: usize = 8;

/// In [`WideBvh::traverse_hybrid`], the most rays entering an inner node that go on
/// through it alone rather than as a packet. Chosen by instruction counts on the bench
/// mesh's random rays (2 to 4 alike; 0, no switching, and 8, always alone, both worse)
/// and left camera-ray packets as they were.
pub const SWITCH: u32 = 3;

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

/// Whether the rays of mask `active` all travel into one octant (the same signs of
/// their direction's components). Rays of different octants share few nodes below the
/// root; Embree's hybrid walk, too, keeps only rays of one octant in a packet.
#[inline(always)]
pub fn one_octant(rays: &[Ray], active: u32) -> bool {
    let (all, any) = bits(active).fold((7, 0), |(all, any), r| {
        let signs = rays[r].dir.is_negative_bitmask();
        (all & signs, any | signs)
    });
    all == any
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
        visit: impl FnMut(u32, u32, &mut [f32; PACKET]) -> u32,
    ) {
        let nearest = Order::NearestFirst;
        self.traverse_packet_or_alone::<L, P, false>(lanes, nearest, leaves, rays, active, t_max, visit, |_, _, _| {
            false
        });
    }

    /// [`WideBvh::traverse_packet`], children in `order` (any-hit rays keep their
    /// `t_max` until they are done, so they need neither sorting nor distances), and
    /// where no more than [`SWITCH`] rays enter an inner node, each of them goes on alone
    /// through its subtree: `alone(ray, node, t_max)` traces ray `ray` from inner node
    /// `node` (with [`WideBvh::traverse_from`]), may shrink its `t_max` and returns
    /// whether it is done. This is Embree's hybrid traversal: incoherent rays part ways
    /// within a few levels, and a packet of one or two rays is a single ray with the
    /// packet's bookkeeping added. Rays into different octants go on alone from the
    /// root. `alone` is a closure of its own, rather than the single-ray walk calling
    /// `visit`, so that each closure has one call site and is inlined into the caller's
    /// AVX2 code.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn traverse_hybrid<L: Lanes, P>(
        &self,
        lanes: L,
        order: Order,
        leaves: &[P],
        rays: &[Ray],
        active: u32,
        t_max: &mut [f32; PACKET],
        visit: impl FnMut(u32, u32, &mut [f32; PACKET]) -> u32,
        alone: impl FnMut(usize, u32, &mut f32) -> bool,
    ) {
        self.traverse_packet_or_alone::<L, P, true>(lanes, order, leaves, rays, active, t_max, visit, alone);
    }

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn traverse_packet_or_alone<L: Lanes, P, const HYBRID: bool>(
        &self,
        lanes: L,
        order: Order,
        leaves: &[P],
        rays: &[Ray],
        active: u32,
        t_max: &mut [f32; PACKET],
        mut visit: impl FnMut(u32, u32, &mut [f32; PACKET]) -> u32,
        mut alone: impl FnMut(usize, u32, &mut f32) -> bool,
    ) {
        assert!(rays.len() <= PACKET, "a packet holds at most {PACKET} rays");
        let active = active & ((1u32 << rays.len()) - 1);
        if self.nodes.is_empty() || active == 0 {
            return;
        }
        // Rays into different octants part ways at once: they go on alone from the root
        // (the switch below, taken at once: one call site of `alone`, so it is inlined).
        let octant = one_octant(rays, active);
        let mut scattered = HYBRID && !octant;
        // Rays of one octant are tested side by side, child by child, after their
        // frustum has ruled out the children none of them can enter; others ray by ray.
        let frustum = octant.then(|| Frustum::new(lanes, rays, active));
        // The frustum ends where its farthest ray does: shadow rays end at their light.
        // Any-hit rays keep their `t_max` until they are done, so that is known now.
        let fixed_far = (order == Order::Any).then(|| farthest(active, t_max));
        // Scattered rays all go on alone from the root, so they need no packet slabs.
        let slabs: Option<[SlabRay<L>; PACKET]> = (frustum.is_none() && !scattered)
            .then(|| std::array::from_fn(|r| SlabRay::new(lanes, &rays[r.min(rays.len() - 1)])));
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
            // Rays done, or whose closest hit so far is nearer than the node (any-hit
            // rays keep their `t_max` until they are done).
            let rays = match order {
                Order::Any => entry.rays & !done,
                Order::NearestFirst => {
                    bits(entry.rays & !done).fold(0, |m, r| m | u32::from(entry.t_enter <= t_max[r]) << r)
                }
            };
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
            if HYBRID && (scattered || rays.count_ones() <= SWITCH) {
                scattered = false;
                for r in bits(rays) {
                    done |= u32::from(alone(r, entry.index, &mut t_max[r])) << r;
                }
                if done == active {
                    return;
                }
                continue;
            }
            let n = &self.nodes[entry.index as usize];
            let (child_rays, child_near) = match (&frustum, &slabs) {
                (Some(frustum), _) => {
                    let t_far = fixed_far.unwrap_or_else(|| farthest(rays, t_max));
                    frustum.children_entered(n, rays, t_max, t_far)
                }
                (None, Some(slabs)) => children_entered_ray_by_ray(lanes, slabs, n, order, rays, t_max),
                (None, None) => unreachable!("a packet without a frustum tests ray by ray"),
            };
            let hit = nonzero_bytes(child_rays);
            if hit == 0 {
                continue;
            }
            if order == Order::Any {
                // Children as they come: the first is next, the rest are pushed.
                let mut hit = hit;
                let entry = |lane: usize| {
                    let (index, count) = (n.child[lane], n.count[lane]);
                    self.prefetch_child(leaves, index, count);
                    Entry { index, count, rays: u32::from(child_rays[lane]), t_enter: 0.0 }
                };
                next = Some(entry(hit.trailing_zeros() as usize));
                hit &= hit - 1;
                for lane in bits(hit) {
                    stack[top].write(entry(lane));
                    top += 1;
                }
                continue;
            }
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

/// The lowest and highest of `values`, by halving: each step compares the two halves
/// lane by lane, which compiles to vector `min`/`max` (a fold, one value after another,
/// was a chain of 16 dependent compares, the frustum's costliest set-up). Plain compares,
/// not `f32::min`: no lane is NaN (a ray's origin is finite, its reciprocals are numbers
/// or infinities), so the NaN handling would be wasted.
#[inline(always)]
fn range(values: &[f32; PACKET]) -> (f32, f32) {
    let min = |a: f32, b: f32| if b < a { b } else { a };
    let max = |a: f32, b: f32| if b > a { b } else { a };
    let (lo, hi): ([f32; 4], [f32; 4]) = (
        std::array::from_fn(|i| min(values[i], values[i + 4])),
        std::array::from_fn(|i| max(values[i], values[i + 4])),
    );
    let (lo, hi) = ([min(lo[0], lo[2]), min(lo[1], lo[3])], [max(hi[0], hi[2]), max(hi[1], hi[3])]);
    (min(lo[0], lo[1]), max(hi[0], hi[1]))
}

/// Bit `i` set where byte `i` of `bytes` is not zero: the children some ray entered, by
/// bit arithmetic on one word (ORing in each byte's test took 30 instructions a node).
#[inline(always)]
fn nonzero_bytes(bytes: [u8; 8]) -> u32 {
    const LOW7: u64 = 0x7f7f_7f7f_7f7f_7f7f;
    let x = u64::from_le_bytes(bytes);
    // A byte's top bit is set where the byte is not zero (the carry from its low seven
    // bits, or its own top bit); no carry crosses into the next byte.
    let top = (((x & LOW7) + LOW7) | x) & !LOW7;
    // The eight top bits gathered into the highest byte, bit `i` from byte `i`.
    ((top >> 7).wrapping_mul(0x0102_0408_1020_4080) >> 56) as u32
}

/// The largest `t_max` of the rays of mask `rays`.
#[inline(always)]
fn farthest(rays: u32, t_max: &[f32; PACKET]) -> f32 {
    bits(rays).fold(0.0f32, |far, r| if t_max[r] > far { t_max[r] } else { far })
}

/// For each of `n`'s children, the mask of the rays of `rays` that enter it (byte `lane`)
/// and, for a nearest-first walk, the nearest of their entry distances (+∞ for a child
/// none enters): each ray tests the node's eight boxes at once, as it does alone. For
/// packets whose rays head into different octants.
#[inline(always)]
fn children_entered_ray_by_ray<L: Lanes>(
    lanes: L,
    slabs: &[SlabRay<L>; PACKET],
    n: &WideNode,
    order: Order,
    rays: u32,
    t_max: &[f32; PACKET],
) -> ([u8; WIDTH], [f32; WIDTH]) {
    // Row r of `entered` (byte r) is the mask of children ray r entered.
    let mut entered = 0u64;
    let mut child_near = lanes.splat(f32::INFINITY);
    for r in bits(rays) {
        if order == Order::Any {
            entered |= u64::from(slabs[r].test(n, t_max[r]).1) << (8 * r);
            continue;
        }
        let (near, mask) = slabs[r].test_or_infinity(n, t_max[r]);
        entered |= u64::from(mask) << (8 * r);
        child_near = child_near.min(near);
    }
    // Transposed, byte `lane` is the mask of rays that entered child `lane`.
    (transpose_8x8(entered).to_le_bytes(), child_near.to_array())
}

/// A packet of rays that all travel into one octant, ray `r` in lane `r`, and the
/// bounds of their origins and reciprocal directions. A node's eight boxes are first
/// tested against the whole packet at once by interval arithmetic: a box whose entry
/// distance, at its lowest over the rays, exceeds its exit distance at its highest, is
/// entered by none of them. Only the children left are tested, each against all the
/// rays at once: a coherent packet enters two or three children of a node, so that
/// takes three or four box tests where testing ray by ray takes eight. The children's
/// order, and the distance past which a ray with a nearer hit leaves a child, come from
/// the frustum's lowest entry distance, never above any of its rays' own.
///
/// The bounds hold for the rounded arithmetic too: subtraction and multiplication round
/// monotonically, so the bound computed from the extreme origin and reciprocal is never
/// above (below) any ray's own rounded distance, and a ray's test here is its single
/// test, operation for operation, so each ray enters exactly the children it enters
/// alone.
struct Frustum<L: Lanes> {
    lanes: L,
    origin: [L::V; 3],
    inv: [L::V; 3],
    inv_far: [L::V; 3],
    near_plane: [usize; 3],
    far_plane: [usize; 3],
    /// Per axis, the origins' lowest and highest coordinates, and the lowest and highest
    /// of `inv` and of `inv_far`.
    origin_range: [(f32, f32); 3],
    inv_range: [(f32, f32); 3],
    inv_far_range: [(f32, f32); 3],
    /// Per axis, whether the rays travel up it.
    ascending: [bool; 3],
}

impl<L: Lanes> Frustum<L> {
    /// The frustum of the rays of `rays` in `active` (which must travel into one octant).
    #[inline(always)]
    fn new(lanes: L, rays: &[Ray], active: u32) -> Self {
        // Per axis and lane: origin, the very reciprocal `SlabRay::new` takes, and it
        // widened for the far planes.
        // Lanes of rays outside `active` repeat the first active ray, so that the ranges
        // can be taken over all eight lanes.
        let first = bits(active).next().unwrap_or(0);
        let (mut origin, mut inv, mut inv_far) = ([[0.0; PACKET]; 3], [[0.0; PACKET]; 3], [[0.0; PACKET]; 3]);
        for r in 0..PACKET {
            let ray = &rays[if active >> r & 1 == 1 { r } else { first }];
            let recip = ray.dir.recip();
            for a in 0..3 {
                (origin[a][r], inv[a][r], inv_far[a][r]) = (ray.origin[a], recip[a], recip[a] * ROBUST_FAR);
            }
        }
        let (origin_range, inv_range, inv_far_range) =
            (origin.map(|o| range(&o)), inv.map(|i| range(&i)), inv_far.map(|i| range(&i)));
        // The planes `SlabRay::new` picks: the upper one first where 1/d < 0.
        let descending: [bool; 3] = std::array::from_fn(|a| inv[a][first] < 0.0);
        let near_plane = std::array::from_fn(|a| 2 * a + usize::from(descending[a]));
        Frustum {
            lanes,
            origin: origin.map(|o| lanes.load(&o)),
            inv: inv.map(|i| lanes.load(&i)),
            inv_far: inv_far.map(|i| lanes.load(&i)),
            near_plane,
            far_plane: near_plane.map(|p| p ^ 1),
            origin_range,
            inv_range,
            inv_far_range,
            ascending: descending.map(|d| !d),
        }
    }

    /// The children of `n` that some ray of the packet may enter before `t_far` (the
    /// packet's farthest `t_max`).
    #[inline(always)]
    fn candidates(&self, n: &WideNode, t_far: f32) -> (u32, L::V) {
        let (lanes, zero) = (self.lanes, self.lanes.splat(0.0));
        let bound = |plane, axis, range, lowest| self.bound(n, plane, axis, range, lowest);
        let [nx, ny, nz] = self.near_plane;
        let [fx, fy, fz] = self.far_plane;
        let (inv, inv_far) = (&self.inv_range, &self.inv_far_range);
        let near = bound(nx, 0, inv[0], true).max(bound(ny, 1, inv[1], true).max(bound(nz, 2, inv[2], true).max(zero)));
        let far = bound(fx, 0, inv_far[0], false)
            .min(bound(fy, 1, inv_far[1], false).min(bound(fz, 2, inv_far[2], false).min(lanes.splat(t_far))));
        (near.le_mask(far), near)
    }

    /// The lowest (`lowest`) or highest distance over the rays to plane `plane` of each
    /// of `n`'s boxes, on axis `axis`, with reciprocals in `(lo, hi)`: from the origin
    /// that makes the offset smallest (largest), times the reciprocal that makes the
    /// product so. (A method, not a closure: a closure that is not inlined loses the
    /// caller's AVX2, and its intrinsics become calls.)
    #[inline(always)]
    fn bound(&self, n: &WideNode, plane: usize, axis: usize, (lo, hi): (f32, f32), lowest: bool) -> L::V {
        let lanes = self.lanes;
        let (o_lo, o_hi) = self.origin_range[axis];
        let farthest_origin = if lowest == self.ascending[axis] { o_hi } else { o_lo };
        let offset = lanes.load(&n.bounds[plane]).sub(lanes.splat(farthest_origin));
        let (if_ahead, if_behind) = if lowest { (lo, hi) } else { (hi, lo) };
        offset.mul(lanes.splat(0.0).select_le(offset, lanes.splat(if_ahead), lanes.splat(if_behind)))
    }

    /// The distances of every ray to plane `plane` of `n`'s box `lane`, on axis `axis`,
    /// with reciprocals `inv`: `SlabRay`'s, with the rays in the lanes.
    #[inline(always)]
    fn slab(&self, n: &WideNode, lane: usize, plane: usize, axis: usize, inv: &[L::V; 3]) -> L::V {
        self.lanes.splat(n.bounds[plane][lane]).sub(self.origin[axis]).mul(inv[axis])
    }

    /// [`children_entered_ray_by_ray`], child by child over the candidates, with the
    /// frustum's lowest entry distances (a bound below the rays' nearest).
    #[inline(always)]
    fn children_entered(
        &self,
        n: &WideNode,
        rays: u32,
        t_max: &[f32; PACKET],
        t_far: f32,
    ) -> ([u8; WIDTH], [f32; WIDTH]) {
        let lanes = self.lanes;
        let t_max_lanes = lanes.load(t_max);
        let (candidates, lowest_near) = self.candidates(n, t_far);
        let mut child_rays = [0u8; WIDTH];
        for lane in bits(candidates) {
            // `SlabRay::interval`, with the rays in the lanes and the one box splatted.
            let slab = |plane, axis, inv| self.slab(n, lane, plane, axis, inv);
            let [nx, ny, nz] = self.near_plane;
            let [fx, fy, fz] = self.far_plane;
            let (inv, inv_far) = (&self.inv, &self.inv_far);
            let zero = lanes.splat(0.0);
            let near = slab(nx, 0, inv).max(slab(ny, 1, inv).max(slab(nz, 2, inv).max(zero)));
            let far = slab(fx, 0, inv_far).min(slab(fy, 1, inv_far).min(slab(fz, 2, inv_far).min(t_max_lanes)));
            child_rays[lane] = (near.le_mask(far) & rays) as u8;
        }
        // The children's order, and the distance past which a ray that has found a hit
        // leaves them, by the frustum's lowest entry distance: never above the rays' own.
        (child_rays, lowest_near.to_array())
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::accel::lanes::Portable;
    use crate::accel::{Bvh, Order};
    use crate::math::Aabb;

    /// For each ray, the sorted primitives a traversal visited it with.
    type Visited = Vec<Vec<u32>>;

    /// Per ray, the packet walk, the hybrid walk (whose rays go on alone where at most
    /// [`SWITCH`] enter a node) and the single-ray walk visit the very same primitives,
    /// for packets that fan out a little (camera rays) and packets of unrelated rays,
    /// of every size and with rays masked out.
    #[test]
    fn hybrid_and_packet_walks_visit_what_single_rays_visit() {
        let mut rng = crate::sampling::Rng::new(11);
        let mut next = move || rng.next_f32();
        let boxes: Vec<Aabb> = (0..4000)
            .map(|_| {
                let c = Vec3::new(next(), next(), next()) * 20.0 - 10.0;
                let h = Vec3::new(next(), next(), next()) * 0.8;
                Aabb::new(c - h, c + h)
            })
            .collect();
        let wide = WideBvh::from_binary(&Bvh::build(&boxes).0);
        let mut switched = 0;
        for i in 0..400 {
            let coherent = i % 2 == 0;
            let base = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
            let origin = Vec3::new(next(), next(), next()) * 30.0 - 15.0;
            let rays: Vec<Ray> = (0..1 + i % PACKET)
                .map(|_| {
                    let jitter = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
                    if coherent {
                        Ray::new(origin, base + 0.05 * jitter)
                    } else {
                        Ray::new(Vec3::new(next(), next(), next()) * 30.0 - 15.0, jitter)
                    }
                })
                .collect();
            let active = if i % 5 == 0 { 0b1011_0110 } else { u32::MAX } & ((1 << rays.len()) - 1);
            let mut single: Visited = vec![Vec::new(); rays.len()];
            for r in bits(active) {
                wide.traverse(&rays[r], &mut { f32::INFINITY }, |prim, _| {
                    single[r].push(prim);
                    false
                });
            }
            let mut packet: Visited = vec![Vec::new(); rays.len()];
            wide.traverse_packet::<_, ()>(Portable, &[], &rays, active, &mut [f32::INFINITY; PACKET], |prim, m, _| {
                bits(m).for_each(|r| packet[r].push(prim));
                0
            });
            for visited in [&mut single, &mut packet] {
                visited.iter_mut().for_each(|v| v.sort());
            }
            assert_eq!(single, packet, "packet {i}");
            for order in [Order::NearestFirst, Order::Any] {
                let hybrid = std::cell::RefCell::new(vec![Vec::new(); rays.len()]);
                wide.traverse_hybrid::<_, ()>(
                    Portable,
                    order,
                    &[],
                    &rays,
                    active,
                    &mut [f32::INFINITY; PACKET],
                    |prim, m, _| {
                        bits(m).for_each(|r| hybrid.borrow_mut()[r].push(prim));
                        0
                    },
                    |r, node, t_max| {
                        switched += 1;
                        wide.traverse_from::<_, ()>(Portable, order, &[], &rays[r], node, t_max, |prim, _| {
                            hybrid.borrow_mut()[r].push(prim);
                            false
                        });
                        false
                    },
                );
                let mut hybrid = hybrid.into_inner();
                hybrid.iter_mut().for_each(|v| v.sort());
                assert_eq!(single, hybrid, "packet {i}, {order:?}");
            }
        }
        assert!(switched > 100, "rays went on alone {switched} times");
    }

    /// The word trick marks exactly the non-zero bytes, over every pattern of zero and
    /// non-zero bytes and byte values that carry (0x80, 0x7f, 0xff, 0x01).
    #[test]
    fn nonzero_bytes_marks_each_non_zero_byte() {
        for pattern in 0u32..256 {
            for value in [0x01u8, 0x7f, 0x80, 0xff, 0x55] {
                let bytes: [u8; 8] = std::array::from_fn(|i| if pattern >> i & 1 == 1 { value } else { 0 });
                assert_eq!(nonzero_bytes(bytes), pattern, "{bytes:?}");
            }
        }
    }

    /// The halving reduction gives the lowest and highest lane, wherever they lie, with
    /// infinities among them.
    #[test]
    fn range_finds_the_extremes_in_any_lane() {
        for lo in 0..PACKET {
            for hi in (0..PACKET).filter(|&h| h != lo) {
                let mut values = [0.5f32; PACKET];
                values[lo] = f32::NEG_INFINITY;
                values[hi] = 3.0;
                assert_eq!(range(&values), (f32::NEG_INFINITY, 3.0));
                values[lo] = -2.0;
                values[hi] = f32::INFINITY;
                assert_eq!(range(&values), (-2.0, f32::INFINITY));
            }
        }
    }

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

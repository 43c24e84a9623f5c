//! An 8-wide BVH made by collapsing the binary one (each node takes up to eight of its
//! descendants, opening the largest first), so one SIMD slab test checks eight boxes —
//! the layout of Embree's BVH8 (Wald et al., "Embree: A Kernel Framework for Efficient
//! CPU Ray Tracing", 2014) and, as eight-child nodes, of GPU wide BVHs (Ylitie et al.,
//! "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", 2017).
//! Nodes are plain `Pod` records, structure of arrays, uploadable as they are.

use std::mem::MaybeUninit;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::bvh::Bvh;
use super::lanes::{F32x8, Lanes, Portable, prefetch};
use crate::math::{Aabb, ROBUST_FAR, Ray};

/// Children per node.
pub const WIDTH: usize = 8;

/// `count` of an unused child slot.
pub const EMPTY: u32 = u32::MAX;

/// Eight child boxes and what each child is; 256 bytes, four cache lines and aligned
/// to them, so a node never straddles a fifth.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct WideNode {
    /// `bounds[2·axis]` holds the children's lower bounds on `axis` and
    /// `bounds[2·axis + 1]` their upper bounds, lane = child. An unused lane holds the
    /// empty box (+∞ … −∞), which the slab test never enters, so traversal needs no
    /// check for it.
    pub bounds: [[f32; WIDTH]; 6],
    /// An inner child's node index, or a leaf's first primitive.
    pub child: [u32; WIDTH],
    /// 0 for an inner child, the primitive count of a leaf, or [`EMPTY`].
    pub count: [u32; WIDTH],
}

impl WideNode {
    const UNUSED: WideNode = WideNode {
        bounds: [
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [0; WIDTH],
        count: [EMPTY; WIDTH],
    };

    fn set_box(&mut self, lane: usize, b: Aabb) {
        for axis in 0..3 {
            self.bounds[2 * axis][lane] = b.min[axis];
            self.bounds[2 * axis + 1][lane] = b.max[axis];
        }
    }
}

/// Which children a traversal visits first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// Nearest entry first: a closest-hit query shrinks `t_max` soonest this way.
    NearestFirst,
    /// In storage order, unsorted: an any-hit query stops at its first hit, wherever it
    /// is, so sorting would only cost time (Embree's occlusion traversal does the same).
    Any,
}

/// The 8-wide hierarchy; primitives keep the order of the binary BVH it came from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideBvh {
    pub nodes: Vec<WideNode>,
    bounds: Option<(Vec3, Vec3)>,
}

/// Most entries the traversal stack can hold: each level pops one entry and pushes at
/// most seven, and the binary BVH (so this one too) is at most 60 levels deep.
pub(super) const STACK: usize = (WIDTH - 1) * 61 + 1;

impl WideBvh {
    /// Collapses `bvh` (whose primitive order stays valid).
    pub fn from_binary(bvh: &Bvh) -> WideBvh {
        let bounds = bvh.nodes.first().map(|r| (r.min, r.max));
        let Some(root) = bvh.nodes.first() else { return WideBvh { nodes: vec![], bounds } };
        let nodes = if bvh.leaf_preferred[0] {
            let mut node = WideNode::UNUSED;
            node.set_box(0, Aabb::new(root.min, root.max));
            (node.child[0], node.count[0]) = bvh.primitives(0);
            vec![node]
        } else {
            collapse_in_parallel(bvh, 0)
        };
        WideBvh { nodes, bounds }
    }

    /// Bounds of everything in the hierarchy (empty when it holds nothing), kept apart
    /// from the nodes because the root node stores only its children's boxes.
    pub fn bounds(&self) -> Aabb {
        self.bounds.map_or(Aabb::EMPTY, |(min, max)| Aabb::new(min, max))
    }

    /// `visit(primitive, t_max)` for every primitive whose leaf box the ray enters
    /// before `*t_max`, nearest boxes first; `visit` may shrink `t_max` (closest hit) and
    /// returns `true` to stop at once (any hit). Portable lanes; hot paths that can use
    /// AVX2 call [`WideBvh::traverse_with`] from an AVX2 function.
    pub fn traverse(&self, ray: &Ray, t_max: &mut f32, visit: impl FnMut(u32, &mut f32) -> bool) {
        self.traverse_with::<_, ()>(Portable, Order::NearestFirst, &[], ray, t_max, visit);
    }

    /// [`WideBvh::traverse`] on the lanes `L`, children visited in `order`; a leaf's
    /// first primitive in `leaves` (if given) is prefetched when its box is hit.
    #[inline(always)]
    pub fn traverse_with<L: Lanes, P>(
        &self,
        lanes: L,
        order: Order,
        leaves: &[P],
        ray: &Ray,
        t_max: &mut f32,
        visit: impl FnMut(u32, &mut f32) -> bool,
    ) {
        self.traverse_from(lanes, order, leaves, ray, 0, t_max, visit);
    }

    /// [`WideBvh::traverse_with`] over the subtree of inner node `root` only: a packet
    /// whose rays have parted ways goes on with each of them alone from where it split
    /// ([`WideBvh::traverse_hybrid`]).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn traverse_from<L: Lanes, P>(
        &self,
        lanes: L,
        order: Order,
        leaves: &[P],
        ray: &Ray,
        root: u32,
        t_max: &mut f32,
        mut visit: impl FnMut(u32, &mut f32) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let slab = SlabRay::new(lanes, ray);
        // (index, count, entry distance); count 0 = inner node. Left uninitialized: zeroing
        // 5 KiB per ray cost more than a slab test.
        let mut stack = [MaybeUninit::<(u32, u32, f32)>::uninit(); STACK];
        let mut top = 0;
        let mut next = Some((root, 0u32, 0.0f32));
        loop {
            // A child of the node just tested is visited straight away rather than pushed
            // and at once popped again; otherwise the top of the stack.
            let (index, count) = match next.take() {
                // Entered before `t_max`: the node test just said so.
                Some((index, count, _)) => (index, count),
                None if top > 0 => {
                    top -= 1;
                    // SAFETY: entries below `top` were all written by a push.
                    let (index, count, t_enter) = unsafe { stack[top].assume_init() };
                    // A closer hit found since the push rules the node out.
                    if t_enter > *t_max {
                        continue;
                    }
                    (index, count)
                }
                None => return,
            };
            if count > 0 {
                for prim in index..index + count {
                    if visit(prim, t_max) {
                        return;
                    }
                }
                continue;
            }
            let n = &self.nodes[index as usize];
            let (near, mut mask) = slab.test(n, *t_max);
            if mask == 0 {
                continue;
            }
            let near = near.to_array();
            // A child's sort key: its entry distance's bits (never negative, so they
            // order as the distance does) with the lane in the lowest three, which only
            // breaks near-ties.
            let key = |lane: usize| (near[lane].to_bits() & !7) | lane as u32;
            let lane_of = |key: u32| (key & 7) as usize;
            let entry = |lane: usize| {
                let (child, count) = (n.child[lane], n.count[lane]);
                self.prefetch_child(leaves, child, count);
                (child, count, near[lane])
            };
            if mask & (mask - 1) == 0 || order == Order::Any {
                // One child (the common case), or any-hit order: the first is next, the
                // rest go on the stack as they come.
                next = Some(entry(lowest_lane(mask)));
                mask &= mask - 1;
                while mask != 0 {
                    stack[top].write(entry(lowest_lane(mask)));
                    top += 1;
                    mask &= mask - 1;
                }
                continue;
            }
            // Two children (most nodes with more than one): the farther is pushed and the
            // nearer is next, ordered by the keys the sort below orders by, with no loop.
            let rest = mask & (mask - 1);
            if rest & (rest - 1) == 0 {
                let (a, b) = (key(lowest_lane(mask)), key(lowest_lane(rest)));
                let (nearer, farther) = if b < a { (b, a) } else { (a, b) };
                stack[top].write(entry(lane_of(farther)));
                top += 1;
                next = Some(entry(lane_of(nearer)));
                continue;
            }
            // Sort the hit children farthest first: all but the nearest are pushed, so
            // the nearest of them is popped first. Sorted as keys of four bytes rather
            // than as stack entries of twelve.
            let mut keys = [0u32; WIDTH];
            let mut k = 0;
            while mask != 0 {
                let lane = lowest_lane(mask);
                // Loads started as soon as the children are known.
                self.prefetch_child(leaves, n.child[lane], n.count[lane]);
                insert_farthest_first(&mut keys, &mut k, key(lane), |&key| key);
                mask &= mask - 1;
            }
            let sorted_entry = |key: u32| {
                let lane = lane_of(key);
                (n.child[lane], n.count[lane], near[lane])
            };
            for &key in &keys[..k - 1] {
                stack[top].write(sorted_entry(key));
                top += 1;
            }
            next = Some(sorted_entry(keys[k - 1]));
        }
    }
}

impl WideBvh {
    /// Starts loading a child that is about to be pushed or visited: its node, or its
    /// leaf's first two primitives (a leaf holds one or two packets, except the rare
    /// one the depth limit forced, whose first two are enough).
    #[inline(always)]
    pub(super) fn prefetch_child<P>(&self, leaves: &[P], child: u32, count: u32) {
        if count == 0 {
            prefetch(&self.nodes[child as usize]);
        } else if let Some(first) = leaves.get(child as usize) {
            prefetch(first);
            if count > 1
                && let Some(second) = leaves.get(child as usize + 1)
            {
                prefetch(second);
            }
        }
    }
}

/// The lowest set lane of a child mask, masked to the eight lanes so that indexing a
/// node's arrays by it needs no bounds check.
#[inline(always)]
pub(super) fn lowest_lane(mask: u32) -> usize {
    (mask.trailing_zeros() & (WIDTH as u32 - 1)) as usize
}

/// Inserts `entry` into `sorted[..*len]`, kept farthest first by `distance`: the caller
/// pushes all but the last, so the nearest of the pushed ones is popped first.
#[inline(always)]
pub(super) fn insert_farthest_first<E: Copy, D: PartialOrd>(
    sorted: &mut [E],
    len: &mut usize,
    entry: E,
    distance: impl Fn(&E) -> D,
) {
    let mut j = *len;
    while j > 0 && distance(&sorted[j - 1]) < distance(&entry) {
        sorted[j] = sorted[j - 1];
        j -= 1;
    }
    sorted[j] = entry;
    *len += 1;
}

/// A ray prepared for slab tests against a node's eight boxes at once.
#[derive(Clone, Copy)]
pub(super) struct SlabRay<L: Lanes> {
    lanes: L,
    inv: [L::V; 3],
    /// `inv` widened by [`ROBUST_FAR`], for the far planes: the far distances come out
    /// widened, with no multiply of their own on the way to the compare.
    inv_far: [L::V; 3],
    origin: [L::V; 3],
    near_plane: [usize; 3],
    far_plane: [usize; 3],
}

impl<L: Lanes> SlabRay<L> {
    #[inline(always)]
    pub(super) fn new(lanes: L, ray: &Ray) -> Self {
        // A zero component gives 1/d = ±∞: the slab distances are then ±∞ (the ray
        // never crosses that plane) or, where the origin lies on the plane, 0·∞ = NaN,
        // which `interval` ignores, so the ray counts as inside the closed slab for all
        // t. An empty lane (+∞ … −∞) is never entered: ∞ − o is never 0.
        let inv = ray.dir.recip();
        // The plane a ray meets first on each axis is the lower one where it travels
        // up that axis and the upper one otherwise, so each axis costs one subtract and
        // one multiply per plane and no min/max (Williams et al., "An Efficient and
        // Robust Ray–Box Intersection Algorithm", 2005).
        let near_plane = [0, 1, 2].map(|a| 2 * a + usize::from(inv[a] < 0.0));
        SlabRay {
            lanes,
            inv: [inv.x, inv.y, inv.z].map(|x| lanes.splat(x)),
            inv_far: [inv.x, inv.y, inv.z].map(|x| lanes.splat(x * ROBUST_FAR)),
            origin: [ray.origin.x, ray.origin.y, ray.origin.z].map(|x| lanes.splat(x)),
            near_plane,
            far_plane: near_plane.map(|p| p ^ 1),
        }
    }

    /// Where the ray enters each of `n`'s boxes and where it leaves them or reaches
    /// `t_max`, whichever is first: a box is entered where the first is ≤ the second.
    #[inline(always)]
    fn interval(&self, n: &WideNode, t_max: f32) -> (L::V, L::V) {
        let lanes = self.lanes;
        let slab = |plane: usize, axis: usize, inv: &[L::V; 3]| {
            lanes.load(&n.bounds[plane]).sub(self.origin[axis]).mul(inv[axis])
        };
        let [nx, ny, nz] = self.near_plane;
        let [fx, fy, fz] = self.far_plane;
        let (inv, inv_far) = (&self.inv, &self.inv_far);
        // `min` and `max` return their second operand where either is NaN: each slab
        // distance comes first, so a NaN one (origin on that plane, d parallel to it)
        // drops out and the accumulator, which starts finite, never becomes NaN.
        let near = slab(nx, 0, inv).max(slab(ny, 1, inv).max(slab(nz, 2, inv).max(lanes.splat(0.0))));
        // Widened as in `Aabb::hit_interval` so flat boxes hit on an edge are kept; the
        // chain starts from `t_max`, so it ends in the compare.
        let far = slab(fx, 0, inv_far).min(slab(fy, 1, inv_far).min(slab(fz, 2, inv_far).min(lanes.splat(t_max))));
        (near, far)
    }

    /// The distances at which the ray enters each of `n`'s boxes, and the mask of the
    /// boxes it enters before `t_max`.
    #[inline(always)]
    pub(super) fn test(&self, n: &WideNode, t_max: f32) -> (L::V, u32) {
        let (near, far) = self.interval(n, t_max);
        (near, near.le_mask(far))
    }

    /// As [`SlabRay::test`], with +∞ as the entry distance of the boxes missed.
    #[inline(always)]
    pub(super) fn test_or_infinity(&self, n: &WideNode, t_max: f32) -> (L::V, u32) {
        let (near, far) = self.interval(n, t_max);
        (near.select_le(far, near, self.lanes.splat(f32::INFINITY)), near.le_mask(far))
    }
}

/// The binary nodes that become the wide node for the inner binary node `n2`: its
/// children, with the largest inner one opened until there are eight (past where the
/// SAH would stop, as Embree fills its nodes). Returns them and how many there are.
fn wide_children(bvh: &Bvh, n2: usize) -> ([usize; WIDTH], usize) {
    let node = &bvh.nodes[n2];
    let mut kids = [0; WIDTH];
    (kids[0], kids[1]) = (node.index as usize, node.index as usize + 1);
    let mut len = 2;
    let area = |i: usize| Aabb::new(bvh.nodes[i].min, bvh.nodes[i].max).half_area();
    while len < WIDTH {
        let Some(open) = (0..len)
            .filter(|&k| bvh.nodes[kids[k]].count == 0)
            .max_by(|&a, &b| area(kids[a]).total_cmp(&area(kids[b])))
        else {
            break;
        };
        // As a swap-remove and two pushes would order them.
        let first = bvh.nodes[kids[open]].index as usize;
        kids[open] = kids[len - 1];
        (kids[len - 1], kids[len]) = (first, first + 1);
        len += 1;
    }
    (kids, len)
}

/// Builds the wide node for the inner binary node `n2` and its descendants (in
/// pre-order) onto `out`, and returns its index: each child becomes a leaf where the SAH
/// prefers one and a wide node otherwise.
fn collapse(bvh: &Bvh, n2: usize, out: &mut Vec<WideNode>) -> u32 {
    let me = out.len();
    out.push(WideNode::UNUSED);
    let (kids, len) = wide_children(bvh, n2);
    for (lane, &k) in kids[..len].iter().enumerate() {
        let child = bvh.nodes[k];
        let (index, count) = if bvh.leaf_preferred[k] { bvh.primitives(k) } else { (collapse(bvh, k, out), 0) };
        let n = &mut out[me];
        n.set_box(lane, Aabb::new(child.min, child.max));
        n.child[lane] = index;
        n.count[lane] = count;
    }
    me as u32
}

/// [`collapse`] of the whole tree from the root `n2`, the root's children collapsed in
/// parallel into vectors of their own and then appended in order, their inner indices
/// moved by where they land: the same nodes in the same order as [`collapse`] gives.
fn collapse_in_parallel(bvh: &Bvh, n2: usize) -> Vec<WideNode> {
    use rayon::prelude::*;
    let (kids, len) = wide_children(bvh, n2);
    let subtrees: Vec<Vec<WideNode>> = kids[..len]
        .par_iter()
        .map(|&k| {
            let mut nodes = Vec::new();
            if !bvh.leaf_preferred[k] {
                collapse(bvh, k, &mut nodes);
            }
            nodes
        })
        .collect();
    let total = 1 + subtrees.iter().map(Vec::len).sum::<usize>();
    let mut out = super::with_capacity_on_huge_pages(total);
    out.push(WideNode::UNUSED);
    for (lane, (&k, subtree)) in kids[..len].iter().zip(&subtrees).enumerate() {
        let child = bvh.nodes[k];
        let (index, count) = if bvh.leaf_preferred[k] { bvh.primitives(k) } else { (out.len() as u32, 0) };
        let offset = out.len() as u32;
        out.extend(subtree.iter().map(|node| {
            let mut node = *node;
            for lane in 0..WIDTH {
                if node.count[lane] == 0 {
                    node.child[lane] += offset;
                }
            }
            node
        }));
        out[0].set_box(lane, Aabb::new(child.min, child.max));
        out[0].child[lane] = index;
        out[0].count[lane] = count;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a traversal calls at each primitive.
    type Visit<'a> = dyn FnMut(u32, &mut f32) -> bool + 'a;

    fn random_boxes(n: usize, next: &mut impl FnMut() -> f32) -> Vec<Aabb> {
        (0..n)
            .map(|_| {
                let c = Vec3::new(next(), next(), next()) * 20.0 - 10.0;
                let h = Vec3::new(next(), next(), next()) * 0.6;
                Aabb::new(c - h, c + h)
            })
            .collect()
    }

    /// The root's subtrees collapsed in parallel and stitched together are the very
    /// nodes, in the very order, that one serial pre-order collapse writes.
    #[test]
    fn parallel_collapse_is_the_serial_collapse() {
        let mut state = 7u32;
        let mut next = || {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            (state >> 8) as f32 / (1 << 24) as f32
        };
        let (bvh, _) = Bvh::build(&random_boxes(20_000, &mut next));
        let mut serial = Vec::new();
        collapse(&bvh, 0, &mut serial);
        let parallel = collapse_in_parallel(&bvh, 0);
        assert!(serial.len() > 1000);
        assert!(serial == parallel, "{} serial nodes, {} parallel", serial.len(), parallel.len());
    }

    /// Every box the ray enters, by brute force and through the wide hierarchy in both
    /// orders and on every lane implementation this CPU has, over a few thousand boxes
    /// (a tree several levels deep), axis-parallel rays included.
    #[test]
    fn visits_exactly_the_boxes_the_ray_enters() {
        let mut rng = crate::sampling::Rng::new(7);
        let mut next = move || rng.next_f32();
        let boxes = random_boxes(3000, &mut next);
        let (bvh, order) = Bvh::build(&boxes);
        let wide = WideBvh::from_binary(&bvh);
        assert!(wide.nodes.len() < bvh.nodes.len() / 4);
        for i in 0..300 {
            let origin = Vec3::new(next(), next(), next()) * 30.0 - 15.0;
            let mut dir = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
            if i % 3 == 0 {
                dir[i % 9 / 3] = 0.0;
            }
            let ray = Ray::new(origin, dir);
            let inv = dir.recip();
            let brute: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].hit_interval(&ray, inv, f32::INFINITY).is_some())
                .collect();
            let collect = |traverse: &dyn Fn(&mut Visit)| {
                let mut found = Vec::new();
                traverse(&mut |prim, _| {
                    let original = order[prim as usize];
                    if boxes[original as usize].hit_interval(&ray, inv, f32::INFINITY).is_some() {
                        found.push(original);
                    }
                    false
                });
                found.sort();
                found
            };
            for order in [Order::NearestFirst, Order::Any] {
                let portable =
                    collect(&|v| wide.traverse_with::<_, ()>(Portable, order, &[], &ray, &mut { f32::INFINITY }, v));
                assert_eq!(brute, portable);
                #[cfg(target_arch = "x86_64")]
                if let Some(lanes) =
                    super::super::lanes::avx2_token_or_skip("wide::visits_exactly_the_boxes_the_ray_enters")
                {
                    #[target_feature(enable = "avx2")]
                    fn avx(lanes: crate::accel::lanes::Avx2, w: &WideBvh, o: Order, r: &Ray, v: &mut Visit) {
                        w.traverse_with::<_, ()>(lanes, o, &[], r, &mut { f32::INFINITY }, v);
                    }
                    // SAFETY: the token says this CPU has AVX2.
                    let found = collect(&|v| unsafe { avx(lanes, &wide, order, &ray, v) });
                    assert_eq!(brute, found);
                }
            }
        }
    }

    /// A ray in a face plane of a box, parallel to it (a zero direction component of
    /// either sign), is inside that closed slab for all t and enters the box, on the
    /// lower face and the upper and on every lane implementation. A ±0 component was
    /// once taken for a tiny ±1e-30, which leaves the plane at t = 0.
    #[test]
    fn rays_in_a_face_plane_enter_the_box() {
        let b = Aabb::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        let wide = WideBvh::from_binary(&Bvh::build(&[b]).0);
        // Leaves visited, per lane implementation this CPU has.
        let visits = |order: Order, ray: &Ray| {
            let mut counts = Vec::new();
            let mut n = 0;
            wide.traverse_with::<_, ()>(Portable, order, &[], ray, &mut { f32::INFINITY }, |_, _| {
                n += 1;
                false
            });
            counts.push(n);
            #[cfg(target_arch = "x86_64")]
            if let Some(lanes) = super::super::lanes::avx2_token_or_skip("wide::rays_in_a_face_plane_enter_the_box") {
                #[target_feature(enable = "avx2")]
                fn avx(lanes: crate::accel::lanes::Avx2, w: &WideBvh, o: Order, r: &Ray, v: &mut Visit) {
                    w.traverse_with::<_, ()>(lanes, o, &[], r, &mut { f32::INFINITY }, v);
                }
                let mut n = 0;
                // SAFETY: the token says this CPU has AVX2.
                unsafe {
                    avx(lanes, &wide, order, ray, &mut |_, _| {
                        n += 1;
                        false
                    })
                };
                counts.push(n);
            }
            counts
        };
        for axis in 0..3 {
            let (next, last) = ((axis + 1) % 3, (axis + 2) % 3);
            for face in [b.min[axis], b.max[axis]] {
                for zero in [0.0, -0.0] {
                    // From outside the box on the next axis, into it, a little askew.
                    let mut origin = b.center();
                    (origin[axis], origin[next]) = (face, -1.0);
                    let mut dir = Vec3::ZERO;
                    (dir[axis], dir[next], dir[last]) = (zero, 1.0, 0.1);
                    let ray = Ray::new(origin, dir);
                    for order in [Order::NearestFirst, Order::Any] {
                        let counts = visits(order, &ray);
                        assert!(counts.iter().all(|&n| n == 1), "{ray:?} in face {face} of axis {axis}: {counts:?}");
                    }
                }
            }
        }
    }

    /// Nearest-first order: along a row of disjoint boxes, leaves come in the order the
    /// ray meets them, from either end.
    #[test]
    fn nearest_first_visits_disjoint_leaves_in_order() {
        let boxes: Vec<Aabb> =
            (0..500).map(|i| Aabb::new(Vec3::new(i as f32, 0.0, 0.0), Vec3::new(i as f32 + 0.5, 1.0, 1.0))).collect();
        let (bvh, order) = Bvh::build(&boxes);
        let wide = WideBvh::from_binary(&bvh);
        // Each leaf's lowest x, by the leaf's first primitive.
        let mut leaf_x = std::collections::HashMap::new();
        for n in &wide.nodes {
            for lane in (0..WIDTH).filter(|&l| n.count[l] != 0 && n.count[l] != EMPTY) {
                let range = n.child[lane]..n.child[lane] + n.count[lane];
                let x = range.clone().map(|p| order[p as usize] as f32).fold(f32::INFINITY, f32::min);
                leaf_x.extend(range.map(|p| (p, x)));
            }
        }
        for (origin, dir) in [(Vec3::new(-1.0, 0.5, 0.5), Vec3::X), (Vec3::new(600.0, 0.5, 0.5), -Vec3::X)] {
            let mut xs: Vec<f32> = Vec::new();
            wide.traverse(&Ray::new(origin, dir), &mut { f32::INFINITY }, |p, _| {
                xs.push(leaf_x[&p] * dir.x);
                false
            });
            assert_eq!(xs.len(), 500);
            assert!(xs.windows(2).all(|w| w[0] <= w[1]), "leaves out of order: {xs:?}");
        }
    }
}

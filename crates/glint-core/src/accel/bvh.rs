//! A binary bounding-volume hierarchy built with the binned surface-area heuristic
//! (Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", 2007), in
//! parallel: the build step before the collapse to the 8-wide [`super::WideBvh`] that
//! rays traverse.
//!
//! What makes it fast is what it does not do, as in Embree's builders: one pass bins a
//! node's primitives on all three axes at once, from 32-byte records that hold nothing
//! but a box and an index; the partition that follows also finds both sides' bounds, so
//! no node makes a pass of its own for them; the split sweep has no branches on the
//! bins' counts, which in the many small nodes near the leaves follow no pattern a CPU
//! predicts; and subtrees small enough for one thread write their nodes compactly, so
//! memory they do not use is never touched.

use bytemuck::{Pod, Zeroable};
use glam::{BVec4A, Vec3, Vec4};

use crate::math::Aabb;

/// One node, 32 bytes. An interior node's two children are stored side by side at
/// `index` and `index + 1`; a leaf's `index` is its first primitive. Node 0 is the root and node 1 is unused, so sibling pairs start at even
/// indices.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub min: Vec3,
    pub index: u32,
    pub max: Vec3,
    /// Number of primitives in a leaf; 0 for interior nodes.
    pub count: u32,
}

impl BvhNode {
    fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }
}

/// The hierarchy over primitives `0..n`; [`Bvh::build`] returns the order in which the
/// caller must store its primitives so that each leaf covers a contiguous range.
///
/// It is split down to leaves of one block, further than the SAH would stop, and each
/// node records in [`Bvh::leaf_preferred`] whether the SAH finds one leaf of it cheaper: the
/// collapse to [`super::WideBvh`] opens nodes past that point to fill its eight slots,
/// as Embree's builders do, and ends a branch where the SAH asks for a leaf.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    /// Slot 0 is the root; a subtree of `n` primitives owns `2n − 2` slots after its
    /// children, so subtrees build in parallel without sharing any. A subtree uses the
    /// front of its slots; those it did not need stay zeroed and unreferenced.
    pub nodes: Vec<BvhNode>,
    /// Per node: whether the SAH finds one leaf of its primitives cheaper than any
    /// split (always true of a leaf). One byte a slot: build scratch stays small.
    pub leaf_preferred: Vec<bool>,
}

/// A power of two (binning masks with `BINS - 1`).
const BINS: usize = 16;
/// Largest leaf the SAH may choose, in blocks.
const MAX_LEAF_BLOCKS: usize = 2;
/// Cost of one traversal step relative to one primitive intersection.
const TRAVERSAL_COST: f32 = 1.0;
/// Deeper subtrees become leaves, so the traversal stack (one entry per level) can
/// never overflow, however unbalanced the SAH splits.
const MAX_DEPTH: usize = 60;
/// Subtrees with more primitives than this build their two halves in parallel; smaller
/// ones build on one thread, compactly.
const PARALLEL_ABOVE: usize = 4096;
/// Nodes with more primitives than this bin them in parallel chunks of this size: the
/// top of the tree, where otherwise one core bins everything while the others wait.
const PARALLEL_BINNING_CHUNK: usize = 1 << 15;

/// One primitive during the build, 32 bytes: its box, with the primitive's index in
/// the spare fourth lane of `lo` (and 0 in `hi`'s), so a partition moves one aligned
/// pair of vectors and binning reads nothing else.
#[derive(Clone, Copy)]
#[repr(C)]
struct PrimRef {
    lo: Vec4,
    hi: Vec4,
}

/// Keeps x, y, z and zeroes w: masked with bits, not arithmetic, so an index's bits in
/// w never enter a floating-point operation (as a denormal they could be slow).
#[inline(always)]
fn xyz(v: Vec4) -> Vec4 {
    Vec4::select(BVec4A::new(true, true, true, false), v, Vec4::ZERO)
}

impl PrimRef {
    fn new(bounds: &Aabb, index: u32) -> Self {
        PrimRef { lo: bounds.min.extend(f32::from_bits(index)), hi: bounds.max.extend(0.0) }
    }

    fn index(&self) -> u32 {
        self.lo.w.to_bits()
    }

    /// Twice the box's centre, w = 0: binning compares centroids only against each
    /// other, and `min + max` is exactly twice `0.5·(min + max)`, so the bins are those
    /// of the centres themselves.
    #[inline(always)]
    fn centroid2(&self) -> Vec4 {
        xyz(self.lo) + self.hi
    }
}

/// Bounds of a set of primitives' boxes and of their doubled centroids: computed while
/// partitioning the parent, so a node never makes a pass of its own to find them.
#[derive(Clone, Copy)]
struct Extents {
    lo: Vec4,
    hi: Vec4,
    c_lo: Vec4,
    c_hi: Vec4,
}

impl Extents {
    const EMPTY: Extents =
        Extents { lo: Vec4::INFINITY, hi: Vec4::NEG_INFINITY, c_lo: Vec4::INFINITY, c_hi: Vec4::NEG_INFINITY };

    #[inline(always)]
    fn add(&mut self, p: &PrimRef) {
        self.lo = self.lo.min(p.lo);
        self.hi = self.hi.max(p.hi);
        let c = p.centroid2();
        self.c_lo = self.c_lo.min(c);
        self.c_hi = self.c_hi.max(c);
    }

    fn merge(self, o: Extents) -> Extents {
        Extents {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
            c_lo: self.c_lo.min(o.c_lo),
            c_hi: self.c_hi.max(o.c_hi),
        }
    }

    fn of(prims: &[PrimRef]) -> Extents {
        let mut e = Extents::EMPTY;
        prims.iter().for_each(|p| e.add(p));
        e
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(self.lo.truncate(), self.hi.truncate())
    }
}

/// Where a node's doubled centroids fall among the bins of each axis; an axis along
/// which they all coincide gets scale 0 (everything in bin 0) and is never split.
#[derive(Clone, Copy)]
struct BinMap {
    offset: Vec4,
    scale: Vec4,
}

impl BinMap {
    fn new(e: &Extents) -> Self {
        let extent = (e.c_hi - e.c_lo).truncate();
        let scale = Vec3::select(extent.cmpgt(Vec3::ZERO), BINS as f32 / extent, Vec3::ZERO);
        BinMap { offset: xyz(e.c_lo), scale: scale.extend(0.0) }
    }

    fn splits_along(&self, axis: usize) -> bool {
        self.scale[axis] > 0.0
    }

    /// The bin of `p` along each axis (x, y, z; w is 0). The clamp comes before the
    /// conversion, which then fits in one vector instruction and gives the same bins as
    /// converting first.
    #[inline(always)]
    fn bins_of(&self, p: &PrimRef) -> [u32; 4] {
        let b = ((p.centroid2() - self.offset) * self.scale).min(Vec4::splat((BINS - 1) as f32));
        truncate_to_u32(b)
    }

    #[inline(always)]
    fn bin_of(&self, p: &PrimRef, axis: usize) -> u32 {
        self.bins_of(p)[axis]
    }
}

/// `v`'s lanes, all in `[0, 2³¹)`, truncated toward zero.
#[inline(always)]
fn truncate_to_u32(v: Vec4) -> [u32; 4] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128, _mm_cvttps_epi32};
        // SAFETY: SSE2 is part of every x86-64 CPU.
        bytemuck::cast(unsafe { _mm_cvttps_epi32(__m128::from(v)) })
    }
    #[cfg(not(target_arch = "x86_64"))]
    v.to_array().map(|x| x as u32)
}

/// Per axis and bin, the bounds and number of the primitives whose centroid falls in it.
#[derive(Clone, Copy)]
struct Bins {
    lo: [[Vec4; BINS]; 3],
    hi: [[Vec4; BINS]; 3],
    count: [[u32; BINS]; 3],
}

impl Bins {
    const EMPTY: Bins =
        Bins { lo: [[Vec4::INFINITY; BINS]; 3], hi: [[Vec4::NEG_INFINITY; BINS]; 3], count: [[0; BINS]; 3] };

    /// Adds `prims` on all three axes in one pass. Neighbouring primitives tend to share
    /// bins, so even and odd ones go to two sets of bins, merged at the end: no update
    /// waits on the one just before it. In place, since a `Bins` is 1.7 KB to copy.
    fn fill(&mut self, prims: &[PrimRef], map: &BinMap) {
        if prims.len() < 64 {
            // Too few for a second set of bins to pay for clearing it.
            prims.iter().for_each(|p| self.add(p, map));
            return;
        }
        let mut odd = Bins::EMPTY;
        let mut pairs = prims.chunks_exact(2);
        for pair in &mut pairs {
            self.add(&pair[0], map);
            odd.add(&pair[1], map);
        }
        pairs.remainder().iter().for_each(|p| self.add(p, map));
        self.merge(&odd);
    }

    #[inline(always)]
    fn add(&mut self, p: &PrimRef, map: &BinMap) {
        let b = map.bins_of(p);
        for axis in 0..3 {
            // Already below BINS; the mask only spares the bounds checks.
            let b = b[axis] as usize & (BINS - 1);
            self.lo[axis][b] = self.lo[axis][b].min(p.lo);
            self.hi[axis][b] = self.hi[axis][b].max(p.hi);
            self.count[axis][b] += 1;
        }
    }

    /// Empties the bins in place, by stores: assigning [`Bins::EMPTY`] copied its 1.7 KB
    /// with a `memcpy` call, as did returning a `Bins`, twice a node (3% of a build).
    #[inline(always)]
    fn clear(&mut self) {
        for axis in 0..3 {
            self.lo[axis].fill(Vec4::INFINITY);
            self.hi[axis].fill(Vec4::NEG_INFINITY);
            self.count[axis].fill(0);
        }
    }

    /// The bins of `prims` alone, in place: [`Bins::fill`] from empty bins, in parallel
    /// chunks when there are many primitives.
    fn bin(&mut self, prims: &[PrimRef], map: &BinMap) {
        use rayon::prelude::*;
        if prims.len() <= 2 * PARALLEL_BINNING_CHUNK {
            self.clear();
            self.fill(prims, map);
            return;
        }
        let one_chunk = |chunk: &[PrimRef]| {
            let mut bins = Bins::EMPTY;
            bins.fill(chunk, map);
            bins
        };
        *self = prims.par_chunks(PARALLEL_BINNING_CHUNK).map(one_chunk).reduce(
            || Bins::EMPTY,
            |mut a, b| {
                a.merge(&b);
                a
            },
        );
    }

    fn merge(&mut self, o: &Bins) {
        for axis in 0..3 {
            for b in 0..BINS {
                self.lo[axis][b] = self.lo[axis][b].min(o.lo[axis][b]);
                self.hi[axis][b] = self.hi[axis][b].max(o.hi[axis][b]);
                self.count[axis][b] += o.count[axis][b];
            }
        }
    }
}

/// Half the surface area of the box `lo..hi` (x, y, z lanes), with the same operations
/// as [`Aabb::half_area`] for a box with something in it; for the empty box it is not a
/// number, and the sweep never chooses a side whose count is 0.
#[inline(always)]
fn half_area(lo: Vec4, hi: Vec4) -> f32 {
    let e = hi - xyz(lo);
    e.x * e.y + e.y * e.z + e.z * e.x
}

/// What one subtree build needs to know besides its primitives.
#[derive(Clone, Copy)]
struct Params {
    /// `log2` of the block size (a power of two).
    block_shift: u32,
    max_leaf: usize,
}

impl Params {
    /// Intersections a leaf of `n` primitives costs: `⌈n/block⌉`, by shifts, since the
    /// split sweep asks for it 180 times a node.
    #[inline(always)]
    fn blocks(&self, n: u32) -> f32 {
        ((n + ((1 << self.block_shift) - 1)) >> self.block_shift) as f32
    }
}

impl Bvh {
    /// Builds over finite boxes; returns the BVH and the primitive order it expects.
    pub fn build(bounds: &[Aabb]) -> (Bvh, Vec<u32>) {
        Bvh::build_blocks(bounds, 1)
    }

    /// As [`Bvh::build`], for primitives a leaf tests `block` at a time (a mesh's
    /// four-triangle packets; a power of two, others are rounded up): the SAH charges a leaf of `n` primitives `⌈n/block⌉`
    /// intersections, as Embree's builders do for their `Triangle4` leaves, and leaves
    /// hold at most one block unless the SAH prefers a bigger one. Subtrees build in
    /// parallel on rayon's pool.
    pub fn build_blocks(bounds: &[Aabb], block: usize) -> (Bvh, Vec<u32>) {
        Bvh::build_blocks_with(bounds.len(), block, |i| bounds[i])
    }

    /// As [`Bvh::build_blocks`] over primitives `0..count`, asking `bounds_of` for each
    /// box (in parallel) rather than reading a slice: a mesh need not store a box per
    /// triangle for the build to read once.
    pub fn build_blocks_with(count: usize, block: usize, bounds_of: impl Fn(usize) -> Aabb + Sync) -> (Bvh, Vec<u32>) {
        use rayon::prelude::*;
        let block = block.max(1).next_power_of_two();
        let params = Params { block_shift: block.trailing_zeros(), max_leaf: MAX_LEAF_BLOCKS * block.max(4) };
        if count == 0 {
            return (Bvh::default(), vec![]);
        }
        let mut prims: Vec<PrimRef> =
            (0..count).into_par_iter().map(|i| PrimRef::new(&bounds_of(i), i as u32)).collect();
        let extents =
            prims.par_chunks(PARALLEL_BINNING_CHUNK).map(Extents::of).reduce(|| Extents::EMPTY, Extents::merge);
        // Zeroed lazily by the OS (allocated zeroed, not written): the pages of slots no
        // subtree uses are never touched. (`vec![BvhNode::zeroed(); n]` would write every
        // one of them: only primitive types get a zeroed allocation from `vec!`.)
        let mut nodes: Vec<BvhNode> = bytemuck::zeroed_vec(2 * count);
        let mut leaf_preferred = vec![false; 2 * count];
        let (root_node, rest) = nodes.split_at_mut(2);
        let (root_leaf, rest_leaf) = leaf_preferred.split_at_mut(2);
        let region = Region { nodes: rest, leaf_preferred: rest_leaf, start: 2 };
        (root_node[0], root_leaf[0]) = build_subtree(&mut prims, &extents, 0, 0, region, params);
        (Bvh { nodes, leaf_preferred }, prims.par_iter().map(PrimRef::index).collect())
    }

    /// The primitives under `node` as `(first, count)`: a contiguous range from its
    /// leftmost leaf to the end of its rightmost one.
    pub fn primitives(&self, node: usize) -> (u32, u32) {
        let leaf_along = |step: u32| {
            let mut k = node;
            while self.nodes[k].count == 0 {
                k = (self.nodes[k].index + step) as usize;
            }
            self.nodes[k]
        };
        let (first, last) = (leaf_along(0), leaf_along(1));
        (first.index, last.index + last.count - first.index)
    }

    /// Bounds of everything in the hierarchy.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, BvhNode::bounds)
    }
}

/// The node slots a subtree owns for its descendants, `start` being the index of the
/// first in the whole array.
struct Region<'a> {
    nodes: &'a mut [BvhNode],
    leaf_preferred: &'a mut [bool],
    start: usize,
}

/// Builds the subtree over `prims` (whose first element is primitive `first`, and
/// whose bounds are `extents`), its descendants into `region`, and returns its root.
fn build_subtree(
    prims: &mut [PrimRef],
    extents: &Extents,
    first: u32,
    depth: usize,
    region: Region,
    params: Params,
) -> (BvhNode, bool) {
    if prims.len() <= PARALLEL_ABOVE || depth >= MAX_DEPTH {
        // Built compactly and copied into the front of the region: the slots it does
        // not use stay untouched (a subtree rarely needs a quarter of its 2n − 2).
        let mut local = Vec::new();
        let mut scratch = Bins::EMPTY;
        let root = build_compact(prims, extents, first, depth, region.start as u32, &mut local, (params, &mut scratch));
        for (k, (node, leaf)) in local.into_iter().enumerate() {
            (region.nodes[k], region.leaf_preferred[k]) = (node, leaf);
        }
        return root;
    }
    let bounds = extents.bounds();
    let mut bins = Bins::EMPTY;
    let (mid, leaf_cheaper, [left_extents, right_extents]) = sah_partition(prims, extents, params, &mut bins);
    let Region { nodes, leaf_preferred, start } = region;
    let (children, rest) = nodes.split_at_mut(2);
    let (child_leaf, rest_leaf) = leaf_preferred.split_at_mut(2);
    let left_len = 2 * mid - 2;
    let (left_nodes, right_nodes) = rest.split_at_mut(left_len);
    let (left_leaf, right_leaf) = rest_leaf.split_at_mut(left_len);
    let left_region = Region { nodes: left_nodes, leaf_preferred: left_leaf, start: start + 2 };
    let right_region = Region { nodes: right_nodes, leaf_preferred: right_leaf, start: start + 2 + left_len };
    let (left_prims, right_prims) = prims.split_at_mut(mid);
    let right_first = first + mid as u32;
    let build_left = || build_subtree(left_prims, &left_extents, first, depth + 1, left_region, params);
    let build_right = || build_subtree(right_prims, &right_extents, right_first, depth + 1, right_region, params);
    let (left, right) = rayon::join(build_left, build_right);
    (children[0], child_leaf[0]) = left;
    (children[1], child_leaf[1]) = right;
    (BvhNode { min: bounds.min, index: start as u32, max: bounds.max, count: 0 }, leaf_cheaper)
}

/// Builds the subtree over `prims` on this thread, pushing each node's pair of children
/// onto `out` (whose first slot has index `base`) before the children's own; returns the
/// subtree's root and whether the SAH prefers it as one leaf. Every node bins into
/// `bins`, scratch shared down the recursion.
fn build_compact(
    prims: &mut [PrimRef],
    extents: &Extents,
    first: u32,
    depth: usize,
    base: u32,
    out: &mut Vec<(BvhNode, bool)>,
    (params, bins): (Params, &mut Bins),
) -> (BvhNode, bool) {
    let bounds = extents.bounds();
    let n = prims.len();
    if n <= 1 << params.block_shift || depth >= MAX_DEPTH {
        return (BvhNode { min: bounds.min, index: first, max: bounds.max, count: n as u32 }, true);
    }
    let (mid, leaf_cheaper, [left_extents, right_extents]) = sah_partition(prims, extents, params, bins);
    let slot = out.len();
    out.extend([(BvhNode::zeroed(), false); 2]);
    let (left_prims, right_prims) = prims.split_at_mut(mid);
    out[slot] = build_compact(left_prims, &left_extents, first, depth + 1, base, out, (params, &mut *bins));
    let right_first = first + mid as u32;
    out[slot + 1] = build_compact(right_prims, &right_extents, right_first, depth + 1, base, out, (params, bins));
    (BvhNode { min: bounds.min, index: base + slot as u32, max: bounds.max, count: 0 }, leaf_cheaper)
}

/// The cheapest binned SAH split: its cost (unnormalized), axis and first bin on the right.
type Split = (f32, usize, usize);

/// The cheapest split of the binned primitives over all axes, if any splits them in two.
/// Only the bins with something in them are swept: every split between two of them
/// that lie next to each other, past empty bins, makes the same two sides at the same
/// cost (an empty bin's box and count leave a union and a sum exactly as they are), so
/// the sweep over the non-empty bins finds exactly the split, cost and bin the sweep
/// over all of them found, the lowest such bin. Most nodes are small, with a few of
/// their 16 bins filled.
fn best_split(bins: &Bins, map: &BinMap, n: usize, params: Params) -> Option<Split> {
    let blocks = |n: u32| params.blocks(n);
    let mut best: Option<Split> = None;
    for axis in (0..3).filter(|&a| map.splits_along(a)) {
        let (lo, hi, count) = (&bins.lo[axis], &bins.hi[axis], &bins.count[axis]);
        // The non-empty bins in order, gathered without a branch (small nodes' empty
        // bins follow no predictable pattern).
        let mut filled = [0usize; BINS];
        let mut m = 0;
        for (b, &c) in count.iter().enumerate() {
            filled[m] = b;
            m += usize::from(c != 0);
        }
        let filled = &filled[..m];
        // Sweep from the right for the cost of every right side, then from the left:
        // `right_cost[j]` is the cost of the bins from `filled[j]` on.
        let mut right_cost = [0.0f32; BINS];
        let (mut acc_lo, mut acc_hi, mut k) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0);
        for j in (1..m).rev() {
            let b = filled[j];
            (acc_lo, acc_hi, k) = (acc_lo.min(lo[b]), acc_hi.max(hi[b]), k + count[b]);
            right_cost[j] = half_area(acc_lo, acc_hi) * blocks(k);
        }
        let (mut acc_lo, mut acc_hi, mut k) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0);
        for j in 1..m {
            let b = filled[j - 1];
            (acc_lo, acc_hi, k) = (acc_lo.min(lo[b]), acc_hi.max(hi[b]), k + count[b]);
            let cost = half_area(acc_lo, acc_hi) * blocks(k) + right_cost[j];
            if best.is_none_or(|(c, _, _)| cost < c) {
                // The lowest bin that starts the right side: the one after the left's last.
                best = Some((cost, axis, b + 1));
            }
        }
    }
    debug_assert!(best.is_none_or(|(_, axis, split)| {
        let left: u32 = bins.count[axis][..split].iter().sum();
        left != 0 && (left as usize) < n
    }));
    best
}

/// Partitions `prims` at the cheapest binned SAH split (in the middle where all
/// centroids coincide); returns where, whether one leaf would be cheaper still (and
/// small enough), and the extents of the two sides. A leaf of `n` costs `⌈n/block⌉`
/// intersections.
fn sah_partition(
    prims: &mut [PrimRef],
    extents: &Extents,
    params: Params,
    bins: &mut Bins,
) -> (usize, bool, [Extents; 2]) {
    let n = prims.len();
    let map = BinMap::new(extents);
    bins.bin(prims, &map);
    let bins = &*bins;
    let leaf_cost = params.blocks(n as u32);
    let small = n <= params.max_leaf;
    let Some((cost, axis, split)) = best_split(bins, &map, n, params) else {
        let mid = n / 2;
        return (mid, small, [Extents::of(&prims[..mid]), Extents::of(&prims[mid..])]);
    };
    let split_cost = TRAVERSAL_COST + cost / extents.bounds().half_area().max(f32::MIN_POSITIVE);
    let leaf_cheaper = small && split_cost >= leaf_cost;
    let (mid, sides) = partition(prims, |p| (map.bin_of(p, axis) as usize) < split);
    (mid, leaf_cheaper, sides)
}

/// Moves the primitives `goes_left` says belong left before the others; returns how
/// many went left and each side's extents. One forward sweep that swaps each left one
/// into place (Lomuto's), so the order it leaves, hence which triangles share a leaf's
/// packets, is the one glint's earlier builder left: traced trees stay as they were.
/// (A branch-free version, selecting every swap and bound, was 1.4× slower.)
fn partition(prims: &mut [PrimRef], goes_left: impl Fn(&PrimRef) -> bool) -> (usize, [Extents; 2]) {
    let (mut left, mut right) = (Extents::EMPTY, Extents::EMPTY);
    let mut mid = 0;
    for i in 0..prims.len() {
        if goes_left(&prims[i]) {
            left.add(&prims[i]);
            prims.swap(i, mid);
            mid += 1;
        } else {
            right.add(&prims[i]);
        }
    }
    (mid, [left, right])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Ray;
    use proptest::prelude::*;

    fn boxes_from(seeds: &[(f32, f32, f32, f32)]) -> Vec<Aabb> {
        seeds
            .iter()
            .map(|&(x, y, z, s)| {
                let c = Vec3::new(x, y, z);
                Aabb::new(c - Vec3::splat(s), c + Vec3::splat(s))
            })
            .collect()
    }

    /// Every box the ray enters, found by brute force and by traversing the wide
    /// hierarchy collapsed from this one.
    fn entered(boxes: &[Aabb], ray: &Ray) -> (Vec<u32>, Vec<u32>) {
        let inv = ray.dir.recip();
        let brute: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| boxes[i as usize].hit_interval(ray, inv, f32::INFINITY).is_some())
            .collect();
        let (bvh, order) = Bvh::build(boxes);
        let wide = super::super::WideBvh::from_binary(&bvh);
        let mut found = Vec::new();
        wide.traverse(ray, &mut { f32::INFINITY }, |prim, _| {
            let original = order[prim as usize];
            if boxes[original as usize].hit_interval(ray, inv, f32::INFINITY).is_some() {
                found.push(original);
            }
            false
        });
        found.sort();
        (brute, found)
    }

    proptest! {
        #[test]
        fn traversal_finds_exactly_what_brute_force_finds(
            seeds in prop::collection::vec((-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0, 0.05f32..2.0), 1..200),
            origin in (-20.0f32..20.0, -20.0f32..20.0, -20.0f32..20.0),
            dir in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        ) {
            let dir = Vec3::new(dir.0, dir.1, dir.2);
            prop_assume!(dir.length() > 1e-3);
            let ray = Ray::new(Vec3::new(origin.0, origin.1, origin.2), dir);
            let boxes = boxes_from(&seeds);
            let (brute, found) = entered(&boxes, &ray);
            prop_assert_eq!(brute, found);
        }
    }

    fn prim_refs(n: usize) -> Vec<PrimRef> {
        let mut state = 11u32;
        let mut next = || {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            (state >> 8) as f32 / (1 << 24) as f32
        };
        (0..n)
            .map(|i| {
                let c = Vec3::new(next(), next(), next()) * 8.0 - 4.0;
                let h = Vec3::new(next(), next(), next()) * 0.3;
                PrimRef::new(&Aabb::new(c - h, c + h), i as u32)
            })
            .collect()
    }

    fn same_extents(a: &Extents, b: &Extents) -> bool {
        let xyz = |v: Vec4| v.truncate();
        (xyz(a.lo), xyz(a.hi), xyz(a.c_lo), xyz(a.c_hi)) == (xyz(b.lo), xyz(b.hi), xyz(b.c_lo), xyz(b.c_hi))
    }

    /// The extents a partition hands each side are those a fresh pass over the side
    /// finds, and the two sides are exactly the primitives left and right of the split.
    #[test]
    fn a_partition_carries_exact_extents_to_both_sides() {
        let mut prims = prim_refs(5000);
        let map = BinMap::new(&Extents::of(&prims));
        let goes_left = |p: &PrimRef| map.bin_of(p, 1) < 7;
        let lefts = prims.iter().filter(|p| goes_left(p)).count();
        let (mid, [left, right]) = partition(&mut prims, goes_left);
        assert_eq!(mid, lefts);
        assert!(prims[..mid].iter().all(goes_left) && !prims[mid..].iter().any(goes_left));
        assert!(same_extents(&left, &Extents::of(&prims[..mid])));
        assert!(same_extents(&right, &Extents::of(&prims[mid..])));
        let mut indices: Vec<u32> = prims.iter().map(PrimRef::index).collect();
        indices.sort();
        assert_eq!(indices, (0..5000).collect::<Vec<_>>());
    }

    /// Binning in parallel chunks, or in the even/odd pair of bin sets, gives the bins
    /// one plain pass gives; the bins of a centroid are those of the halved centroid.
    #[test]
    fn every_way_of_binning_gives_the_same_bins() {
        let prims = prim_refs(4 * PARALLEL_BINNING_CHUNK + 3);
        let extents = Extents::of(&prims);
        let map = BinMap::new(&extents);
        let mut plain = Bins::EMPTY;
        prims.iter().for_each(|p| plain.add(p, &map));
        let mut chunked = Bins::EMPTY;
        chunked.bin(&prims, &map);
        assert_eq!(plain.count, chunked.count);
        assert!(plain.lo == chunked.lo && plain.hi == chunked.hi);
        // The reference: Wald's binning of the true centres, one axis at a time.
        let (c_min, c_max) = (0.5 * extents.c_lo.truncate(), 0.5 * extents.c_hi.truncate());
        for p in prims.iter().take(1000) {
            let centre = Aabb::new(p.lo.truncate(), p.hi.truncate()).center();
            for axis in 0..3 {
                let scale = BINS as f32 / (c_max - c_min)[axis];
                let expected = (((centre[axis] - c_min[axis]) * scale) as usize).min(BINS - 1);
                assert_eq!(map.bin_of(p, axis) as usize, expected);
            }
        }
    }

    #[test]
    fn every_primitive_is_in_exactly_one_leaf() {
        let seeds: Vec<_> = (0..1000).map(|i| ((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32, 0.3)).collect();
        let (bvh, order) = Bvh::build(&boxes_from(&seeds));
        let mut seen = vec![0; seeds.len()];
        for n in bvh.nodes.iter().filter(|n| n.count > 0) {
            for p in n.index..n.index + n.count {
                seen[order[p as usize] as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        assert!(bvh.nodes.iter().filter(|n| n.count > 0).all(|n| n.count == 1));
        // A node's primitives are the leaves below it, contiguous.
        let below = |node: usize| {
            let (mut stack, mut prims) = (vec![node], vec![]);
            while let Some(k) = stack.pop() {
                let n = bvh.nodes[k];
                if n.count > 0 {
                    prims.extend(n.index..n.index + n.count);
                } else {
                    stack.extend([n.index as usize, n.index as usize + 1]);
                }
            }
            prims.sort();
            prims
        };
        let mut reachable = vec![0usize];
        while let Some(k) = reachable.pop() {
            let (first, count) = bvh.primitives(k);
            assert_eq!(below(k), (first..first + count).collect::<Vec<_>>());
            if bvh.nodes[k].count == 0 {
                reachable.extend([bvh.nodes[k].index as usize, bvh.nodes[k].index as usize + 1]);
            }
        }
    }

    /// The sweep over every bin, empty ones too: what `best_split` did before it swept
    /// the filled bins only.
    fn best_split_over_all_bins(bins: &Bins, map: &BinMap, n: usize, params: Params) -> Option<Split> {
        let mut best: Option<Split> = None;
        for axis in (0..3).filter(|&a| map.splits_along(a)) {
            let (lo, hi, count) = (&bins.lo[axis], &bins.hi[axis], &bins.count[axis]);
            let mut right_cost = [0.0f32; BINS];
            let (mut acc_lo, mut acc_hi, mut k) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0);
            for b in (1..BINS).rev() {
                (acc_lo, acc_hi, k) = (acc_lo.min(lo[b]), acc_hi.max(hi[b]), k + count[b]);
                right_cost[b] = half_area(acc_lo, acc_hi) * params.blocks(k);
            }
            let (mut acc_lo, mut acc_hi, mut k) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0);
            for split in 1..BINS {
                (acc_lo, acc_hi, k) = (acc_lo.min(lo[split - 1]), acc_hi.max(hi[split - 1]), k + count[split - 1]);
                let cost = half_area(acc_lo, acc_hi) * params.blocks(k) + right_cost[split];
                if k != 0 && (k as usize) < n && best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, split));
                }
            }
        }
        best
    }

    proptest! {
        /// Sweeping the filled bins finds the very split (cost, axis and bin, bit for
        /// bit) that sweeping all of them found, so trees are built exactly as before:
        /// nodes of a few primitives (mostly empty bins) and of many, with ties
        /// (primitives of equal boxes) and axes that cannot split.
        #[test]
        fn filled_bins_sweep_finds_the_all_bins_split(
            prims in prop::collection::vec((0usize..3 * BINS, 0u8..4, 1u32..4), 1..40),
            flat_axis in 0usize..4,
            block_shift in 0u32..3,
        ) {
            let mut bins = Bins::EMPTY;
            for &(slot, size, copies) in &prims {
                let (axis, b) = (slot / BINS, slot % BINS);
                let c = Vec4::new(b as f32, (b * 7 % 5) as f32, (b * 3 % 4) as f32, 0.0);
                let half = Vec4::splat(0.25 + f32::from(size));
                bins.lo[axis][b] = bins.lo[axis][b].min(c - half);
                bins.hi[axis][b] = bins.hi[axis][b].max(c + half);
                bins.count[axis][b] += copies;
            }
            // Every axis holds every primitive, as after `Bins::fill`: top up the
            // others' counts in their first bin.
            let totals = bins.count.map(|c| c.iter().sum::<u32>());
            let most = *totals.iter().max().unwrap();
            for (axis, total) in totals.into_iter().enumerate() {
                if total < most {
                    bins.count[axis][0] += most - total;
                    bins.lo[axis][0] = bins.lo[axis][0].min(Vec4::ZERO);
                    bins.hi[axis][0] = bins.hi[axis][0].max(Vec4::ONE);
                }
            }
            let n = most as usize;
            let mut scale = Vec4::new(1.0, 1.0, 1.0, 0.0);
            if flat_axis < 3 {
                scale[flat_axis] = 0.0;
            }
            let map = BinMap { offset: Vec4::ZERO, scale };
            let params = Params { block_shift, max_leaf: 8 };
            let found = best_split(&bins, &map, n, params);
            let expected = best_split_over_all_bins(&bins, &map, n, params);
            prop_assert_eq!(found.map(|(c, a, b)| (c.to_bits(), a, b)), expected.map(|(c, a, b)| (c.to_bits(), a, b)));
        }
    }
}

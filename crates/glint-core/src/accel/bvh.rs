//! A binary bounding-volume hierarchy built with the binned surface-area heuristic
//! (Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", 2007), in
//! parallel: the build step before the collapse to the 8-wide [`super::WideBvh`] that
//! rays traverse.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

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
    /// children, so subtrees build in parallel without sharing any. Slots a subtree did
    /// not need stay zeroed and unreferenced.
    pub nodes: Vec<BvhNode>,
    /// Per node: whether the SAH finds one leaf of its primitives cheaper than any
    /// split (always true of a leaf). One byte a slot: build scratch stays small.
    pub leaf_preferred: Vec<bool>,
}

const BINS: usize = 16;
/// Largest leaf the SAH may choose, in blocks.
const MAX_LEAF_BLOCKS: usize = 2;
/// Cost of one traversal step relative to one primitive intersection.
const TRAVERSAL_COST: f32 = 1.0;
/// Deeper subtrees become leaves, so the traversal stack (one entry per level) can
/// never overflow, however unbalanced the SAH splits.
const MAX_DEPTH: usize = 60;
/// Subtrees with more primitives than this build their two halves in parallel.
const PARALLEL_ABOVE: usize = 4096;

#[derive(Clone, Copy)]
struct BuildItem {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

/// What one subtree build needs to know besides its primitives.
#[derive(Clone, Copy)]
struct Params {
    block: usize,
    max_leaf: usize,
}

impl Bvh {
    /// Builds over finite boxes; returns the BVH and the primitive order it expects.
    pub fn build(bounds: &[Aabb]) -> (Bvh, Vec<u32>) {
        Bvh::build_blocks(bounds, 1)
    }

    /// As [`Bvh::build`], for primitives a leaf tests `block` at a time (a mesh's
    /// four-triangle packets): the SAH charges a leaf of `n` primitives `⌈n/block⌉`
    /// intersections, as Embree's builders do for their `Triangle4` leaves, and leaves
    /// hold at most one block unless the SAH prefers a bigger one. Subtrees build in
    /// parallel on rayon's pool.
    pub fn build_blocks(bounds: &[Aabb], block: usize) -> (Bvh, Vec<u32>) {
        let block = block.max(1);
        let params = Params { block, max_leaf: MAX_LEAF_BLOCKS * block.max(4) };
        let mut items: Vec<BuildItem> = bounds
            .iter()
            .enumerate()
            .map(|(i, b)| BuildItem { bounds: *b, centroid: b.center(), index: i as u32 })
            .collect();
        let n = items.len();
        if n == 0 {
            return (Bvh::default(), vec![]);
        }
        let mut nodes = vec![BvhNode::zeroed(); 2 * n];
        let mut leaf_preferred = vec![false; 2 * n];
        let (root_node, rest) = nodes.split_at_mut(2);
        let (root_leaf, rest_leaf) = leaf_preferred.split_at_mut(2);
        let region = Region { nodes: rest, leaf_preferred: rest_leaf, start: 2 };
        (root_node[0], root_leaf[0]) = build_subtree(&mut items, 0, 0, region, params);
        (Bvh { nodes, leaf_preferred }, items.iter().map(|it| it.index).collect())
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

/// Builds the subtree over `items` (whose first element is primitive `first`), its
/// descendants into `region`, and returns its root.
fn build_subtree(items: &mut [BuildItem], first: u32, depth: usize, region: Region, params: Params) -> (BvhNode, bool) {
    let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
    let n = items.len();
    let leaf = BvhNode { min: bounds.min, index: first, max: bounds.max, count: n as u32 };
    if n <= params.block || depth >= MAX_DEPTH {
        return (leaf, true);
    }
    let (mid, leaf_cheaper) = sah_partition(items, &bounds, params);
    let Region { nodes, leaf_preferred, start } = region;
    let (children, rest) = nodes.split_at_mut(2);
    let (child_leaf, rest_leaf) = leaf_preferred.split_at_mut(2);
    let left_len = 2 * mid - 2;
    let (left_nodes, right_nodes) = rest.split_at_mut(left_len);
    let (left_leaf, right_leaf) = rest_leaf.split_at_mut(left_len);
    let left_region = Region { nodes: left_nodes, leaf_preferred: left_leaf, start: start + 2 };
    let right_region = Region { nodes: right_nodes, leaf_preferred: right_leaf, start: start + 2 + left_len };
    let (left_items, right_items) = items.split_at_mut(mid);
    let right_first = first + mid as u32;
    let build_left = || build_subtree(left_items, first, depth + 1, left_region, params);
    let build_right = || build_subtree(right_items, right_first, depth + 1, right_region, params);
    let (left, right) =
        if n > PARALLEL_ABOVE { rayon::join(build_left, build_right) } else { (build_left(), build_right()) };
    (children[0], child_leaf[0]) = left;
    (children[1], child_leaf[1]) = right;
    (BvhNode { min: bounds.min, index: start as u32, max: bounds.max, count: 0 }, leaf_cheaper)
}

/// Partitions `items` at the cheapest binned SAH split (in the middle where all
/// centroids coincide); returns where, and whether one leaf would be cheaper still
/// (and small enough). A leaf of `n` costs `⌈n/block⌉` intersections.
fn sah_partition(items: &mut [BuildItem], bounds: &Aabb, params: Params) -> (usize, bool) {
    let blocks = |n: usize| n.div_ceil(params.block) as f32;
    let centroids = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    let extent = centroids.extent();
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, split bin)
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let scale = BINS as f32 / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - centroids.min[axis]) * scale) as usize).min(BINS - 1);
        let mut bin_bounds = [Aabb::EMPTY; BINS];
        let mut bin_count = [0usize; BINS];
        for it in items.iter() {
            let b = bin_of(it.centroid);
            bin_bounds[b] = bin_bounds[b].union(it.bounds);
            bin_count[b] += 1;
        }
        // Sweep from the right to get the cost of every right side, then from the left.
        let mut right_cost = [0.0f32; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for b in (1..BINS).rev() {
            acc = acc.union(bin_bounds[b]);
            n += bin_count[b];
            right_cost[b] = acc.half_area() * blocks(n);
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for split in 1..BINS {
            acc = acc.union(bin_bounds[split - 1]);
            n += bin_count[split - 1];
            if n == 0 || n == items.len() {
                continue;
            }
            let cost = acc.half_area() * blocks(n) + right_cost[split];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, split));
            }
        }
    }
    let leaf_cost = blocks(items.len());
    let small = items.len() <= params.max_leaf;
    let Some((cost, axis, split)) = best else {
        return (items.len() / 2, small);
    };
    let split_cost = TRAVERSAL_COST + cost / bounds.half_area().max(f32::MIN_POSITIVE);
    let leaf_cheaper = small && split_cost >= leaf_cost;
    let scale = BINS as f32 / extent[axis];
    let threshold = split;
    let mut left = 0;
    for i in 0..items.len() {
        let b = (((items[i].centroid[axis] - centroids.min[axis]) * scale) as usize).min(BINS - 1);
        if b < threshold {
            items.swap(i, left);
            left += 1;
        }
    }
    (left, leaf_cheaper)
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
}

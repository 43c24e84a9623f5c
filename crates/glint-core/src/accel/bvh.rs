//! A bounding-volume hierarchy built with the binned surface-area heuristic
//! (Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", 2007) and
//! traversed iteratively, near child first.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::math::{Aabb, Ray};

/// One node, 32 bytes. An interior node's two children are stored side by side at
/// `index` and `index + 1` (one 64-byte fetch tests both); a leaf's `index` is its first
/// primitive. Node 0 is the root and node 1 is unused, so sibling pairs start at even
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
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
}

const BINS: usize = 16;
const MAX_LEAF: usize = 8;
/// Cost of one traversal step relative to one primitive intersection.
const TRAVERSAL_COST: f32 = 1.0;
/// Deeper subtrees become leaves, so the traversal stack (one entry per level) can
/// never overflow, however unbalanced the SAH splits.
const MAX_DEPTH: usize = 60;

struct BuildItem {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

impl Bvh {
    /// Builds over finite boxes; returns the BVH and the primitive order it expects.
    pub fn build(bounds: &[Aabb]) -> (Bvh, Vec<u32>) {
        Bvh::build_blocks(bounds, 1)
    }

    /// As [`Bvh::build`], for primitives a leaf tests `block` at a time (a mesh's
    /// four-triangle packets): the SAH charges a leaf of `n` primitives `⌈n/block⌉`
    /// intersections, as Embree's builders do for their `Triangle4` leaves.
    pub fn build_blocks(bounds: &[Aabb], block: usize) -> (Bvh, Vec<u32>) {
        let block = block.max(1);
        let mut items: Vec<BuildItem> = bounds
            .iter()
            .enumerate()
            .map(|(i, b)| BuildItem { bounds: *b, centroid: b.center(), index: i as u32 })
            .collect();
        let mut nodes = Vec::with_capacity(2 * bounds.len().max(1));
        if !items.is_empty() {
            nodes.resize(2, BvhNode::zeroed());
            build_node(&mut items, 0, 0, &mut nodes, 0, block);
        }
        (Bvh { nodes }, items.iter().map(|it| it.index).collect())
    }

    /// Calls `visit(primitive, t_max)` for every primitive whose leaf box the ray
    /// enters before `*t_max`; `visit` may shrink `t_max` (closest hit) and returns
    /// `true` to stop at once (any hit).
    #[inline]
    pub fn traverse(&self, ray: &Ray, t_max: &mut f32, mut visit: impl FnMut(u32, &mut f32) -> bool) {
        if self.nodes.is_empty() {
            return;
        }
        let inv_dir = ray.dir.recip();
        if self.nodes[0].bounds().hit_interval(ray, inv_dir, *t_max).is_none() {
            return;
        }
        // Each entry keeps the distance at which the ray enters the node, so a pop can
        // skip a node that a closer hit has since ruled out without testing its box again.
        let mut stack = [(0u32, 0.0f32); 64];
        let mut top = 0;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.count > 0 {
                for prim in n.index..n.index + n.count {
                    if visit(prim, t_max) {
                        return;
                    }
                }
            } else {
                let (a, b) = (n.index as usize, n.index as usize + 1);
                let hit_a = self.nodes[a].bounds().hit_interval(ray, inv_dir, *t_max);
                let hit_b = self.nodes[b].bounds().hit_interval(ray, inv_dir, *t_max);
                match (hit_a, hit_b) {
                    (Some((ta, _)), Some((tb, _))) => {
                        let (near, far, t_far) = if ta <= tb { (a, b, tb) } else { (b, a, ta) };
                        stack[top] = (far as u32, t_far);
                        top += 1;
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop until a node the ray still reaches (t_max may have shrunk).
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let (candidate, t_enter) = stack[top];
                if t_enter <= *t_max {
                    node = candidate as usize;
                    break;
                }
            }
        }
    }

    /// Bounds of everything in the hierarchy.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, BvhNode::bounds)
    }
}

/// Builds the subtree over `items` (whose first element is primitive `first`) into the
/// already reserved node `me`.
fn build_node(items: &mut [BuildItem], first: u32, depth: usize, nodes: &mut Vec<BvhNode>, me: usize, block: usize) {
    let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
    nodes[me] = BvhNode { min: bounds.min, index: first, max: bounds.max, count: items.len() as u32 };
    if items.len() <= 2 || depth >= MAX_DEPTH {
        return;
    }
    let Some(mid) = sah_partition(items, &bounds, block) else {
        return;
    };
    let children = nodes.len();
    nodes.resize(children + 2, BvhNode::zeroed());
    build_node(&mut items[..mid], first, depth + 1, nodes, children, block);
    build_node(&mut items[mid..], first + mid as u32, depth + 1, nodes, children + 1, block);
    nodes[me].index = children as u32;
    nodes[me].count = 0;
}

/// Partitions `items` at the cheapest binned SAH split, or `None` when a leaf is
/// cheaper (and small enough). A leaf of `n` costs `⌈n/block⌉` intersections.
fn sah_partition(items: &mut [BuildItem], bounds: &Aabb, block: usize) -> Option<usize> {
    let blocks = |n: usize| n.div_ceil(block) as f32;
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
    let Some((cost, axis, split)) = best else {
        // All centroids coincide: split in the middle if the leaf would be too big.
        return (items.len() > MAX_LEAF).then_some(items.len() / 2);
    };
    let split_cost = TRAVERSAL_COST + cost / bounds.half_area().max(f32::MIN_POSITIVE);
    if split_cost >= leaf_cost && items.len() <= MAX_LEAF {
        return None;
    }
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
    Some(left)
}

#[cfg(test)]
mod tests {
    use super::*;
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

    /// Every box the ray enters, found by brute force and by traversal.
    fn entered(boxes: &[Aabb], ray: &Ray) -> (Vec<u32>, Vec<u32>) {
        let inv = ray.dir.recip();
        let brute: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| boxes[i as usize].hit_interval(ray, inv, f32::INFINITY).is_some())
            .collect();
        let (bvh, order) = Bvh::build(boxes);
        let mut found = Vec::new();
        bvh.traverse(ray, &mut { f32::INFINITY }, |prim, _| {
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
        assert!(bvh.nodes.iter().filter(|n| n.count > 0).all(|n| n.count as usize <= MAX_LEAF));
    }
}

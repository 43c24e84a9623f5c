//! A 4-wide BVH made by collapsing the binary one (each node takes up to four of its
//! grandchildren, largest first), so one SIMD slab test checks four boxes at once —
//! the layout Embree's BVH4 uses (Wald et al., "Embree: A Kernel Framework for
//! Efficient CPU Ray Tracing", 2014). Nodes are plain `Pod` records, structure of arrays.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

use super::bvh::Bvh;
use crate::math::{Aabb, ROBUST_FAR, Ray};

/// `count` of an unused child slot.
pub const EMPTY: u32 = u32::MAX;

/// Four child boxes (coordinates by axis, lane = child), 128 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Bvh4Node {
    pub min_x: [f32; 4],
    pub min_y: [f32; 4],
    pub min_z: [f32; 4],
    pub max_x: [f32; 4],
    pub max_y: [f32; 4],
    pub max_z: [f32; 4],
    /// An inner child's node index, or a leaf's first primitive.
    pub child: [u32; 4],
    /// 0 for an inner child, the primitive count of a leaf, or [`EMPTY`].
    pub count: [u32; 4],
}

impl Bvh4Node {
    const UNUSED: Bvh4Node = Bvh4Node {
        min_x: [0.0; 4],
        min_y: [0.0; 4],
        min_z: [0.0; 4],
        max_x: [0.0; 4],
        max_y: [0.0; 4],
        max_z: [0.0; 4],
        child: [0; 4],
        count: [EMPTY; 4],
    };

    fn set_box(&mut self, lane: usize, b: Aabb) {
        (self.min_x[lane], self.min_y[lane], self.min_z[lane]) = (b.min.x, b.min.y, b.min.z);
        (self.max_x[lane], self.max_y[lane], self.max_z[lane]) = (b.max.x, b.max.y, b.max.z);
    }
}

/// The 4-wide hierarchy; primitives keep the order of the binary BVH it came from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh4 {
    pub nodes: Vec<Bvh4Node>,
    bounds: Option<(Vec3, Vec3)>,
}

/// Most entries the traversal stack can hold: each level pops one entry and pushes at
/// most three (the nearest of four hit children is not pushed), and the binary BVH is
/// at most 60 levels deep (so this one at most 60).
const STACK: usize = 3 * 64 + 4;

impl Bvh4 {
    /// Collapses `bvh` (whose primitive order stays valid).
    pub fn from_binary(bvh: &Bvh) -> Bvh4 {
        let mut nodes = Vec::with_capacity(bvh.nodes.len() / 2 + 1);
        if let Some(root) = bvh.nodes.first() {
            if root.count > 0 {
                let mut node = Bvh4Node::UNUSED;
                node.set_box(0, Aabb::new(root.min, root.max));
                node.child[0] = root.index;
                node.count[0] = root.count;
                nodes.push(node);
            } else {
                collapse(bvh, 0, &mut nodes);
            }
        }
        let bounds = bvh.nodes.first().map(|r| (r.min, r.max));
        Bvh4 { nodes, bounds }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds.map_or(Aabb::EMPTY, |(min, max)| Aabb::new(min, max))
    }

    /// As [`Bvh::traverse`]: `visit(primitive, t_max)` for every primitive whose leaf
    /// box the ray enters before `*t_max`, nearest boxes first; `visit` may shrink
    /// `t_max` and returns `true` to stop.
    #[inline]
    pub fn traverse(&self, ray: &Ray, t_max: &mut f32, mut visit: impl FnMut(u32, &mut f32) -> bool) {
        if self.nodes.is_empty() {
            return;
        }
        // A zero direction component becomes a tiny one of the same sign: 1/d stays
        // finite, so no 0·∞ = NaN appears when the origin lies on a slab plane.
        let tiny = |d: f32| if d.abs() < 1e-30 { 1e-30f32.copysign(d) } else { d };
        let inv = Vec3::new(tiny(ray.dir.x), tiny(ray.dir.y), tiny(ray.dir.z)).recip();
        let (ix, iy, iz) = (Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z));
        let (ox, oy, oz) = (Vec4::splat(ray.origin.x), Vec4::splat(ray.origin.y), Vec4::splat(ray.origin.z));
        // (index, count, entry distance); count 0 = inner node.
        let mut stack = [(0u32, 0u32, 0.0f32); STACK];
        let mut top = 0;
        let mut next = Some((0u32, 0u32, 0.0f32));
        loop {
            // The nearest child the last node hit is visited straight away instead of
            // being pushed and at once popped again; with that, and the other hits pushed
            // one by one instead of by a `memcpy` call, traversal got 1.25–1.47× faster
            // (docs/performance.md). Otherwise the top of the stack.
            let (index, count, t_enter) = match next.take() {
                Some(entry) => entry,
                None if top > 0 => {
                    top -= 1;
                    stack[top]
                }
                None => return,
            };
            if t_enter > *t_max {
                continue;
            }
            if count > 0 {
                for prim in index..index + count {
                    if visit(prim, t_max) {
                        return;
                    }
                }
                continue;
            }
            let n = &self.nodes[index as usize];
            let (x0, x1) = ((Vec4::from(n.min_x) - ox) * ix, (Vec4::from(n.max_x) - ox) * ix);
            let (y0, y1) = ((Vec4::from(n.min_y) - oy) * iy, (Vec4::from(n.max_y) - oy) * iy);
            let (z0, z1) = ((Vec4::from(n.min_z) - oz) * iz, (Vec4::from(n.max_z) - oz) * iz);
            let near = x0.min(x1).max(y0.min(y1)).max(z0.min(z1)).max(Vec4::ZERO);
            // Widened as in `Aabb::hit_interval` so flat boxes hit on an edge are kept.
            let far = (x0.max(x1).min(y0.max(y1)).min(z0.max(z1)) * ROBUST_FAR).min(Vec4::splat(*t_max));
            let mask = near.cmple(far).bitmask();
            if mask == 0 {
                continue;
            }
            let near = near.to_array();
            // Sort the hit children farthest first: all but the nearest are pushed, so the
            // nearest of them is popped first.
            let mut hits = [(0u32, 0u32, 0.0f32); 4];
            let mut k = 0;
            for (lane, &t_near) in near.iter().enumerate() {
                if mask & (1 << lane) != 0 && n.count[lane] != EMPTY {
                    let entry = (n.child[lane], n.count[lane], t_near);
                    // Insertion sort by decreasing distance.
                    let mut j = k;
                    while j > 0 && hits[j - 1].2 < entry.2 {
                        hits[j] = hits[j - 1];
                        j -= 1;
                    }
                    hits[j] = entry;
                    k += 1;
                }
            }
            if k == 0 {
                continue;
            }
            // One by one: at most three entries, too few to be worth a `memcpy` call.
            for &entry in &hits[..k - 1] {
                stack[top] = entry;
                top += 1;
            }
            next = Some(hits[k - 1]);
        }
    }
}

/// Builds the 4-wide node for the inner binary node `n2` and returns its index.
fn collapse(bvh: &Bvh, n2: usize, out: &mut Vec<Bvh4Node>) -> u32 {
    let me = out.len();
    out.push(Bvh4Node::UNUSED);
    let node = &bvh.nodes[n2];
    let mut kids = vec![node.index as usize, node.index as usize + 1];
    // Open the largest inner child until there are four.
    while kids.len() < 4 {
        let area = |i: usize| Aabb::new(bvh.nodes[i].min, bvh.nodes[i].max).half_area();
        let Some(open) = (0..kids.len())
            .filter(|&k| bvh.nodes[kids[k]].count == 0)
            .max_by(|&a, &b| area(kids[a]).total_cmp(&area(kids[b])))
        else {
            break;
        };
        let inner = kids.swap_remove(open);
        let first = bvh.nodes[inner].index as usize;
        kids.extend([first, first + 1]);
    }
    for (lane, &k) in kids.iter().enumerate() {
        let child = bvh.nodes[k];
        let (index, count) = if child.count > 0 { (child.index, child.count) } else { (collapse(bvh, k, out), 0) };
        let n = &mut out[me];
        n.set_box(lane, Aabb::new(child.min, child.max));
        n.child[lane] = index;
        n.count[lane] = count;
    }
    me as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every box the ray enters, by brute force and through the 4-wide hierarchy, over
    /// a few thousand boxes (a tree several levels deep).
    #[test]
    fn visits_exactly_the_boxes_the_ray_enters() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let boxes: Vec<Aabb> = (0..3000)
            .map(|_| {
                let c = Vec3::new(next(), next(), next()) * 20.0 - 10.0;
                let h = Vec3::new(next(), next(), next()) * 0.6;
                Aabb::new(c - h, c + h)
            })
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        let wide = Bvh4::from_binary(&bvh);
        assert!(wide.nodes.len() < bvh.nodes.len() / 2);
        for _ in 0..200 {
            let origin = Vec3::new(next(), next(), next()) * 30.0 - 15.0;
            let dir = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
            let ray = Ray::new(origin, dir);
            let inv = dir.recip();
            let mut brute: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].hit_interval(&ray, inv, f32::INFINITY).is_some())
                .collect();
            let mut found = Vec::new();
            wide.traverse(&ray, &mut { f32::INFINITY }, |prim, _| {
                let original = order[prim as usize];
                if boxes[original as usize].hit_interval(&ray, inv, f32::INFINITY).is_some() {
                    found.push(original);
                }
                false
            });
            brute.sort();
            found.sort();
            assert_eq!(brute, found);
        }
    }
}

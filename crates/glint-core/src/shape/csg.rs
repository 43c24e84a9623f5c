//! Constructive solid geometry traced directly: each ray gathers the spans of every leaf
//! solid and combines them with the tree's set operations (Roth, "Ray Casting for
//! Modeling Solids", 1982). The solid itself is never built.
//!
//! A tree is stored flat, in post-order, in `ShapeTables::csg_nodes`: evaluating it is
//! one pass over its nodes with a stack of span lists (leaves push, operations pop two
//! and push one), with no recursion, so it runs the same on a GPU. Transforms of inner
//! nodes are folded into the leaves at compile time; every node keeps its bounds in the
//! CSG object's space, and a leaf whose box the ray misses within the searched range
//! contributes nothing (set operations act pointwise along the ray, so this is exact).

use std::cell::RefCell;

use bytemuck::NoUninit;
use glam::Vec3;

use super::span::{Span, first_crossing};
use super::{Primitive, Shape, ShapeHit, ShapeTables, Solid, SurfacePoint};
use crate::math::{Aabb, Ray, Transform};

/// What a CSG node does.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum CsgOp {
    /// A solid primitive.
    Leaf = 0,
    Union = 1,
    Intersection = 2,
    /// The left operand minus the right.
    Difference = 3,
}

impl CsgOp {
    /// Membership of the result from membership of the operands.
    #[inline]
    pub fn apply(self, a: bool, b: bool) -> bool {
        match self {
            CsgOp::Union => a || b,
            CsgOp::Intersection => a && b,
            CsgOp::Difference => a && !b,
            CsgOp::Leaf => a,
        }
    }
}

/// One node of a flattened CSG tree, 176 bytes of plain data.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct CsgNode {
    /// Leaves: the primitive's placement in the CSG object's space (all the transforms
    /// from the leaf up to, not including, the CSG root). Identity for operations.
    pub transform: Transform,
    /// Bounds of the node's solid in the CSG object's space (may be infinite).
    pub min: Vec3,
    pub op: CsgOp,
    pub max: Vec3,
    /// Leaves: the material of the surface.
    pub material: u32,
    /// Leaves: the primitive.
    pub shape: Shape,
    /// Index of the first node of this node's subtree: in post-order the subtree is
    /// `first..=self`.
    pub first: u32,
    pub _pad: u32,
}

impl CsgNode {
    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }
}

/// The most nodes one scene's CSG trees may have: a hit's `part` packs the leaf index
/// into 24 bits.
pub const MAX_CSG_NODES: usize = 1 << 24;

/// Bit of a packed part that says the surface was subtracted (its normal flips).
const FLIP: u32 = 1 << 7;

/// A leaf's own part numbers stay below this.
pub const MAX_LEAF_PART: u32 = FLIP;

/// `part` of a CSG hit: leaf index, flip bit, the leaf primitive's own part.
#[inline]
fn pack(leaf: u32, part: u32) -> u32 {
    (leaf << 8) | part
}

#[inline]
fn unpack(part: u32) -> (usize, bool, u32) {
    ((part >> 8) as usize, part & FLIP != 0, part & (FLIP - 1))
}

/// Combines two sorted lists of disjoint spans with a set operation, appending the
/// result (sorted, disjoint, no empty spans) to `out`.
///
/// A sweep over the span ends of both operands in order of `t`. All ends at one `t` are
/// taken together before membership is re-evaluated, so solids that touch (a face shared
/// by two unioned cubes) leave no zero-width gap or sliver. Each end of the result keeps
/// the surface it came from, preferring the left operand's when both meet there; ends
/// contributed by a subtracted solid get the flip bit, because that solid's outward normal
/// points into the result.
pub fn combine(op: CsgOp, a: &[Span], b: &[Span], out: &mut Vec<Span>) {
    // Shortcuts that also save work on the common cases.
    match op {
        CsgOp::Union if a.is_empty() => return out.extend_from_slice(b),
        CsgOp::Union | CsgOp::Difference if b.is_empty() => return out.extend_from_slice(a),
        CsgOp::Intersection if a.is_empty() || b.is_empty() => return,
        CsgOp::Difference if a.is_empty() => return,
        _ => {}
    }
    let end = |spans: &[Span], k: usize| if k & 1 == 0 { spans[k / 2].enter } else { spans[k / 2].exit };
    let (na, nb) = (2 * a.len(), 2 * b.len());
    let (mut ia, mut ib) = (0, 0);
    let (mut in_a, mut in_b, mut inside) = (false, false, false);
    let mut open = ShapeHit { t: 0.0, part: 0 };
    while ia < na || ib < nb {
        let ta = if ia < na { end(a, ia).t } else { f32::INFINITY };
        let tb = if ib < nb { end(b, ib).t } else { f32::INFINITY };
        let t = ta.min(tb);
        let (mut from_a, mut from_b) = (None, None);
        while ia < na && end(a, ia).t == t {
            in_a = ia & 1 == 0;
            from_a = Some(end(a, ia));
            ia += 1;
        }
        while ib < nb && end(b, ib).t == t {
            in_b = ib & 1 == 0;
            from_b = Some(end(b, ib));
            ib += 1;
        }
        if from_a.is_none() && from_b.is_none() {
            // Only infinite ends remain (t = +∞ on both sides): nothing more to do.
            break;
        }
        let now = op.apply(in_a, in_b);
        if now == inside {
            continue;
        }
        inside = now;
        let surface = match (from_a, from_b) {
            (Some(hit), _) => hit,
            (None, Some(mut hit)) => {
                if op == CsgOp::Difference {
                    hit.part ^= FLIP;
                }
                hit
            }
            (None, None) => continue,
        };
        if now {
            open = surface;
        } else if open.t < surface.t {
            out.push(Span { enter: open, exit: surface });
        }
    }
}

/// Per-thread buffers for evaluating trees, so a ray allocates nothing once warm.
#[derive(Default)]
struct Scratch {
    /// The span lists of the evaluation stack, back to back.
    spans: Vec<Span>,
    /// Where each list on the stack starts and how long it is.
    stack: Vec<(usize, usize)>,
    /// Output of one set operation before it replaces its operands.
    result: Vec<Span>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// A CSG tree (its root node) with the tables its leaves refer to, ready to intersect.
#[derive(Clone, Copy, Debug)]
pub struct CsgShape<'a> {
    pub root: u32,
    pub tables: &'a ShapeTables,
}

impl CsgShape<'_> {
    fn nodes(&self) -> &[CsgNode] {
        &self.tables.csg_nodes
    }

    /// The spans of the tree along `ray`, exact within `(t_lo, t_hi)` (leaves that cannot
    /// reach that range are skipped), appended to `out`.
    fn evaluate(&self, ray: &Ray, t_lo: f32, t_hi: f32, out: &mut Vec<Span>) {
        let nodes = self.nodes();
        let root = self.root as usize;
        let inv_dir = ray.dir.recip();
        SCRATCH.with_borrow_mut(|scratch| {
            let Scratch { spans, stack, result } = scratch;
            spans.clear();
            stack.clear();
            let first = nodes[root].first as usize;
            for (index, node) in nodes.iter().enumerate().take(root + 1).skip(first) {
                if node.op == CsgOp::Leaf {
                    let start = spans.len();
                    if reaches(&node.bounds(), ray, inv_dir, t_lo, t_hi) {
                        let local = node.transform.ray_to_object(ray);
                        node.shape.spans_with(self.tables, &local, spans);
                        for s in &mut spans[start..] {
                            s.enter.part = pack(index as u32, s.enter.part);
                            s.exit.part = pack(index as u32, s.exit.part);
                        }
                    }
                    stack.push((start, spans.len() - start));
                    continue;
                }
                // Operands are adjacent: the left list directly before the right one.
                let (Some((b_start, b_len)), Some((a_start, a_len))) = (stack.pop(), stack.pop()) else {
                    debug_assert!(false, "malformed CSG program");
                    return;
                };
                result.clear();
                combine(node.op, &spans[a_start..a_start + a_len], &spans[b_start..b_start + b_len], result);
                spans.truncate(a_start);
                spans.extend_from_slice(result);
                stack.push((a_start, result.len()));
            }
            if let Some(&(start, len)) = stack.last() {
                out.extend_from_slice(&spans[start..start + len]);
            }
        });
    }

    /// The leaf a hit came from.
    fn leaf(&self, hit: ShapeHit) -> (&CsgNode, bool, ShapeHit) {
        let (leaf, flip, part) = unpack(hit.part);
        (&self.nodes()[leaf], flip, ShapeHit { t: hit.t, part })
    }

    /// The material of the leaf surface a hit is on.
    pub fn material(&self, hit: ShapeHit) -> u32 {
        self.leaf(hit).0.material
    }
}

/// Whether the ray is inside `bounds` somewhere in `(t_lo, t_hi)`.
#[inline]
fn reaches(bounds: &Aabb, ray: &Ray, inv_dir: Vec3, t_lo: f32, t_hi: f32) -> bool {
    if !bounds.is_finite() {
        return !bounds.is_empty();
    }
    let t0 = (bounds.min - ray.origin) * inv_dir;
    let t1 = (bounds.max - ray.origin) * inv_dir;
    let near = t0.min(t1).max_element().max(t_lo);
    let far = t0.max(t1).min_element().min(t_hi);
    near <= far
}

impl Primitive for CsgShape<'_> {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        // One thread-local list for the result too: intersect runs once per ray and
        // instance, and must not allocate.
        thread_local! {
            static RESULT: RefCell<Vec<Span>> = const { RefCell::new(Vec::new()) };
        }
        RESULT.with_borrow_mut(|spans| {
            spans.clear();
            self.evaluate(ray, 0.0, t_max, spans);
            first_crossing(spans, t_max)
        })
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let (node, flip, leaf_hit) = self.leaf(hit);
        let local = node.transform.ray_to_object(ray);
        let s = node.shape.surface_with(self.tables, &local, leaf_hit);
        let normal = node.transform.normal_to_world(s.normal);
        SurfacePoint {
            point: node.transform.point_to_world(s.point),
            normal: if flip { -normal } else { normal },
            uv: s.uv,
        }
    }

    fn bounds(&self) -> Aabb {
        self.nodes()[self.root as usize].bounds()
    }
}

impl Solid for CsgShape<'_> {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        self.evaluate(ray, f32::NEG_INFINITY, f32::INFINITY, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spans(list: &[(f32, f32)], part: u32) -> Vec<Span> {
        list.iter().map(|&(a, b)| Span::new(a, part, b, part)).collect()
    }

    fn run(op: CsgOp, a: &[(f32, f32)], b: &[(f32, f32)]) -> Vec<(f32, f32, u32, u32)> {
        let mut out = Vec::new();
        combine(op, &spans(a, 1), &spans(b, 2), &mut out);
        out.iter().map(|s| (s.enter.t, s.exit.t, s.enter.part, s.exit.part)).collect()
    }

    #[test]
    fn set_operations_on_overlapping_spans() {
        let a = [(0.0, 4.0), (6.0, 8.0)];
        let b = [(2.0, 7.0)];
        assert_eq!(run(CsgOp::Union, &a, &b), [(0.0, 8.0, 1, 1)]);
        assert_eq!(run(CsgOp::Intersection, &a, &b), [(2.0, 4.0, 2, 1), (6.0, 7.0, 1, 2)]);
        // Subtracted ends carry the flip bit.
        assert_eq!(run(CsgOp::Difference, &a, &b), [(0.0, 2.0, 1, 2 | FLIP), (7.0, 8.0, 2 | FLIP, 1)]);
        assert_eq!(run(CsgOp::Difference, &b, &a), [(4.0, 6.0, 2 | FLIP, 2 | FLIP)]);
    }

    #[test]
    fn touching_solids_leave_no_gap_and_no_sliver() {
        // Two cubes sharing a face: one span, not two.
        assert_eq!(run(CsgOp::Union, &[(0.0, 1.0)], &[(1.0, 2.0)]), [(0.0, 2.0, 1, 2)]);
        // Their intersection is empty, not a zero-width span.
        assert!(run(CsgOp::Intersection, &[(0.0, 1.0)], &[(1.0, 2.0)]).is_empty());
        // Subtracting an identical solid leaves nothing.
        assert!(run(CsgOp::Difference, &[(0.0, 1.0)], &[(0.0, 1.0)]).is_empty());
    }

    #[test]
    fn infinite_spans_combine() {
        let inf = f32::INFINITY;
        let half_space = [(-inf, 3.0)];
        assert_eq!(run(CsgOp::Intersection, &[(1.0, 5.0)], &half_space), [(1.0, 3.0, 1, 2)]);
        assert_eq!(run(CsgOp::Union, &[(1.0, 5.0)], &half_space), [(-inf, 5.0, 2, 1)]);
        assert_eq!(run(CsgOp::Difference, &[(-inf, inf)], &[(1.0, 2.0)]).len(), 2);
    }
}

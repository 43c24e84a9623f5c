//! Compiling [`SolidDesc`] nodes into the flat records of [`ShapeTables`]: CSG trees in
//! post-order, blob components, implicit bytecode, quadrics and superellipsoids, each
//! validated with an error that names the node.

use glam::Vec3;

use super::{CompileError, invalid, node_transform, shape_record};
use crate::desc::{BlobComponentShape, BlobDesc, ImplicitDesc, NodeDesc, NodeKind, SetOp, SolidDesc};
use crate::math::{Aabb, Transform};
use crate::shape::csg::{MAX_CSG_NODES, MAX_LEAF_PART};
use crate::shape::implicit::{compile_expression, sampled_gradient_max};
use crate::shape::superellipsoid::EXPONENT_RANGE;
use crate::shape::{
    Blob, BlobComponent, CsgNode, CsgOp, Implicit, Quadric, Shape, ShapeKind, ShapeTables, Superellipsoid,
    placed_bounds,
};

// Box faces (parts up to 6) must fit below the flip bit of a CSG hit's part.
const _: () = assert!(MAX_LEAF_PART > 6);

/// Grid points per axis at which a given Lipschitz bound is checked against `|∇f|`.
const LIPSCHITZ_SAMPLES: u32 = 16;

/// A solid node as a shape record and the material of an instance of it; `None` when
/// the solid is empty (an intersection of disjoint solids), which places nothing.
pub(super) fn compile_solid(
    solid: &SolidDesc,
    origin: &str,
    material_count: usize,
    tables: &mut ShapeTables,
) -> Result<Option<(Shape, u32)>, CompileError> {
    if let SolidDesc::Csg { op, children } = solid {
        return compile_csg(*op, children, origin, material_count, tables);
    }
    let (shape, material) = leaf_record(solid, origin, material_count, tables)?;
    Ok(Some((shape, material)))
}

/// A solid other than CSG as a record in `tables`, with its material.
fn leaf_record(
    solid: &SolidDesc,
    origin: &str,
    material_count: usize,
    tables: &mut ShapeTables,
) -> Result<(Shape, u32), CompileError> {
    let (shape, material) = match solid {
        SolidDesc::Csg { .. } => return Err(invalid(origin, "a CSG node cannot be a leaf (internal error)")),
        SolidDesc::Blob { blob, material } => (compile_blob(blob, origin, tables)?, *material),
        SolidDesc::Implicit { implicit, material } => (compile_implicit(implicit, origin, tables)?, *material),
        SolidDesc::Quadric { coefficients, bounds, material } => {
            if !coefficients.iter().all(|c| c.is_finite()) {
                return Err(invalid(origin, format!("quadric coefficients must be finite, found {coefficients:?}")));
            }
            if coefficients[..9].iter().all(|&c| c == 0.0) {
                return Err(invalid(origin, "a quadric needs a non-zero coefficient among A…I; J alone is no surface"));
            }
            let (min, max) = match bounds {
                Some(b) => checked_box(*b, origin, "quadric bounds")?,
                None => (Vec3::NEG_INFINITY, Vec3::INFINITY),
            };
            tables.quadrics.push(Quadric { coefficients: *coefficients, min, max });
            (Shape::indexed(ShapeKind::Quadric, tables.quadrics.len() as u32 - 1), *material)
        }
        SolidDesc::Superellipsoid { e1, e2, material } => {
            let (lo, hi) = EXPONENT_RANGE;
            if !((lo..=hi).contains(e1) && (lo..=hi).contains(e2)) {
                return Err(invalid(
                    origin,
                    format!("superellipsoid exponents [{e1} {e2}] must each be from {lo} to {hi}"),
                ));
            }
            tables.superellipsoids.push(Superellipsoid { e1: *e1, e2: *e2 });
            (Shape::indexed(ShapeKind::Superellipsoid, tables.superellipsoids.len() as u32 - 1), *material)
        }
    };
    if material >= material_count {
        return Err(invalid(origin, format!("material index {material} out of range")));
    }
    Ok((shape, material as u32))
}

/// A box `[min, max]` with finite corners and `min < max` on every axis.
fn checked_box([min, max]: [Vec3; 2], origin: &str, what: &str) -> Result<(Vec3, Vec3), CompileError> {
    if !(min.is_finite() && max.is_finite() && min.cmplt(max).all()) {
        return Err(invalid(origin, format!("{what} {min} {max} must be finite with min < max on every axis")));
    }
    Ok((min, max))
}

fn compile_blob(blob: &BlobDesc, origin: &str, tables: &mut ShapeTables) -> Result<Shape, CompileError> {
    if !(blob.threshold > 0.0 && blob.threshold.is_finite()) {
        return Err(invalid(origin, format!("blob threshold {} must be greater than 0", blob.threshold)));
    }
    if !blob.components.iter().any(|c| c.strength > 0.0) {
        return Err(invalid(origin, "a blob needs at least one component with positive strength"));
    }
    let first = tables.blob_components.len();
    let mut bounds = Aabb::EMPTY;
    for (i, c) in blob.components.iter().enumerate() {
        let which = format!("blob component {}", i + 1);
        if !(c.strength.is_finite() && c.strength != 0.0) {
            return Err(invalid(origin, format!("{which}: strength {} must be finite and not 0", c.strength)));
        }
        let placement = node_transform(&c.transform, origin)?;
        let (local, half_length) = match c.shape {
            BlobComponentShape::Sphere { center, radius } => {
                check_radius(radius, center.is_finite(), origin, &which)?;
                (Transform::translate(center).scaled_first(radius), 0.0)
            }
            BlobComponentShape::Cylinder { from, to, radius } => {
                check_radius(radius, from.is_finite() && to.is_finite(), origin, &which)?;
                let axis = to - from;
                let rotation = rotate_y_onto(axis);
                let middle = Transform::translate(0.5 * (from + to));
                (rotation.then(&middle).scaled_first(radius), 0.5 * axis.length() / radius)
            }
        };
        let blob_from_component = local.then(&placement).world_from_object;
        if !(blob_from_component.is_finite() && blob_from_component.determinant().abs() > 0.0) {
            return Err(invalid(origin, format!("{which}: its transform is degenerate")));
        }
        let component = BlobComponent::new(blob_from_component, c.strength, half_length);
        if c.strength > 0.0 {
            bounds = bounds.union(component.support_bounds());
        }
        tables.blob_components.push(component);
    }
    tables.blobs.push(Blob {
        min: bounds.min,
        first: first as u32,
        max: bounds.max,
        count: blob.components.len() as u32,
        threshold: blob.threshold,
    });
    Ok(Shape::indexed(ShapeKind::Blob, tables.blobs.len() as u32 - 1))
}

fn check_radius(radius: f32, finite: bool, origin: &str, which: &str) -> Result<(), CompileError> {
    if !(finite && radius > 0.0 && radius.is_finite()) {
        return Err(invalid(origin, format!("{which}: radius {radius} must be greater than 0 and positions finite")));
    }
    Ok(())
}

/// A rotation taking +y onto the direction of `axis` (identity for a zero axis).
fn rotate_y_onto(axis: Vec3) -> Transform {
    let Some(dir) = axis.try_normalize() else { return Transform::IDENTITY };
    let cross = Vec3::Y.cross(dir);
    let angle = Vec3::Y.dot(dir).clamp(-1.0, 1.0).acos().to_degrees();
    let pivot = if cross.length_squared() > 1e-12 { cross } else { Vec3::X };
    Transform::rotate(pivot, angle).unwrap_or(Transform::IDENTITY)
}

/// Uniform scaling applied before a transform.
trait ScaledFirst {
    fn scaled_first(&self, s: f32) -> Transform;
}

impl ScaledFirst for Transform {
    fn scaled_first(&self, s: f32) -> Transform {
        Transform::scale(Vec3::splat(s)).map_or(*self, |scale| scale.then(self))
    }
}

fn compile_implicit(implicit: &ImplicitDesc, origin: &str, tables: &mut ShapeTables) -> Result<Shape, CompileError> {
    let code = compile_expression(&implicit.function)
        .map_err(|e| invalid(origin, format!("implicit function \"{}\": {e}", implicit.function)))?;
    let (min, max) = checked_box(implicit.bounds, origin, "implicit bounds")?;
    let lipschitz = match implicit.lipschitz {
        None => 0.0,
        Some(l) if l > 0.0 && l.is_finite() => {
            // A bound below the real slope would let the solver skip roots: check it.
            let (steepest, at) = sampled_gradient_max(&code, min, max, LIPSCHITZ_SAMPLES);
            if steepest > l as f64 * (1.0 + 1e-4) {
                return Err(invalid(
                    origin,
                    format!(
                        "lipschitz {l} is too small: |∇f| reaches {steepest:.4} at ({:.3}, {:.3}, {:.3}); \
                         raise it or leave it out",
                        at.x, at.y, at.z
                    ),
                ));
            }
            l
        }
        Some(l) => return Err(invalid(origin, format!("lipschitz {l} must be greater than 0"))),
    };
    let first = tables.implicit_code.len() as u32;
    tables.implicit_code.extend_from_slice(&code);
    tables.implicits.push(Implicit { min, first, max, len: code.len() as u32, lipschitz });
    Ok(Shape::indexed(ShapeKind::Implicit, tables.implicits.len() as u32 - 1))
}

/// What CSG compilation threads through the tree.
struct CsgBuild<'a> {
    material_count: usize,
    tables: &'a mut ShapeTables,
}

fn compile_csg(
    op: SetOp,
    children: &[NodeDesc],
    origin: &str,
    material_count: usize,
    tables: &mut ShapeTables,
) -> Result<Option<(Shape, u32)>, CompileError> {
    let start = tables.csg_nodes.len();
    let mut build = CsgBuild { material_count, tables };
    let root = build.operation(op, children, &Transform::IDENTITY, origin)?;
    let nodes = &build.tables.csg_nodes;
    if nodes.len() > MAX_CSG_NODES {
        return Err(invalid(origin, format!("the scene's CSG trees have more than {MAX_CSG_NODES} nodes")));
    }
    if nodes[root as usize].bounds().is_empty() {
        // An intersection of solids that do not overlap: nothing to place.
        build.tables.csg_nodes.truncate(start);
        return Ok(None);
    }
    let material = nodes[start..].iter().find(|n| n.op == CsgOp::Leaf).map_or(0, |n| n.material);
    Ok(Some((Shape::indexed(ShapeKind::Csg, root), material)))
}

impl CsgBuild<'_> {
    fn push(&mut self, node: CsgNode) -> u32 {
        self.tables.csg_nodes.push(node);
        self.tables.csg_nodes.len() as u32 - 1
    }

    /// Emits `op` over `children`, folded left into binary nodes, in post-order; returns
    /// the index of its root.
    fn operation(
        &mut self,
        op: SetOp,
        children: &[NodeDesc],
        parent: &Transform,
        origin: &str,
    ) -> Result<u32, CompileError> {
        let name = match op {
            SetOp::Union => "union",
            SetOp::Intersection => "intersection",
            SetOp::Difference => "difference",
        };
        let Some((first, rest)) = children.split_first() else {
            return Err(invalid(origin, format!("{name} has no children; it needs at least one solid")));
        };
        let op = match op {
            SetOp::Union => CsgOp::Union,
            SetOp::Intersection => CsgOp::Intersection,
            SetOp::Difference => CsgOp::Difference,
        };
        let mut left = self.child(first, parent)?;
        for child in rest {
            let right = self.child(child, parent)?;
            let nodes = &self.tables.csg_nodes;
            let (a, b) = (nodes[left as usize], nodes[right as usize]);
            let bounds = match op {
                CsgOp::Union => a.bounds().union(b.bounds()),
                CsgOp::Intersection => Aabb::new(a.min.max(b.min), a.max.min(b.max)),
                _ => a.bounds(),
            };
            let bounds = if bounds.is_empty() { Aabb::EMPTY } else { bounds };
            left = self.push(CsgNode {
                transform: Transform::IDENTITY,
                min: bounds.min,
                op,
                max: bounds.max,
                material: 0,
                shape: Shape::new(ShapeKind::Sphere),
                first: a.first,
                _pad: 0,
            });
        }
        Ok(left)
    }

    /// Emits one child (a leaf, a nested operation, or a group as a union).
    fn child(&mut self, node: &NodeDesc, parent: &Transform) -> Result<u32, CompileError> {
        let origin = node.origin.as_str();
        let transform = node_transform(&node.transform, origin)?.then(parent);
        if !(transform.world_from_object.is_finite() && transform.object_from_world.is_finite()) {
            return Err(invalid(origin, "the accumulated transform overflows"));
        }
        let (shape, material) = match &node.kind {
            NodeKind::Group(children) => {
                if children.is_empty() {
                    return Err(invalid(origin, "an empty group inside CSG has no solid to combine"));
                }
                return self.operation(SetOp::Union, children, &transform, origin);
            }
            NodeKind::Solid(SolidDesc::Csg { op, children }) => {
                return self.operation(*op, children, &transform, origin);
            }
            NodeKind::Solid(solid) => leaf_record(solid, origin, self.material_count, self.tables)?,
            NodeKind::Moving { .. } => {
                return Err(invalid(origin, "a CSG solid cannot have moving parts; move the whole solid instead"));
            }
            NodeKind::Shape { shape, material } => {
                let record = shape_record(shape, origin)?;
                if !record.is_solid() {
                    let message = if record.kind == ShapeKind::Disk {
                        "a disk has no inside, so it cannot be part of a CSG solid; use a thin cylinder \
                         (a plane works: inside CSG it is the half-space below it)"
                    } else {
                        "a mesh cannot be part of a CSG solid; use the analytic solids"
                    };
                    return Err(invalid(origin, message));
                }
                if *material >= self.material_count {
                    return Err(invalid(origin, format!("material index {material} out of range")));
                }
                (record, *material as u32)
            }
        };
        let bounds = placed_bounds(shape.bounds_with(self.tables), &transform.world_from_object);
        let index = self.tables.csg_nodes.len() as u32;
        Ok(self.push(CsgNode {
            transform,
            min: bounds.min,
            op: CsgOp::Leaf,
            max: bounds.max,
            material,
            shape,
            first: index,
            _pad: 0,
        }))
    }
}

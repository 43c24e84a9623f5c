//! The side tables of shapes whose data does not fit in a [`Shape`] record, and the
//! dispatch that reads them.
//!
//! A CSG tree, a blob's components, an implicit function's bytecode, a quadric's ten
//! coefficients: each lives in one flat array of plain records (uploadable to a GPU as
//! is), and the [`Shape`] record holds the index. `Shape::*_with` is [`Primitive`] with
//! the tables at hand; it handles every kind except meshes, which the scene routes itself.

use glam::{Vec2, Vec3};

use super::{
    Blob, BlobComponent, BlobShape, CsgNode, CsgShape, Implicit, ImplicitOp, ImplicitShape, Primitive, Quadric, Shape,
    ShapeHit, ShapeKind, Solid, Span, Superellipsoid, SurfacePoint,
};
use crate::math::{Aabb, Ray};

/// Flat arrays that indexed shapes point into.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShapeTables {
    /// Every CSG tree, each in post-order (see [`super::csg`]).
    pub csg_nodes: Vec<CsgNode>,
    pub blobs: Vec<Blob>,
    /// The components of all blobs, each blob's run contiguous.
    pub blob_components: Vec<BlobComponent>,
    pub implicits: Vec<Implicit>,
    /// The programs of all implicit surfaces, each contiguous.
    pub implicit_code: Vec<ImplicitOp>,
    pub quadrics: Vec<Quadric>,
    pub superellipsoids: Vec<Superellipsoid>,
}

/// What an indexed [`Shape`] can say without its tables: nothing. Keeps
/// `Primitive for Shape` total; the scene calls the `_with` methods instead.
pub struct NeedsTables;

impl Primitive for NeedsTables {
    fn intersect(&self, _ray: &Ray, _t_max: f32) -> Option<ShapeHit> {
        None
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        SurfacePoint { point: ray.at(hit.t), normal: -ray.dir, uv: Vec2::ZERO }
    }

    fn bounds(&self) -> Aabb {
        Aabb::EMPTY
    }
}

impl ShapeTables {
    pub fn csg(&self, root: u32) -> CsgShape<'_> {
        CsgShape { root, tables: self }
    }

    pub fn blob(&self, index: u32) -> BlobShape<'_> {
        let blob = &self.blobs[index as usize];
        let components = &self.blob_components[blob.first as usize..(blob.first + blob.count) as usize];
        BlobShape { blob, components }
    }

    pub fn implicit(&self, index: u32) -> ImplicitShape<'_> {
        let record = &self.implicits[index as usize];
        let code = &self.implicit_code[record.first as usize..(record.first + record.len) as usize];
        ImplicitShape { record, code }
    }
}

/// Runs `$body` with `$prim` bound to the primitive an indexed shape resolves to, or
/// evaluates `$otherwise` for the self-contained kinds.
macro_rules! with_tables {
    ($shape:expr, $tables:expr, $prim:ident => $body:expr, $otherwise:expr) => {
        match $shape.kind {
            ShapeKind::Csg => {
                let $prim = $tables.csg($shape.index());
                $body
            }
            ShapeKind::Blob => {
                let $prim = $tables.blob($shape.index());
                $body
            }
            ShapeKind::Implicit => {
                let $prim = $tables.implicit($shape.index());
                $body
            }
            ShapeKind::Quadric => {
                let $prim = $tables.quadrics[$shape.index() as usize];
                $body
            }
            ShapeKind::Superellipsoid => {
                let $prim = $tables.superellipsoids[$shape.index() as usize];
                $body
            }
            _ => $otherwise,
        }
    };
}

impl Shape {
    /// [`Primitive::intersect`] for every kind but meshes.
    #[inline]
    pub fn intersect_with(&self, tables: &ShapeTables, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        with_tables!(self, tables, p => p.intersect(ray, t_max), self.intersect(ray, t_max))
    }

    /// [`Primitive::surface`] for every kind but meshes.
    pub fn surface_with(&self, tables: &ShapeTables, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        with_tables!(self, tables, p => p.surface(ray, hit), self.surface(ray, hit))
    }

    /// [`Primitive::bounds`] for every kind but meshes.
    pub fn bounds_with(&self, tables: &ShapeTables) -> Aabb {
        with_tables!(self, tables, p => p.bounds(), self.bounds())
    }

    /// The material a hit's surface has when it differs from the instance's: a CSG
    /// surface keeps the material of the leaf it came from.
    pub fn hit_material(&self, tables: &ShapeTables, hit: ShapeHit) -> Option<u32> {
        (self.kind == ShapeKind::Csg).then(|| tables.csg(self.index()).material(hit))
    }

    /// Whether the kind has an inside and can be part of a CSG tree (a plane counts, as
    /// its lower half-space).
    pub fn is_solid(&self) -> bool {
        !matches!(self.kind, ShapeKind::Disk | ShapeKind::Rectangle | ShapeKind::Mesh)
    }

    /// [`Solid::spans`] for every solid kind (see [`Shape::is_solid`]); other kinds add
    /// nothing.
    pub fn spans_with(&self, tables: &ShapeTables, ray: &Ray, out: &mut Vec<Span>) {
        use super::{Cone, Cube, Cylinder, Plane, Sphere, Torus};
        with_tables!(self, tables, p => p.spans(ray, out), match self.kind {
            ShapeKind::Sphere => Sphere.spans(ray, out),
            ShapeKind::Cube => Cube.spans(ray, out),
            ShapeKind::Cylinder => Cylinder.spans(ray, out),
            ShapeKind::Cone => Cone.spans(ray, out),
            ShapeKind::Plane => Plane.spans(ray, out),
            ShapeKind::Torus => Torus { minor_radius: self.param }.spans(ray, out),
            _ => debug_assert!(!self.is_solid(), "{:?} has no spans", self.kind),
        })
    }
}

/// The bounds of a shape in its parent's space after `world_from_object`, infinite in
/// every direction when the shape is unbounded.
pub fn placed_bounds(bounds: Aabb, world_from_object: &glam::Mat4) -> Aabb {
    if bounds.is_empty() {
        return bounds;
    }
    if !bounds.is_finite() {
        return Aabb::new(Vec3::NEG_INFINITY, Vec3::INFINITY);
    }
    bounds.transformed(world_from_object)
}

//! The canonical primitives, each intersected in its own object space.
//!
//! Every primitive answers the same three questions ([`Primitive`]): where does a ray
//! first meet me (`t`, in object space — the caller has already applied `M⁻¹`), what is
//! the surface there (refined point, gradient normal, uv), and what box bounds me.
//! [`Shape`] is the closed set of them as plain data, dispatched by `match` so the same
//! record serves the CPU and, uploaded as is, the GPU.

pub mod blob;
mod cone;
pub mod csg;
mod cube;
mod cylinder;
mod disk;
pub mod implicit;
mod plane;
pub mod quadric;
mod rectangle;
mod span;
mod sphere;
pub mod superellipsoid;
mod tables;
mod torus;

pub use cone::Cone;
pub use cube::Cube;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use plane::Plane;
pub use rectangle::Rectangle;
pub use sphere::Sphere;
pub use torus::Torus;

pub use blob::{Blob, BlobComponent, BlobShape};
pub use csg::{CsgNode, CsgOp, CsgShape};
pub use implicit::{Implicit, ImplicitOp, ImplicitShape};
pub use quadric::Quadric;
pub use span::{Solid, Span, first_crossing};
pub use superellipsoid::Superellipsoid;
pub use tables::{ShapeTables, placed_bounds};

use bytemuck::NoUninit;
use glam::{Vec2, Vec3};

use crate::math::{Aabb, Ray};

/// Where a ray first meets a primitive: the ray parameter and which part of the
/// surface (a cube face, a cylinder cap, …) so the surface data can be derived later,
/// only for the closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    pub t: f32,
    pub part: u32,
}

/// Surface data at a hit, in object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The hit point moved exactly onto the surface (removes the error in `t`).
    pub point: Vec3,
    /// `∇f` at the point, pointing out of the solid; not normalized.
    pub normal: Vec3,
    /// Texture coordinates; [0, 1]² for bounded surfaces, unbounded on the plane.
    pub uv: Vec2,
}

/// The interface every primitive implements.
pub trait Primitive {
    /// The smallest `t` in `(0, t_max)` where `ray` (object space, direction not
    /// normalized) meets the surface.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit>;
    /// Surface data at a hit returned by [`Primitive::intersect`] for the same ray.
    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint;
    /// [`Primitive::surface`]'s point and normal alone, for surfaces shaded without a
    /// texture: a round shape's uv costs calls to `atan2` and `asin` that the compiler
    /// cannot drop when they go unused.
    #[inline(always)]
    fn point_and_normal(&self, ray: &Ray, hit: ShapeHit) -> (Vec3, Vec3) {
        let surface = self.surface(ray, hit);
        (surface.point, surface.normal)
    }
    /// Object-space bounds; infinite for unbounded surfaces.
    fn bounds(&self) -> Aabb;
}

/// Which primitive a [`Shape`] record is.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum ShapeKind {
    Sphere = 0,
    Cube = 1,
    Cylinder = 2,
    Cone = 3,
    Plane = 4,
    Disk = 5,
    Torus = 6,
    /// A triangle mesh of [`crate::scene::RenderScene::meshes`]; `param` holds its index.
    Mesh = 7,
    /// The kinds below keep their data in [`ShapeTables`]; `param`'s bits hold the index
    /// (see [`Shape::indexed`]). A CSG tree, by the index of its root node.
    Csg = 8,
    Blob = 9,
    Implicit = 10,
    Quadric = 11,
    Superellipsoid = 12,
    /// The square of [`Rectangle`].
    Rectangle = 13,
}

/// A primitive as flat data: its kind and its one shape parameter (the torus's tube
/// radius; unused by the others).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Shape {
    pub kind: ShapeKind,
    pub param: f32,
}

impl Shape {
    pub const fn new(kind: ShapeKind) -> Self {
        Self { kind, param: 0.0 }
    }

    pub const fn torus(minor_radius: f32) -> Self {
        Self { kind: ShapeKind::Torus, param: minor_radius }
    }

    /// An instance of mesh `index`; the index travels in `param`'s bits so the record
    /// stays two words for every kind.
    pub const fn mesh(index: u32) -> Self {
        Self { kind: ShapeKind::Mesh, param: f32::from_bits(index) }
    }

    /// The mesh index of a [`ShapeKind::Mesh`] record.
    pub const fn mesh_index(&self) -> u32 {
        self.param.to_bits()
    }

    /// A record of a kind whose data lives in [`ShapeTables`], at `index` of its table.
    pub const fn indexed(kind: ShapeKind, index: u32) -> Self {
        Self { kind, param: f32::from_bits(index) }
    }

    /// The table index of a record made by [`Shape::indexed`].
    pub const fn index(&self) -> u32 {
        self.param.to_bits()
    }
}

macro_rules! dispatch {
    ($shape:expr, $prim:ident => $body:expr) => {
        match $shape.kind {
            ShapeKind::Sphere => {
                let $prim = Sphere;
                $body
            }
            ShapeKind::Cube => {
                let $prim = Cube;
                $body
            }
            ShapeKind::Cylinder => {
                let $prim = Cylinder;
                $body
            }
            ShapeKind::Cone => {
                let $prim = Cone;
                $body
            }
            ShapeKind::Plane => {
                let $prim = Plane;
                $body
            }
            ShapeKind::Disk => {
                let $prim = Disk;
                $body
            }
            ShapeKind::Rectangle => {
                let $prim = Rectangle;
                $body
            }
            ShapeKind::Torus => {
                let $prim = Torus { minor_radius: $shape.param };
                $body
            }
            ShapeKind::Mesh => {
                let $prim = crate::mesh::MeshRef;
                $body
            }
            ShapeKind::Csg | ShapeKind::Blob | ShapeKind::Implicit | ShapeKind::Quadric | ShapeKind::Superellipsoid => {
                let $prim = tables::NeedsTables;
                $body
            }
        }
    };
}

impl Primitive for Shape {
    #[inline]
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        dispatch!(self, p => p.intersect(ray, t_max))
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        dispatch!(self, p => p.surface(ray, hit))
    }

    fn bounds(&self) -> Aabb {
        dispatch!(self, p => p.bounds())
    }
}

/// The nearer of two candidate roots that lies in `(0, t_max)` and passes `accept`.
#[inline]
pub(crate) fn nearest_root(roots: [f32; 2], t_max: f32, mut accept: impl FnMut(f32) -> bool) -> Option<f32> {
    roots.into_iter().find(|&t| t > 0.0 && t < t_max && accept(t))
}

/// Moves the ray origin to the point of the line closest to the object-space origin
/// and returns the parameter shift. Solving the quadric from there keeps the constant
/// term small, which removes the catastrophic cancellation a distant origin causes
/// (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing
/// Gems ch. 7, generalized to any shape centred at the origin).
#[inline]
pub(crate) fn rebase(ray: &Ray) -> (f32, Ray) {
    let t0 = -ray.origin.dot(ray.dir) / ray.dir.length_squared();
    (t0, Ray { origin: ray.at(t0), ..*ray })
}

/// Longitude of a point around the y axis mapped to [0, 1).
#[inline]
pub(crate) fn azimuth_u(p: Vec3) -> f32 {
    let theta = p.z.atan2(p.x);
    let u = -theta / std::f32::consts::TAU;
    if u < 0.0 { u + 1.0 } else { u }
}

/// uv on a disk of radius 1 in a plane y = const, seen from `facing_up`'s side.
#[inline]
pub(crate) fn disk_uv(p: Vec3, facing_up: bool) -> Vec2 {
    let v = if facing_up { 0.5 - 0.5 * p.z } else { 0.5 + 0.5 * p.z };
    Vec2::new(0.5 + 0.5 * p.x, v)
}

#[cfg(test)]
mod tests;

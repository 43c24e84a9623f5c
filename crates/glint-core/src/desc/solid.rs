//! Scene description of the solids beyond the canonical primitives: CSG trees, blobby
//! objects, implicit surfaces, quadrics and superellipsoids (all one [`NodeKind::Solid`]
//! node kind, so code that walks shapes and groups needs one more arm, not five).

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::{NodeDesc, NodeKind, TransformOp};

/// A solid node. Each variant except `Csg` carries the index of its material in
/// [`super::SceneDesc::materials`]; a CSG's surfaces keep the materials of the leaves
/// they come from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum SolidDesc {
    /// The children combined by a set operation, traced directly (no surface is built).
    /// Children are solids: shapes other than `Disk` and `Mesh` (a `Plane` is the
    /// half-space y ≤ 0 below it), other CSG nodes, blobs, implicit surfaces, quadrics,
    /// superellipsoids, and groups (a group is the union of its children). `Union` and
    /// `Intersection` combine all children; `Difference` subtracts every later child from
    /// the first.
    Csg { op: SetOp, children: Vec<NodeDesc> },
    /// A blobby object: the surface where the summed fields equal `threshold`.
    Blob { blob: BlobDesc, material: usize },
    /// The surface `f(x, y, z) = 0` of an expression, inside a box.
    Implicit { implicit: ImplicitDesc, material: usize },
    /// `A x² + B y² + C z² + D xy + E xz + F yz + G x + H y + I z + J ≤ 0` (POV-Ray's
    /// coefficient order), clipped to `bounds` (min, max) when given; unbounded otherwise.
    Quadric { coefficients: [f32; 10], bounds: Option<[Vec3; 2]>, material: usize },
    /// Barr's superellipsoid in the cube [−1, 1]³ with the y axis as its pole: `e1`
    /// shapes it from pole to pole, `e2` around the pole; 1, 1 is the unit sphere.
    Superellipsoid { e1: f32, e2: f32, material: usize },
}

/// A CSG set operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SetOp {
    Union,
    Intersection,
    /// The first child minus all the others.
    Difference,
}

/// A blobby object (metaballs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BlobDesc {
    /// The surface level; must be > 0 (far from every component the field is 0).
    pub threshold: f32,
    pub components: Vec<BlobComponentDesc>,
}

/// One field source: `strength·(1 − (r/radius)²)²` within `radius` of its centre (or
/// axis segment), zero beyond; then placed by `transform` (in the blob's space), so a
/// non-uniform scale makes an ellipsoid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BlobComponentDesc {
    pub shape: BlobComponentShape,
    /// May be negative to carve; must not be 0.
    pub strength: f32,
    pub transform: Vec<TransformOp>,
}

/// The support of a blob component before its transform.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum BlobComponentShape {
    /// A ball.
    Sphere { center: Vec3, radius: f32 },
    /// A capsule: the points within `radius` of the segment `from`–`to` (a cylinder with
    /// hemispherical ends, as in POV-Ray).
    Cylinder { from: Vec3, to: Vec3, radius: f32 },
}

/// An implicit surface.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ImplicitDesc {
    /// `f(x, y, z)` in the expression language of `docs/scene-format.md`; the solid is
    /// where it is negative.
    pub function: String,
    /// The box (min, max) the surface is sought in; where `f < 0` reaches it, its face
    /// closes the solid.
    pub bounds: [Vec3; 2],
    /// A bound on `|∇f|` in the box, if known; it tightens the root finder's enclosures.
    pub lipschitz: Option<f32>,
}

impl From<SolidDesc> for NodeKind {
    fn from(solid: SolidDesc) -> Self {
        NodeKind::Solid(solid)
    }
}

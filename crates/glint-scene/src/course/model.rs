//! What a course scenefile says, in the course's own terms, before glint's meaning is
//! given to it: both the XML and the JSON reader produce this.

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::TransformOp;

use super::{Pos, Result, Source};

/// A whole scenefile.
#[derive(Clone, Debug, PartialEq)]
pub struct CourseScene {
    pub global: Global,
    pub camera: Camera,
    /// Lights given in world space (the XML format's `<lightdata>`).
    pub lights: Vec<Light>,
    /// The tree that is rendered (XML: the object named "root"; JSON: `groups`).
    pub root: Group,
    /// Reusable trees, referenced by index from [`Child::Template`]: XML top-level
    /// objects other than "root" (`master`), JSON `templateGroups`.
    pub templates: Vec<Template>,
}

/// `globaldata`/`globalData`: coefficients that multiply every material's colours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Global {
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub kt: f32,
}

/// `cameradata`/`cameraData`; `look` is already a direction (a `focus` point has had
/// the position subtracted).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub look: Vec3,
    pub up: Vec3,
    /// Full vertical angle, degrees.
    pub height_angle: f32,
    /// `aperture` and `focalLength`, when given (with where the first was written).
    pub depth_of_field: Option<(f32, f32, Pos)>,
    pub pos: Pos,
}

/// A light before placement. XML lights are in world space; JSON lights are placed by
/// the transforms of the group that holds them (`position` is then the origin).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    pub color: Vec3,
    /// `(c1, c2, c3)` of `f_att = min(1, 1/(c1 + c2·d + c3·d²))`.
    pub attenuation: Vec3,
    pub position: Vec3,
    pub direction: Vec3,
    pub pos: Pos,
}

/// The course's light types.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    Point,
    Directional,
    /// Half-angle of the cone and width of its soft edge, degrees.
    Spot {
        angle: f32,
        penumbra: f32,
    },
    /// A rectangle of `width` × `height` (the course's extra credit).
    Area {
        width: f32,
        height: f32,
    },
}

/// A node of the transform tree.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Group {
    /// glint order: the first op acts on the objects first.
    pub transform: Vec<TransformOp>,
    pub lights: Vec<Light>,
    pub primitives: Vec<Primitive>,
    pub children: Vec<Child>,
    pub pos: Pos,
}

/// What a group holds besides primitives and lights.
#[derive(Clone, Debug, PartialEq)]
pub enum Child {
    Group(Group),
    /// A use of `templates[index]`, written at `pos`.
    Template {
        index: usize,
        pos: Pos,
    },
}

/// A named reusable tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Template {
    pub name: String,
    pub group: Group,
}

/// The course's primitives, each inside the unit cube [−0.5, 0.5]³.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Cube,
    Sphere,
    Cylinder,
    Cone,
    Torus,
    /// A triangle mesh from an OBJ file (path as written).
    Mesh(String),
}

/// A primitive with its own material.
#[derive(Clone, Debug, PartialEq)]
pub struct Primitive {
    pub shape: Shape,
    pub material: Material,
    pub pos: Pos,
}

/// A course material: colours `O` that the global `k` coefficients multiply.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub ambient: Vec3,
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub reflective: Vec3,
    pub transparent: Vec3,
    /// XML only: light the surface gives off by itself.
    pub emissive: Vec3,
    pub shininess: f32,
    pub ior: f32,
    pub blend: f32,
    pub texture: Option<TextureMap>,
}

impl Default for Material {
    /// The course's defaults: a white diffuse colour and nothing else.
    fn default() -> Self {
        Self {
            ambient: Vec3::ZERO,
            diffuse: Vec3::ONE,
            specular: Vec3::ZERO,
            reflective: Vec3::ZERO,
            transparent: Vec3::ZERO,
            emissive: Vec3::ZERO,
            shininess: 0.0,
            ior: 0.0,
            blend: 0.0,
            texture: None,
        }
    }
}

/// A texture file as written, its repeats across the surface, and where it was named.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureMap {
    pub file: String,
    pub repeat: Vec2,
    pub pos: Pos,
}

/// `translate`: any finite offset.
pub fn translate(src: &Source, pos: Pos, v: Vec3) -> Result<TransformOp> {
    finite(src, pos, "translate", &v.to_array())?;
    Ok(TransformOp::Translate(v))
}

/// `scale`: non-zero factors (a zero flattens the object and has no inverse).
pub fn scale(src: &Source, pos: Pos, s: Vec3) -> Result<TransformOp> {
    finite(src, pos, "scale", &s.to_array())?;
    if !(Vec3::ONE / s).is_finite() {
        return Err(src.invalid(
            pos,
            format!("'scale' {s} has a zero component, which flattens the object and cannot be inverted; use non-zero factors"),
        ));
    }
    Ok(TransformOp::Scale(s))
}

/// `rotate`: a non-zero axis and an angle in degrees.
pub fn rotate(src: &Source, pos: Pos, axis: Vec3, degrees: f32) -> Result<TransformOp> {
    finite(src, pos, "rotate", &[axis.x, axis.y, axis.z, degrees])?;
    if axis.length_squared() == 0.0 {
        return Err(src.invalid(pos, "the 'rotate' axis is (0, 0, 0); give a non-zero axis"));
    }
    Ok(TransformOp::Rotate { axis, degrees })
}

/// `matrix`: 4 rows, an invertible affine transform.
pub fn matrix(src: &Source, pos: Pos, rows: [[f32; 4]; 4]) -> Result<TransformOp> {
    finite(src, pos, "matrix", rows.as_flattened())?;
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(src.invalid(
            pos,
            format!("the last row of 'matrix' must be 0 0 0 1 (an affine transform), found {:?}", rows[3]),
        ));
    }
    let det = Mat4::from_cols_array_2d(&rows).determinant();
    if det.abs() <= 1e-12 || det.is_nan() {
        return Err(src.invalid(pos, format!("'matrix' is singular (determinant {det}); it must be invertible")));
    }
    Ok(TransformOp::Matrix(rows))
}

fn finite(src: &Source, pos: Pos, what: &str, values: &[f32]) -> Result<()> {
    if values.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(src.invalid(pos, format!("'{what}' has a number too large for 32-bit floats")))
    }
}

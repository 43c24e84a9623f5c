//! `<transform>` properties: `translate`, `rotate`, `scale`, `matrix` and `lookat`,
//! applied in document order (each later operation acts after the earlier ones), which
//! is also the order of a glint [`TransformOp`] list.

use glam::{Mat4, Vec3, Vec4};
use glint_core::desc::TransformOp;

use super::tree::Elem;
use super::values::{numbers, vec3_attr};
use crate::error::SceneError;

/// A Mitsuba transform kept as glint operations, so a node can carry it unchanged.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Transform {
    pub ops: Vec<TransformOp>,
}

impl Transform {
    /// `world_from_object`: the product of the operations, the first one rightmost.
    pub fn matrix(&self) -> Mat4 {
        self.ops.iter().fold(Mat4::IDENTITY, |m, op| op_matrix(op) * m)
    }
}

/// The matrix of one operation.
pub(super) fn op_matrix(op: &TransformOp) -> Mat4 {
    match *op {
        TransformOp::Translate(t) => Mat4::from_translation(t),
        TransformOp::Scale(s) => Mat4::from_scale(s),
        TransformOp::Rotate { axis, degrees } => {
            Mat4::from_axis_angle(axis.normalize_or(Vec3::Y), degrees.to_radians())
        }
        TransformOp::Matrix(rows) => Mat4::from_cols_array_2d(&rows).transpose(),
    }
}

/// Reads the operations inside a `<transform>` element.
pub(super) fn parse(elem: &Elem) -> Result<Transform, SceneError> {
    let ops = elem.children.iter().map(operation).collect::<Result<_, _>>()?;
    Ok(Transform { ops })
}

fn operation(e: &Elem) -> Result<TransformOp, SceneError> {
    match e.tag.as_str() {
        "translate" => Ok(TransformOp::Translate(vector(e, 0.0)?)),
        "scale" => Ok(TransformOp::Scale(vector(e, 1.0)?)),
        "rotate" => rotate(e),
        "matrix" => matrix(e),
        "lookat" => lookat(e),
        other => Err(e.error(format!(
            "<{other}> is not a transform operation; expected translate, rotate, scale, matrix or lookat"
        ))),
    }
}

/// `value="x y z"` (one number: all three) or `x=`, `y=`, `z=` with `missing` for the
/// absent ones (0 for a translation, 1 for a scale, as Mitsuba has it).
fn vector(e: &Elem, missing: f32) -> Result<Vec3, SceneError> {
    if let Some(value) = e.attr("value") {
        return match numbers(value).map_err(|m| e.attr_error("value", m))?.as_slice() {
            [v] => Ok(Vec3::splat(*v)),
            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
            other => Err(e.attr_error("value", format!("<{}> takes 1 or 3 numbers, not {}", e.tag, other.len()))),
        };
    }
    vec3_attr(e, missing)
}

/// `axis="x y z"` or `x= y= z=`, and `angle` in degrees.
fn rotate(e: &Elem) -> Result<TransformOp, SceneError> {
    let axis = match e.attr("axis") {
        Some(a) => match numbers(a).map_err(|m| e.attr_error("axis", m))?.as_slice() {
            [x, y, z] => Vec3::new(*x, *y, *z),
            _ => return Err(e.attr_error("axis", "the rotation axis needs 3 numbers")),
        },
        None => vec3_attr(e, 0.0)?,
    };
    if axis.length_squared() == 0.0 || !axis.is_finite() {
        return Err(e.error("<rotate> needs a non-zero axis (axis=\"x y z\" or x=, y=, z=)"));
    }
    let angle = e.required("angle")?;
    let degrees = single(e, "angle", angle)?;
    Ok(TransformOp::Rotate { axis, degrees })
}

fn single(e: &Elem, attr: &str, text: &str) -> Result<f32, SceneError> {
    match numbers(text).map_err(|m| e.attr_error(attr, m))?.as_slice() {
        [v] => Ok(*v),
        _ => Err(e.attr_error(attr, format!("'{attr}' takes one number"))),
    }
}

/// 16 numbers, rows first (a 3×3 linear part as 9 numbers); the last row must be
/// (0, 0, 0, 1) because glint transforms are affine.
fn matrix(e: &Elem) -> Result<TransformOp, SceneError> {
    let v = numbers(e.required("value")?).map_err(|m| e.attr_error("value", m))?;
    let rows = match v.len() {
        16 => [
            [v[0], v[1], v[2], v[3]],
            [v[4], v[5], v[6], v[7]],
            [v[8], v[9], v[10], v[11]],
            [v[12], v[13], v[14], v[15]],
        ],
        9 => [[v[0], v[1], v[2], 0.0], [v[3], v[4], v[5], 0.0], [v[6], v[7], v[8], 0.0], [0.0, 0.0, 0.0, 1.0]],
        n => return Err(e.attr_error("value", format!("<matrix> takes 16 numbers (or 9), not {n}"))),
    };
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(e.attr_error("value", "projective matrices are not supported: the last row must be 0 0 0 1"));
    }
    Ok(TransformOp::Matrix(rows))
}

/// Mitsuba's look-at frame: local +z towards `target`, +y towards `up`, and +x =
/// up × z, which points to the image's left.
fn lookat(e: &Elem) -> Result<TransformOp, SceneError> {
    let point = |name: &str| -> Result<Vec3, SceneError> {
        match numbers(e.required(name)?).map_err(|m| e.attr_error(name, m))?.as_slice() {
            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
            _ => Err(e.attr_error(name, format!("'{name}' takes 3 numbers"))),
        }
    };
    let origin = point("origin")?;
    let target = point("target")?;
    let up = if e.attr("up").is_some() { point("up")? } else { Vec3::Y };
    let dir = (target - origin).normalize_or_zero();
    let left = up.cross(dir).normalize_or_zero();
    if dir == Vec3::ZERO || left == Vec3::ZERO {
        return Err(e.error("<lookat>: origin and target coincide, or 'up' is parallel to the view direction"));
    }
    let new_up = dir.cross(left);
    let m = Mat4::from_cols(left.extend(0.0), new_up.extend(0.0), dir.extend(0.0), Vec4::from((origin, 1.0)));
    Ok(TransformOp::Matrix(m.transpose().to_cols_array_2d()))
}

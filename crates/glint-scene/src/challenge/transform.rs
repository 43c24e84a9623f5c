//! `transform:` lists: `[translate, x, y, z]`, `[scale, …]`, `[rotate-x, rad]`,
//! `[shear, …]` and names of defined lists, applied in the order written.

use glam::{Mat3, Vec3};
use glint_core::desc::TransformOp;

use super::Reader;
use super::values::{self, Result};
use super::yaml::Yaml;

/// The operations a transform item may start with, for the "expected one of" message.
const OPERATIONS: [&str; 6] = ["translate", "scale", "rotate-x", "rotate-y", "rotate-z", "shear"];

/// Defined lists may name other defined lists; deeper nesting than this is a cycle.
const MAX_NESTING: usize = 64;

impl Reader {
    /// The operations of a `transform:` value, first-applied first (the book's order:
    /// each item acts on the result of the ones before it).
    pub(super) fn transform(&self, node: &Yaml, key: &str) -> Result<Vec<TransformOp>> {
        let mut ops = Vec::new();
        self.transform_into(node, key, &mut ops, 0)?;
        Ok(ops)
    }

    fn transform_into(&self, node: &Yaml, key: &str, ops: &mut Vec<TransformOp>, depth: usize) -> Result<()> {
        if let Some(name) = node.scalar() {
            return self.transform_reference(node, name, key, ops, depth);
        }
        for item in values::list(&self.src, node, key)? {
            match item.scalar() {
                Some(name) => self.transform_reference(item, name, key, ops, depth)?,
                None => ops.push(self.operation(item)?),
            }
        }
        Ok(())
    }

    /// A defined list named inside a transform, expanded in place.
    fn transform_reference(
        &self,
        node: &Yaml,
        name: &str,
        key: &str,
        ops: &mut Vec<TransformOp>,
        depth: usize,
    ) -> Result<()> {
        if depth >= MAX_NESTING {
            return Err(self.src.invalid(node.pos, format!("definitions nest more than {MAX_NESTING} deep")));
        }
        let define = self.define(node, name, "transform list")?;
        if define.value.seq().is_none() {
            return Err(self.src.invalid(
                node.pos,
                format!(
                    "'{name}' (defined at {}) is {}, not a list of transforms",
                    define.origin,
                    define.value.describe()
                ),
            ));
        }
        self.transform_into(&define.value, key, ops, depth + 1)
    }

    /// One `[operation, numbers…]` item.
    fn operation(&self, item: &Yaml) -> Result<TransformOp> {
        let src = &self.src;
        let shape = "a transform item must be a list like [translate, 1, 2, 3] or the name of a defined list";
        let Some(parts) = item.seq() else {
            return Err(src.invalid(item.pos, format!("{shape}, found {}", item.describe())));
        };
        let Some((head, args)) = parts.split_first() else {
            return Err(src.invalid(item.pos, format!("{shape}, found an empty list")));
        };
        let name = head.scalar().unwrap_or("");
        let count = match name {
            "translate" | "scale" => 3,
            "rotate-x" | "rotate-y" | "rotate-z" => 1,
            "shear" => 6,
            _ => {
                return Err(src.invalid(
                    head.pos,
                    format!("unknown transform '{}'; expected one of: {}", head.describe(), OPERATIONS.join(", ")),
                ));
            }
        };
        if args.len() != count {
            let noun = if count == 1 { "number" } else { "numbers" };
            return Err(
                src.invalid(item.pos, format!("'{name}' takes {count} {noun} after its name, found {}", args.len()))
            );
        }
        let v = args.iter().map(|a| values::number(src, a, name)).collect::<Result<Vec<f32>>>()?;
        Ok(match name {
            "translate" => TransformOp::Translate(Vec3::new(v[0], v[1], v[2])),
            "scale" => {
                let s = Vec3::new(v[0], v[1], v[2]);
                if !(Vec3::ONE / s).is_finite() {
                    return Err(src.invalid(
                        item.pos,
                        format!("'scale' {s} has a zero factor, which flattens the object and cannot be inverted"),
                    ));
                }
                TransformOp::Scale(s)
            }
            "rotate-x" => TransformOp::Rotate { axis: Vec3::X, degrees: v[0].to_degrees() },
            "rotate-y" => TransformOp::Rotate { axis: Vec3::Y, degrees: v[0].to_degrees() },
            "rotate-z" => TransformOp::Rotate { axis: Vec3::Z, degrees: v[0].to_degrees() },
            _ => {
                // The book's shearing(xy, xz, yx, yz, zx, zy): x += xy·y + xz·z, and so on.
                let rows =
                    [[1.0, v[0], v[1], 0.0], [v[2], 1.0, v[3], 0.0], [v[4], v[5], 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];
                let det =
                    Mat3::from_cols_array_2d(&[[1.0, v[2], v[4]], [v[0], 1.0, v[5]], [v[1], v[3], 1.0]]).determinant();
                if !(det.abs() > 1e-6 && det.is_finite()) {
                    return Err(src.invalid(
                        item.pos,
                        format!("this 'shear' flattens space (determinant {det}) and cannot be inverted"),
                    ));
                }
                TransformOp::Matrix(rows)
            }
        })
    }
}

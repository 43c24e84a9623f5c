//! Shapes, `group`, `define`/`use`, and the transform statements they carry.

use glam::{Mat3, Vec3};
use glint_core::desc::{NodeDesc, NodeKind, ShapeDesc, TransformOp};

use super::args::{self, Result, Seen};
use super::builder::{Builder, Definition, Source};
use super::solids::{SOLIDS, is_solid};
use super::tree::{Node, Value, ValueKind};

/// The primitive node names, in the order the documentation lists them.
const SHAPES: [&str; 8] = ["sphere", "cube", "cylinder", "cone", "plane", "disk", "rectangle", "torus"];

/// Transform statements, allowed in every object and in `use`.
pub const TRANSFORMS: [&str; 4] = ["translate", "rotate", "scale", "matrix"];

/// Default tube radius of a torus whose major radius is 1.
const TORUS_MINOR_RADIUS: f32 = 0.25;

/// Whether `name` starts an object (a shape, a group or a use).
pub fn is_object(name: &str) -> bool {
    SHAPES.contains(&name) || ["group", "moving", "use", "mesh_instance"].contains(&name) || is_solid(name)
}

/// Names allowed inside `group` and `define`: transforms (group only) and objects.
fn container_allowed(with_transforms: bool) -> Vec<&'static str> {
    let mut allowed = Vec::new();
    if with_transforms {
        allowed.extend(TRANSFORMS);
    }
    allowed.extend(SHAPES);
    allowed.extend(["group", "moving", "use", "mesh_instance"]);
    allowed.extend(SOLIDS);
    allowed
}

impl Builder {
    /// Builds one object node (which [`is_object`] accepted).
    pub fn object(&mut self, src: &Source, node: &Node) -> Result<NodeDesc> {
        match node.name.as_str() {
            "group" | "moving" => self.group(src, node),
            "use" => self.use_definition(src, node),
            "mesh_instance" => self.mesh_instance(src, node),
            name if is_solid(name) => self.solid(src, node),
            _ => self.shape(src, node),
        }
    }

    /// `sphere { material "x" translate [..] … }` and the other primitives.
    fn shape(&mut self, src: &Source, node: &Node) -> Result<NodeDesc> {
        args::no_values(src, node)?;
        let mut allowed = vec!["material"];
        allowed.extend(TRANSFORMS);
        if node.name == "torus" {
            allowed.push("minor_radius");
        }
        let mut transform = Vec::new();
        let mut material = None;
        let mut minor_radius = TORUS_MINOR_RADIUS;
        let mut seen = Seen::default();
        for prop in node.children() {
            if let Some(op) = transform_op(src, prop)? {
                transform.push(op);
                continue;
            }
            if !allowed.contains(&prop.name.as_str()) {
                let place = format!("in '{}'", node.name);
                return Err(args::unknown(src, prop, "property", &place, &allowed));
            }
            seen.once(src, prop, &node.name)?;
            if prop.name == "material" {
                args::no_block(src, prop)?;
                let (name, pos) = args::string(src, prop, "a material name")?;
                material = Some(self.materials.lookup(src, pos, "material", &name)?);
            } else {
                minor_radius =
                    args::number_where(src, prop, "between 0 and 1 (both excluded; the major radius is 1)", |x| {
                        x > 0.0 && x < 1.0
                    })?;
            }
        }
        let shape = match node.name.as_str() {
            "sphere" => ShapeDesc::Sphere,
            "cube" => ShapeDesc::Cube,
            "cylinder" => ShapeDesc::Cylinder,
            "cone" => ShapeDesc::Cone,
            "plane" => ShapeDesc::Plane,
            "disk" => ShapeDesc::Disk,
            "rectangle" => ShapeDesc::Rectangle,
            _ => ShapeDesc::Torus { minor_radius },
        };
        let material = match material {
            Some(index) => index,
            None => self.material_or_inherited(src, node.pos())?,
        };
        self.count_nodes(src, node.pos(), 1)?;
        Ok(NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: src.origin(node.pos()) })
    }

    /// `group { transforms… objects… }`, and `moving { transforms… close { transforms… }
    /// objects… }` whose children move from the first pose (shutter open) to the `close`
    /// pose (shutter close).
    fn group(&mut self, src: &Source, node: &Node) -> Result<NodeDesc> {
        args::no_values(src, node)?;
        let moving = node.name == "moving";
        let mut transform = Vec::new();
        let mut close = None;
        let mut children = Vec::new();
        for child in node.children() {
            if let Some(op) = transform_op(src, child)? {
                transform.push(op);
            } else if is_object(&child.name) {
                children.push(self.object(src, child)?);
            } else if moving && child.name == "close" && close.is_none() {
                args::no_values(src, child)?;
                let mut ops = Vec::new();
                for prop in child.children() {
                    match transform_op(src, prop)? {
                        Some(op) => ops.push(op),
                        None => return Err(args::unknown(src, prop, "transform", "in 'close'", &TRANSFORMS)),
                    }
                }
                close = Some(ops);
            } else {
                let mut allowed = container_allowed(true);
                if moving {
                    allowed.push("close");
                }
                let place = format!("in '{}'", node.name);
                return Err(args::unknown(src, child, "node", &place, &allowed));
            }
        }
        self.count_nodes(src, node.pos(), 1)?;
        let kind = if moving {
            let Some(close) = close else {
                return Err(src.invalid(node.pos(), "'moving' needs a 'close { … }' block: its pose at shutter close"));
            };
            NodeKind::Moving { close, children }
        } else {
            NodeKind::Group(children)
        };
        Ok(NodeDesc { transform, kind, origin: src.origin(node.pos()) })
    }

    /// `define "name" { objects… }`: builds the objects now (so their materials are the
    /// ones defined before the `define`) and keeps them for `use`.
    pub fn define(&mut self, src: &Source, node: &Node) -> Result<()> {
        let (name, pos) = args::string(src, node, "a definition name")?;
        if let Some(taken) = self.define_names.origin_of(&name) {
            return Err(
                src.invalid(pos, format!("definition '{name}' is already defined at {taken}; names must be unique"))
            );
        }
        let before = self.node_count;
        let mut nodes = Vec::new();
        for child in node.children() {
            if !is_object(&child.name) {
                return Err(args::unknown(
                    src,
                    child,
                    "node",
                    "in 'define' (transforms belong on the 'use')",
                    &container_allowed(false),
                ));
            }
            nodes.push(self.object(src, child)?);
        }
        let node_count = self.node_count - before;
        self.define_names.insert(src, pos, "definition", &name, self.definitions.len())?;
        self.definitions.push(Definition { nodes, node_count });
        Ok(())
    }

    /// `use "name" { transforms… }`: a group holding a copy of the definition's objects.
    fn use_definition(&mut self, src: &Source, node: &Node) -> Result<NodeDesc> {
        let (name, pos) = args::string(src, node, "a definition name")?;
        let index = self.define_names.lookup(src, pos, "definition", &name)?;
        let mut transform = Vec::new();
        for prop in node.children() {
            match transform_op(src, prop)? {
                Some(op) => transform.push(op),
                None => {
                    return Err(args::unknown(src, prop, "property", "in 'use'", &TRANSFORMS));
                }
            }
        }
        let added = self.definitions[index].node_count.saturating_add(1);
        self.count_nodes(src, node.pos(), added)?;
        Ok(NodeDesc {
            transform,
            kind: NodeKind::Group(self.definitions[index].nodes.clone()),
            origin: src.origin(node.pos()),
        })
    }
}

/// Reads `prop` as a transform statement; `None` when it is not one.
pub fn transform_op(src: &Source, prop: &Node) -> Result<Option<TransformOp>> {
    Ok(Some(match prop.name.as_str() {
        "translate" => TransformOp::Translate(args::vec3(src, prop)?),
        "scale" => {
            let s = args::vec3_broadcast(src, prop)?;
            // A zero (or subnormal) factor has no finite inverse.
            if !(Vec3::ONE / s).is_finite() {
                return Err(src.invalid(
                    args::value_pos(prop),
                    format!(
                        "'scale' {s} has a zero component, which flattens the object and cannot \
                         be inverted; use non-zero factors (negative mirrors)"
                    ),
                ));
            }
            TransformOp::Scale(s)
        }
        "rotate" => rotate(src, prop)?,
        "matrix" => matrix(src, prop)?,
        _ => return Ok(None),
    }))
}

/// `rotate [ax ay az] degrees`.
fn rotate(src: &Source, prop: &Node) -> Result<TransformOp> {
    args::no_block(src, prop)?;
    let parsed = match prop.args.as_slice() {
        [axis, Value { kind: ValueKind::Number(degrees), .. }] => match &axis.kind {
            ValueKind::Vector(a) if a.len() == 3 => {
                Some((axis.pos, Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32), *degrees as f32))
            }
            _ => None,
        },
        _ => None,
    };
    if let Some((pos, axis, degrees)) = parsed {
        if !(axis.length_squared() > 0.0 && axis.length_squared().is_finite()) {
            return Err(src.invalid(pos, format!("the 'rotate' axis must be non-zero and finite, found {axis}")));
        }
        return Ok(TransformOp::Rotate { axis, degrees });
    }
    let found = match prop.args.as_slice() {
        [] => "nothing".to_owned(),
        values => values.iter().map(Value::describe).collect::<Vec<_>>().join(" and "),
    };
    Err(src.invalid(
        prop.pos(),
        format!(
            "expected an axis of 3 numbers and an angle in degrees for 'rotate', like \
             `rotate [0 1 0] 30`, found {found}"
        ),
    ))
}

/// `matrix [16 numbers]`, rows first, an invertible affine transform.
fn matrix(src: &Source, prop: &Node) -> Result<TransformOp> {
    let v = args::numbers(src, prop, &[16])?;
    let mut rows = [[0.0f32; 4]; 4];
    for (i, x) in v.iter().enumerate() {
        rows[i / 4][i % 4] = *x;
    }
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(src.invalid(
            args::value_pos(prop),
            format!("the last row of 'matrix' must be 0 0 0 1 (an affine transform), found {:?}", rows[3]),
        ));
    }
    let linear = Mat3::from_cols_array_2d(&[
        [rows[0][0], rows[1][0], rows[2][0]],
        [rows[0][1], rows[1][1], rows[2][1]],
        [rows[0][2], rows[1][2], rows[2][2]],
    ]);
    let det = linear.determinant();
    if !(det.abs() > 1e-12 && det.is_finite()) {
        return Err(src.invalid(
            args::value_pos(prop),
            format!("'matrix' is singular or degenerate (determinant {det}); it must be invertible"),
        ));
    }
    Ok(TransformOp::Matrix(rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shape_name_is_an_object() {
        assert!(SHAPES.iter().all(|s| is_object(s)));
        assert!(is_object("group") && is_object("use"));
        assert!(!is_object("translate") && !is_object("define"));
    }
}
